"""Viewport (Rendered shading) test; needs a display, e.g. Xvfb:

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --enable-event-simulate \
        --python-exit-code 1 --python tests/viewport/viewport_test.py -- <builddir> <out.png>

Builds a scene with two styled segments (red points left, blue points
right), switches the 3D viewport to Rendered shading with the PointNPR
engine, waits for redraws, takes a screenshot, checks that the viewport area
shows both segments' colours, and exits with 0 (pass) or 1 (fail). Then
edits (style, points, a mesh) must reach the viewport, and navigation
(frames rendered off the UI thread, blender/viewport_worker.py): a moving
view gets reduced frames, a resting one the full frame, a stale full frame
is never shown, Esc (a simulated key press with --enable-event-simulate,
else the operator it runs) and closing the viewport cancel the frame in
flight. Waits are on conditions with a timeout, never on timings.
"""
import os
import sys
import time
import traceback

import bpy

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(argv) < 2:
    print("usage: ... --python viewport_test.py -- <builddir> <out.png>")
    os._exit(2)
BUILD_DIR = os.path.abspath(argv[0])
OUT_PNG = os.path.abspath(argv[1])
sys.path.insert(0, BUILD_DIR)

# No splash screen over the viewport (the check below must see the scene).
bpy.context.preferences.view.show_splash = False

import numpy as np  # noqa: E402
import pointnpr  # noqa: E402
from pointnpr.blender import engine, mesh_sync, nodes, viewport_worker  # noqa: E402

TIMEOUT_S = 90.0
START = time.time()


def log(msg):
    print("[viewport_test] %s" % msg, flush=True)


def finish(code):
    log("PASS" if code == 0 else "FAIL")
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


def grid(half_x, half_y, step, centre):
    xs = np.arange(-half_x, half_x + step * 0.5, step) + centre[0]
    ys = np.arange(-half_y, half_y + step * 0.5, step) + centre[1]
    gx, gy = np.meshgrid(xs, ys)
    return np.stack([gx.ravel(), gy.ravel(), np.full(gx.size, centre[2])], axis=1)


def add_points(name, coll, positions):
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.astype(np.float32).ravel())
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    coll.objects.link(obj)
    return obj


def styled_collection(name, color):
    coll = bpy.data.collections.new(name)
    bpy.context.scene.collection.children.link(coll)
    tree = nodes.new_style(name + " Style")
    rast = nodes.mark_node(tree)
    rast.color_source = "constant"
    setattr(rast, nodes.property_identifier("color"), color)
    rast.point_size = 6.0
    coll.pointnpr_style = tree
    return coll


