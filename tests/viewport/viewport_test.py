"""Viewport (Rendered shading) test; needs a display, e.g. Xvfb:

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup \
        --python tests/viewport/viewport_test.py -- <builddir> <out.png>

Builds a scene with two styled segments (red points left, blue points
right), switches the 3D viewport to Rendered shading with the PointNPR
engine, waits for redraws, takes a screenshot, checks that the viewport area
shows both segments' colours, and exits with 0 (pass) or 1 (fail).
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
from pointnpr.blender import engine, nodes  # noqa: E402

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
    rast = tree.nodes["Rasterize"]
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


def screenshot(window, area):
    if os.path.exists(OUT_PNG):
        os.remove(OUT_PNG)
    override = {"window": window, "screen": window.screen, "area": area}
    if hasattr(bpy.context, "temp_override"):
        with bpy.context.temp_override(**override):
            bpy.ops.screen.screenshot(filepath=OUT_PNG)
    else:  # Blender < 3.2
        bpy.ops.screen.screenshot(override, filepath=OUT_PNG)
    return os.path.exists(OUT_PNG)


def check(window, region):
    img = bpy.data.images.load(OUT_PNG, check_existing=False)
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    px = px.reshape(h, w, 4)
    log("screenshot %dx%d, window %dx%d, region at (%d, %d) size %dx%d" % (
        w, h, window.width, window.height, region.x, region.y, region.width, region.height))
    # Region coordinates are window pixels from the bottom left, as are the
    # image rows (bottom row first); scale in case of HiDPI.
    sx, sy = w / float(window.width), h / float(window.height)
    x0, y0 = int(region.x * sx), int(region.y * sy)
    x1, y1 = int((region.x + region.width) * sx), int((region.y + region.height) * sy)
    view = px[y0:y1, x0:x1, :3]
    red = (view[:, :, 0] > 0.8) & (view[:, :, 1] < 0.2) & (view[:, :, 2] < 0.2)
    blue = (view[:, :, 2] > 0.8) & (view[:, :, 0] < 0.2) & (view[:, :, 1] < 0.2)
    n = view.shape[0] * view.shape[1]
    red_frac, blue_frac = red.mean(), blue.mean()
    log("viewport area: %d px, red %.3f, blue %.3f, std %.3f" % (n, red_frac, blue_frac, view.std()))
    ok = True
    if n < 10000:
        log("viewport area too small")
        ok = False
    if view.std() < 0.05:
        log("viewport area is uniform (empty)")
        ok = False
    if red_frac < 0.02 or blue_frac < 0.02:
        log("segment colours not visible")
        ok = False
    # Red must be on the left of blue (segments where the camera sees them).
    if ok:
        red_x = np.nonzero(red)[1].mean()
        blue_x = np.nonzero(blue)[1].mean()
        log("mean x: red %.1f, blue %.1f" % (red_x, blue_x))
        if not red_x < blue_x:
            ok = False
    return ok


state = {"phase": "setup", "ticks": 0, "window": None, "area": None, "region": None,
         "renders_at_shot": 0}


def tick():
    try:
        if time.time() - START > TIMEOUT_S:
            log("timed out in phase %s (viewport renders: %s)" % (state["phase"], engine.stats))
            finish(1)
        state["ticks"] += 1
        if state["phase"] == "setup":
            pointnpr.register()
            build_scene()
            state["window"], state["area"], state["region"] = setup_viewport()
            state["phase"] = "wait"
            return 0.5
        if state["phase"] == "wait":
            state["area"].tag_redraw()
            if engine.stats["viewport_draws"] >= 2 and state["ticks"] > 6:
                state["phase"] = "shoot"
            return 0.5
        if state["phase"] == "shoot":
            log("engine stats: %s" % engine.stats)
            if not screenshot(state["window"], state["area"]):
                log("screenshot failed")
                finish(1)
            finish(0 if check(state["window"], state["region"]) else 1)
    except Exception:
        traceback.print_exc()
        finish(1)
    return 0.5


bpy.app.timers.register(tick, first_interval=1.0)