def build_scene():
    scene = bpy.context.scene
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    scene.render.engine = 'POINTNPR'
    scene.render.resolution_x, scene.render.resolution_y = 800, 600
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    scene.render.film_transparent = False
    if scene.world is None:
        scene.world = bpy.data.worlds.new("World")
    scene.world.color = (0.0, 0.0, 0.0)
    cam_data = bpy.data.cameras.new("Camera")
    cam = bpy.data.objects.new("Camera", cam_data)
    cam.location = (0.0, 0.0, 10.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    red = styled_collection("Red", (1.0, 0.0, 0.0, 1.0))
    blue = styled_collection("Blue", (0.0, 0.0, 1.0, 1.0))
    add_points("RedPoints", red, grid(1.3, 2.0, 0.04, (-1.6, 0.0, 0.0)))
    add_points("BluePoints", blue, grid(1.3, 2.0, 0.04, (1.6, 0.0, 0.0)))


def session():
    """The viewport's session (one 3D view in Rendered shading), or None."""
    sessions = viewport_worker.sessions()
    return sessions[0] if len(sessions) == 1 else None


def settled():
    """The full-resolution frame of the current view is drawn."""
    s = session()
    frame = s.frame() if s is not None else None
    return frame is not None and frame.full and frame.key == s.last_key and s.drawn_generation == frame.generation


def find_view3d():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                region = next(r for r in area.regions if r.type == 'WINDOW')
                return window, area, region
    return None, None, None


def setup_viewport():
    window, area, region = find_view3d()
    if area is None:
        raise RuntimeError("no 3D viewport in the startup layout")
    space = area.spaces.active
    space.shading.type = 'RENDERED'
    space.overlay.show_overlays = False
    space.show_gizmo = False
    space.region_3d.view_perspective = 'CAMERA'
    space.region_3d.view_camera_zoom = 0.0
    space.region_3d.view_camera_offset = (0.0, 0.0)
    # Maximise the viewport so most of the screenshot is the render.
    area.tag_redraw()
    return window, area, region


def screenshot(window, area, path=OUT_PNG):
    if os.path.exists(path):
        os.remove(path)
    override = {"window": window, "screen": window.screen, "area": area}
    if hasattr(bpy.context, "temp_override"):
        with bpy.context.temp_override(**override):
            bpy.ops.screen.screenshot(filepath=path)
    else:  # Blender < 3.2
        bpy.ops.screen.screenshot(override, filepath=path)
    return os.path.exists(path)


def read_view(window, region):
    """The 3D viewport's pixels (rows bottom first) from the screenshot."""
    img = bpy.data.images.load(OUT_PNG, check_existing=False)
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    px = px.reshape(h, w, 4)
    # Region coordinates are window pixels from the bottom left, as are the
    # image rows (bottom row first); scale in case of HiDPI.
    sx, sy = w / float(window.width), h / float(window.height)
    x0, y0 = int(region.x * sx), int(region.y * sy)
    x1, y1 = int((region.x + region.width) * sx), int((region.y + region.height) * sy)
    return px[y0:y1, x0:x1, :3]


def mask(view, rgb):
    hi = [c > 0.5 for c in rgb]
    m = np.ones(view.shape[:2], dtype=bool)
    for i in range(3):
        m &= (view[:, :, i] > 0.8) if hi[i] else (view[:, :, i] < 0.2)
    return m


def centroid(m):
    ys, xs = np.nonzero(m)
    return xs.mean(), ys.mean()


def check_first(view):
    red, blue = mask(view, (1, 0, 0)), mask(view, (0, 0, 1))
    n = view.shape[0] * view.shape[1]
    log("viewport area: %d px, red %.3f, blue %.3f, std %.3f" % (n, red.mean(), blue.mean(), view.std()))
    if n < 10000:
        return "viewport area too small"
    if view.std() < 0.05:
        return "viewport area is uniform (empty)"
    if red.mean() < 0.02 or blue.mean() < 0.02:
        return "segment colours not visible"
    (rx, ry), (bx, by) = centroid(red), centroid(blue)
    log("centroids: red (%.1f, %.1f), blue (%.1f, %.1f)" % (rx, ry, bx, by))
    if not rx < bx:
        return "red segment is not left of blue"
    state["blue_y"] = by
    return None


def check_restyled(view):
    red, green = mask(view, (1, 0, 0)), mask(view, (0, 1, 0))
    log("after restyle: red %.3f, green %.3f" % (red.mean(), green.mean()))
    if green.mean() < 0.02 or red.mean() > 0.001:
        return "style change did not reach the viewport"
    return None


def check_moved(view):
    blue = mask(view, (0, 0, 1))
    if blue.mean() < 0.01:
        return "blue segment vanished after editing its mesh"
    _bx, by = centroid(blue)
    log("blue centroid y: %.1f -> %.1f" % (state["blue_y"], by))
    if not by > state["blue_y"] + 20:
        return "mesh edit did not reach the viewport (stale cached cloud?)"
    return None


def add_yellow_mesh():
    """A quad with faces (a material's yellow) between the two segments,
    in front: drawn as a surface (issue 15)."""
    coll = bpy.data.collections.new("Yellow")
    bpy.context.scene.collection.children.link(coll)
    tree = nodes.new_style("Yellow Style")
    surface = nodes.append_node(tree, nodes.ROLE_MARK, nodes.SURFACE_MARK)
    surface.shading = "none"
    coll.pointnpr_style = tree
    mesh = bpy.data.meshes.new("YellowQuad")
    mesh.from_pydata([(-0.25, -0.5, 0.5), (0.25, -0.5, 0.5), (0.25, 0.5, 0.5), (-0.25, 0.5, 0.5)], [], [(0, 1, 2, 3)])
    mat = bpy.data.materials.new("Yellow")
    mat.use_nodes = True
    mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (1.0, 1.0, 0.0, 1.0)
    mesh.materials.append(mat)
    mesh.update()
    coll.objects.link(bpy.data.objects.new("YellowQuad", mesh))
    state["mesh_uploads"] = mesh_sync.cache_stats()["uploads"]
    state["gpu_uploads"] = engine.renderer().mesh_upload_count()


def check_mesh(view):
    yellow = mask(view, (1, 1, 0))
    log("yellow mesh: %.4f of the view, mesh uploads %s" % (yellow.mean(), mesh_sync.cache_stats()))
    if yellow.mean() < 0.002:
        return "the mesh with faces is not drawn as a surface"
    _x, state["yellow_y"] = centroid(yellow)
    if mesh_sync.cache_stats()["uploads"] != state["mesh_uploads"] + 1:
        return "the new mesh was not read exactly once"
    state["gpu_first"] = engine.renderer().mesh_upload_count() - state["gpu_uploads"]
    state["mesh_uploads"] = mesh_sync.cache_stats()["uploads"]
    state["gpu_uploads"] = engine.renderer().mesh_upload_count()
    return None


def move_yellow_mesh():
    mesh = bpy.data.objects["YellowQuad"].data
    for v in mesh.vertices:
        v.co.y += 1.0
    mesh.update()


def check_mesh_moved(view):
    yellow = mask(view, (1, 1, 0))
    if yellow.mean() < 0.002:
        return "the mesh vanished after its edit"
    _x, y = centroid(yellow)
    log("yellow centroid y: %.1f -> %.1f; %s" % (state["yellow_y"], y, mesh_sync.cache_stats()))
    if not y > state["yellow_y"] + 10:
        return "mesh edit did not reach the viewport (stale cached mesh?)"
    # Redrawn several times since, yet read and uploaded once for the edit.
    if mesh_sync.cache_stats()["uploads"] != state["mesh_uploads"] + 1:
        return "the edited mesh was read %d times" % (mesh_sync.cache_stats()["uploads"] - state["mesh_uploads"])
    if engine.renderer().mesh_upload_count() - state["gpu_uploads"] != state["gpu_first"]:
        return "the edited mesh was not uploaded exactly once"
    return None


def restyle():
    tree = bpy.data.collections["Red"].pointnpr_style
    setattr(nodes.mark_node(tree), nodes.property_identifier("color"), (0.0, 1.0, 0.0, 1.0))


def move_blue_points():
    mesh = bpy.data.objects["BluePoints"].data
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    co[:, 1] += 1.0
    mesh.vertices.foreach_set("co", co.ravel())
    mesh.update()


# ---------------------------------------------------------------------------
# Navigation: frames off the UI thread (blender/viewport_worker.py)

def wait_for(condition, what, timeout=30.0):
    """Yields timer intervals until ``condition()`` holds (redrawing)."""
    t0 = time.time()
    while not condition():
        if time.time() - t0 > timeout:
            raise AssertionError("timed out waiting for %s; events %s" % (what, list(viewport_worker.events)[-12:]))
        state["area"].tag_redraw()
        yield 0.05


def orbit(angle=0.03):
    from mathutils import Quaternion
    rv3d = state["area"].spaces.active.region_3d
    rv3d.view_rotation = Quaternion((0.0, 0.0, 1.0), angle) @ rv3d.view_rotation
    state["area"].tag_redraw()


def events_since(mark, kind=None):
    return [e for e in list(viewport_worker.events)[mark:] if kind is None or e[0] == kind]


def held_full(s):
    running = s.running
    return running is not None and running.full


def press_escape():
    """Esc over the 3D view, through Blender's keymaps where events can be
    simulated (--enable-event-simulate), else the operator it runs."""
    window, region = state["window"], state["region"]
    if getattr(bpy.app, "use_event_simulate", False):
        x, y = region.x + region.width // 2, region.y + region.height // 2
        window.event_simulate(type='MOUSEMOVE', value='NOTHING', x=x, y=y)
        window.event_simulate(type='ESC', value='PRESS', x=x, y=y)
        window.event_simulate(type='ESC', value='RELEASE', x=x, y=y)
        return "simulated Esc key"
    override = {"window": window, "screen": window.screen, "area": state["area"], "region": region}
    with bpy.context.temp_override(**override):
        bpy.ops.pointnpr.viewport_cancel()
    return "operator (no event simulation)"


def navigation():
    """A moving view gets reduced frames, a resting one the full frame; a
    stale full frame is dropped; Esc and closing the viewport cancel."""
    scene = bpy.context.scene
    space = state["area"].spaces.active
    region = state["region"]
    scene.pointnpr.navigation_resolution = "4"
    # Steps come every 50 ms (slower when the machine is loaded): a moving
    # view never rests this long.
    scene.pointnpr.refine_delay = 5.0
    space.region_3d.view_perspective = 'PERSP'
    yield from wait_for(settled, "the full frame after leaving the camera view")
    s = session()

    # 1. Moving: reduced frames only, a quarter of the region's size.
    mark = len(viewport_worker.events)
    t0 = time.time()
    while len([e for e in events_since(mark, "drawn") if e[2] == 4]) < 3:
        if time.time() - t0 > 60.0:
            raise AssertionError("no reduced frames while orbiting: %s" % events_since(mark))
        orbit()
        yield 0.05
    drawn = events_since(mark, "drawn")
    log("orbiting: %d frames drawn, scales %s" % (len(drawn), sorted({e[2] for e in drawn})))
    assert all(e[2] == 4 for e in drawn), "a full frame was drawn while the view moved: %s" % drawn
    frame = s.frame()
    assert (frame.width, frame.height) == (-(-region.width // 4), -(-region.height // 4)), (frame.width, frame.height)

    # 2. Resting: the full frame of the resting view follows.
    yield from wait_for(settled, "the full frame after the view rests")
    assert s.frame().full and (s.frame().width, s.frame().height) == (region.width, region.height)
    if not screenshot(state["window"], state["area"]):
        raise AssertionError("screenshot failed")
    view = read_view(state["window"], region)
    assert view.std() > 0.05, "the rested view is empty"

    # 3. Stale: a full frame held in flight while the view moves on is
    # cancelled and never shown; the newer view's frames are.
    scene.pointnpr.refine_delay = 0.3
    viewport_worker.hold = lambda request: request.full
    mark = len(viewport_worker.events)
    orbit()
    yield from wait_for(lambda: held_full(s), "a full frame in flight")
    stale = s.running.generation
    orbit()
    yield from wait_for(lambda: any(e[1] == stale for e in events_since(mark, "dropped")), "the stale frame dropped")
    viewport_worker.hold = None
    yield from wait_for(settled, "the full frame of the newer view")
    shown = [e[1] for e in events_since(mark) if e[0] in ("published", "drawn")]
    log("stale frame %d: %s" % (stale, [e for e in events_since(mark) if e[1] == stale]))
    assert stale not in shown, "the stale frame was shown"

    # 4. Esc cancels the frame in flight and the refinement; nothing renders
    # until the view changes again.
    viewport_worker.hold = lambda request: request.full
    mark = len(viewport_worker.events)
    orbit()
    yield from wait_for(lambda: held_full(s), "a full frame in flight before Esc")
    cancelled = s.running.generation
    how = press_escape()
    yield from wait_for(lambda: ("dropped", cancelled, 1, "cancelled") in events_since(mark), "Esc to cancel")
    viewport_worker.hold = None
    after, draws, t0 = len(viewport_worker.events), engine.stats["viewport_draws"], time.time()
    yield from wait_for(lambda: engine.stats["viewport_draws"] >= draws + 3 and time.time() - t0 > 1.0,
                        "redraws after Esc")
    log("Esc (%s): frame %d cancelled; events since: %s" % (how, cancelled, events_since(after)))
    assert not events_since(after, "submitted"), "a frame was rendered after Esc without a view change"
    assert not s.frame().full
    orbit()
    yield from wait_for(settled, "frames again after the view moved")

    # 5. Closing the viewport (leaving Rendered shading) frees the engine and
    # cancels its work.
    viewport_worker.hold = lambda request: request.full
    mark = len(viewport_worker.events)
    orbit()
    yield from wait_for(lambda: held_full(s), "a full frame in flight before closing")
    closed = s.running.generation
    space.shading.type = 'SOLID'
    yield from wait_for(lambda: ("dropped", closed, 1, "closed") in events_since(mark) and not viewport_worker.sessions(),
                        "closing the viewport to cancel its frame")
    viewport_worker.hold = None
    space.shading.type = 'RENDERED'
    yield from wait_for(settled, "a new session after reopening")

    # Frames are drawn in request order, whatever was dropped.
    drawn = [e[1] for e in viewport_worker.events if e[0] == "drawn"]
    assert drawn == sorted(drawn), drawn
    log("main-thread time per callback [calls, total ms, max ms]: %s" %
        {k: [v[0], round(v[1], 1), round(v[2], 1)] for k, v in viewport_worker.timing.items()})


# Panel draw() calls are recorded, so a broken panel fails the test.
panel_calls = {}


def watch_panel(cls):
    original = cls.draw

    def draw(self, context):
        try:
            original(self, context)
            panel_calls.setdefault(cls.__name__, []).append(None)
        except Exception as exc:
            panel_calls.setdefault(cls.__name__, []).append(repr(exc))
            raise
    cls.draw = draw


def watch_node_buttons():
    original = nodes._StyleNodeMixin.draw_buttons

    def draw_buttons(self, context, layout):
        try:
            original(self, context, layout)
            panel_calls.setdefault("node draw_buttons", []).append(None)
        except Exception as exc:
            panel_calls.setdefault("node draw_buttons", []).append(repr(exc))
            raise
    nodes._StyleNodeMixin.draw_buttons = draw_buttons


def show_properties(tab):
    for area in state["window"].screen.areas:
        if area.type == 'PROPERTIES':
            area.spaces.active.context = tab
            area.tag_redraw()
            return True
    return False


STEPS = [
    # (name, action before waiting, check on the screenshot)
    ("initial", None, check_first),
    ("restyle", restyle, check_restyled),
    ("move", move_blue_points, check_moved),
    ("mesh", add_yellow_mesh, check_mesh),
    ("move mesh", move_yellow_mesh, check_mesh_moved),
]

state = {"phase": "setup", "ticks": 0, "window": None, "area": None, "region": None,
         "step": 0, "renders": 0, "wait_ticks": 0}


def tick():
    try:
        if time.time() - START > TIMEOUT_S:
            log("timed out in phase %s (engine stats: %s)" % (state["phase"], engine.stats))
            finish(1)
        state["ticks"] += 1
        if state["phase"] == "setup":
            pointnpr.register()
            from pointnpr.blender import ui
            watch_panel(ui.RENDER_PT_pointnpr)
            watch_panel(ui.COLLECTION_PT_pointnpr_style)
            watch_panel(ui.NODE_PT_pointnpr_style)
            watch_node_buttons()
            build_scene()
            state["window"], state["area"], state["region"] = setup_viewport()
            state["phase"] = "act"
            return 1.0
        if state["phase"] == "act":
            name, action, _check = STEPS[state["step"]]
            # Wait for a viewport render made after the action.
            state["renders"] = engine.stats["viewport_renders"] if action is not None else 0
            if action is not None:
                action()
            state["area"].tag_redraw()
            state["wait_ticks"] = 0
            state["phase"] = "wait"
            return 0.3
        if state["phase"] == "wait":
            state["wait_ticks"] += 1
            state["area"].tag_redraw()
            # Frames render off the UI thread, reduced first: wait for the
            # full-resolution frame of this view to be drawn.
            if engine.stats["viewport_renders"] > state["renders"] and state["wait_ticks"] > 3 and settled():
                state["phase"] = "shoot"
            return 0.3
        if state["phase"] == "shoot":
            name, _action, check = STEPS[state["step"]]
            log("step %s, engine stats: %s" % (name, engine.stats))
            if not screenshot(state["window"], state["area"]):
                log("screenshot failed")
                finish(1)
            error = check(read_view(state["window"], state["region"]))
            if error:
                log("step %s: %s" % (name, error))
                finish(1)
            state["step"] += 1
            if state["step"] < len(STEPS):
                state["phase"] = "act"
                return 0.3
            state["phase"] = "navigation"
            state["navigation"] = navigation()
            return 0.1
        if state["phase"] == "navigation":
            try:
                return next(state["navigation"])
            except StopIteration:
                pass
            # Our panels in the Properties editor.
            coll = bpy.data.collections["Red"]
            layer = bpy.context.view_layer.layer_collection.children[coll.name]
            bpy.context.view_layer.active_layer_collection = layer
            if not show_properties('RENDER'):
                log("no Properties editor")
                finish(1)
            state["phase"] = "panels_render"
            return 1.0
        if state["phase"] == "panels_render":
            show_properties('COLLECTION')
            state["phase"] = "panels_collection"
            return 1.0
        if state["phase"] == "panels_collection":
            log("panel draws: %s" % {k: len(v) for k, v in panel_calls.items()})
            # For a human look at the panels; not checked.
            screenshot(state["window"], state["area"], os.path.splitext(OUT_PNG)[0] + "_panels.png")
            errors = [e for calls in panel_calls.values() for e in calls if e]
            if errors:
                log("panel errors: %s" % errors)
                finish(1)
            if not all(panel_calls.get(n) for n in ("RENDER_PT_pointnpr", "COLLECTION_PT_pointnpr_style")):
                log("panels were not drawn")
                finish(1)
            # The style in a node editor (the 3D viewport, checked, becomes
            # one). Its sidebar opens on the "Tool" tab, so the PointNPR
            # panel (tab "Node") is not drawn and not required here.
            area = state["area"]
            area.type = 'NODE_EDITOR'
            space = area.spaces.active
            space.tree_type = nodes.TREE_IDNAME
            space.node_tree = bpy.data.collections["Red"].pointnpr_style
            space.show_region_ui = True
            area.tag_redraw()
            state["phase"] = "node_editor"
            return 1.0
        if state["phase"] == "node_editor":
            log("node editor draws: %s" % {k: len(v) for k, v in panel_calls.items()})
            screenshot(state["window"], state["area"], os.path.splitext(OUT_PNG)[0] + "_nodes.png")
            errors = [e for calls in panel_calls.values() for e in calls if e]
            if errors:
                log("draw errors: %s" % errors)
                finish(1)
            if not panel_calls.get("node draw_buttons"):
                log("style nodes not drawn in the node editor")
                finish(1)
            # Interactive F12: the render runs as a job, off the main thread.
            bpy.context.preferences.view.render_display_type = 'NONE'
            state["final_before"] = engine.stats["final_renders"]
            override = {"window": state["window"], "screen": state["window"].screen,
                        "area": state["area"]}
            if hasattr(bpy.context, "temp_override"):
                with bpy.context.temp_override(**override):
                    bpy.ops.render.render('INVOKE_DEFAULT')
            else:
                bpy.ops.render.render(override, 'INVOKE_DEFAULT')
            state["phase"] = "f12"
            return 0.5
        if state["phase"] == "f12":
            running = bpy.app.is_job_running('RENDER') if hasattr(bpy.app, "is_job_running") else False
            if running or engine.stats["final_renders"] <= state["final_before"]:
                return 0.5
            result = bpy.data.images.get("Render Result")
            log("F12 done: %s, render result %s" % (engine.stats, result is not None))
            if result is None:
                finish(1)
            finish(0)
    except Exception:
        traceback.print_exc()
        finish(1)
    return 0.5


bpy.app.timers.register(tick, first_interval=1.0)
