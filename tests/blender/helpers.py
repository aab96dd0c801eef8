"""Scene building and image helpers for the in-Blender tests."""

import os
import sys

import bpy
import numpy as np

from pointnpr.blender import nodes

WIDTH, HEIGHT = 64, 48
RED = (1.0, 0.0, 0.0, 1.0)
GREEN = (0.0, 1.0, 0.0, 1.0)
BLUE = (0.0, 0.0, 1.0, 1.0)

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
IO_DATA = os.path.join(REPO, "tests", "data", "io")
# "build" (Blender 3.4: build/pointnpr registered by run.py) or "extension"
# (bpy 4.2+: the extension zip installed through Blender's operator).
TESTED_PACKAGE = os.environ.get("POINTNPR_TESTED_PACKAGE", "build")


def blender_command():
    """The command that starts another Blender: its executable, or, in bpy
    (which has none), Python running bpy_blender.py, which takes the same
    arguments and enables the installed extension."""
    if bpy.app.binary_path:
        return [bpy.app.binary_path]
    return [sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "bpy_blender.py")]


def addon_args():
    """What another Blender needs to have PointNPR: the build folder's
    package enabled by scripts/enable_addon.py, or nothing where the
    extension is installed (its user folder is inherited)."""
    if TESTED_PACKAGE == "extension":
        return []
    return ["--python", os.path.join(REPO, "scripts", "enable_addon.py")]


def reset_scene():
    """An empty scene rendered by PointNPR with plain colour management."""
    scene = bpy.context.scene
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in list(bpy.data.collections):
        bpy.data.collections.remove(coll)
    for blocks in (bpy.data.meshes, bpy.data.cameras, bpy.data.lights, bpy.data.node_groups,
                   bpy.data.actions, bpy.data.materials):
        for block in list(blocks):
            blocks.remove(block)
    for img in list(bpy.data.images):
        if img.type == 'IMAGE':
            bpy.data.images.remove(img)
    scene.render.engine = 'POINTNPR'
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = WIDTH, HEIGHT, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.fps, r.fps_base = 24, 1.0
    r.film_transparent = False
    r.dither_intensity = 0.0   # exact 8-bit values, independent of position
    r.use_border = False
    r.use_crop_to_border = False
    r.image_settings.file_format = 'PNG'
    r.image_settings.color_mode = 'RGBA'
    r.image_settings.color_depth = '8'
    for flag in dir(r):
        if flag.startswith("use_stamp") and flag != "use_stamp_labels":
            try:
                setattr(r, flag, False)
            except (AttributeError, TypeError):
                pass
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.display_settings.display_device = 'sRGB'
    scene.sequencer_colorspace_settings.name = 'sRGB'
    if scene.world is None:
        scene.world = bpy.data.worlds.new("World")
    scene.world.color = (0.0, 0.0, 0.0)
    scene.frame_start, scene.frame_end = 1, 10
    scene.frame_set(1)
    if hasattr(scene, "compositor_effects"):  # Blender 5.2+
        scene.compositor_effects.clear()
    elif hasattr(scene, "compositing_node_group"):  # Blender 5.0, 5.1
        scene.compositing_node_group = None
    else:
        scene.use_nodes = False
    scene.view_layers[0].use_pass_z = False
    scene.pointnpr_default_style = None
    # Every scene setting, the budgets too (a test that sets a point budget would thin the next ones).
    for prop in scene.pointnpr.bl_rna.properties.keys():
        if prop not in ("rna_type", "name"):
            scene.pointnpr.property_unset(prop)
    scene.pointnpr.rasterizer = "compute"
    return scene


def add_camera(location=(0.0, 0.0, 10.0), ortho=False, lens=50.0):
    scene = bpy.context.scene
    cam = bpy.data.cameras.new("Camera")
    cam.lens = lens
    cam.sensor_width = 36.0
    cam.sensor_fit = 'AUTO'
    cam.clip_start, cam.clip_end = 0.1, 100.0
    if ortho:
        cam.type = 'ORTHO'
        cam.ortho_scale = 8.0
    obj = bpy.data.objects.new("Camera", cam)
    obj.location = location
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def new_collection(name, parent=None):
    coll = bpy.data.collections.new(name)
    (parent or bpy.context.scene.collection).children.link(coll)
    return coll


def grid_points(half, step, z):
    ticks = np.arange(-half, half + step * 0.5, step)
    xs, ys = np.meshgrid(ticks, ticks)
    return np.stack([xs.ravel(), ys.ravel(), np.full(xs.size, z)], axis=1)


def add_points(name, coll, positions, colors=None, intensity=None):
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", np.asarray(positions, dtype=np.float32).ravel())
    if colors is not None:
        attr = mesh.color_attributes.new("Col", 'BYTE_COLOR', 'POINT')
        rgba = np.ones((len(positions), 4), dtype=np.float32)
        rgba[:, :3] = np.asarray(colors, dtype=np.float32)
        attr.data.foreach_set("color_srgb", rgba.ravel())
    if intensity is not None:
        attr = mesh.attributes.new("intensity", 'FLOAT', 'POINT')
        attr.data.foreach_set("value", np.asarray(intensity, dtype=np.float32))
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    coll.objects.link(obj)
    return obj


def pid(name):
    return nodes.property_identifier(name)


def constant_style(name, color, point_size=6.0):
    tree = nodes.new_style(name)
    points = tree.nodes["Points"]
    points.color_source = "constant"
    setattr(points, pid("color"), color)
    points.point_size = point_size
    return tree


def render_to_png(path):
    bpy.context.scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    assert os.path.exists(path), "render wrote no image"
    return path


def load_png(path):
    """(H, W, 4) float pixels of an image file, bottom row first (display values)."""
    img = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = img.size
        px = np.empty(w * h * 4, dtype=np.float32)
        img.pixels.foreach_get(px)
        return px.reshape(h, w, 4)
    finally:
        bpy.data.images.remove(img)


def render_pixels(tmp_path, name="render.png"):
    path = render_to_png(str(tmp_path / name))
    with open(path, "rb") as f:
        data = f.read()
    return load_png(path), data


def two_planes_scene(mode="depth_test"):
    """'Near' (red, z=2, first segment) in front of 'Far' (blue, z=0, larger,
    second segment), seen from a camera at z=10 looking down."""
    scene = reset_scene()
    add_camera()
    near = new_collection("Near")
    far = new_collection("Far")
    add_points("NearPoints", near, grid_points(1.0, 0.05, 2.0))
    add_points("FarPoints", far, grid_points(3.0, 0.05, 0.0))
    near.pointnpr_style = constant_style("Red", RED)
    far.pointnpr_style = constant_style("Blue", BLUE)
    scene.pointnpr.mode = mode
    return scene, near, far


def is_color(pixel, rgb, tol=0.2):
    return all(abs(float(pixel[i]) - rgb[i]) < tol for i in range(3))


def run_blender_in_window(script_path, env=None, timeout=300):
    """Runs ``script_path`` in a second Blender with a window (Xvfb, event
    simulation) and returns its CompletedProcess. On a timeout the whole
    process group goes, Blender included: a hung interactive Blender must
    not outlive the test and load the machine."""
    import shutil
    import signal
    import subprocess

    if shutil.which("xvfb-run") is None:
        raise AssertionError("xvfb-run is required (scripts/install_deps.sh --tests installs it)")
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 800x600x24", bpy.app.binary_path, "--factory-startup",
           "--enable-event-simulate", "--python", str(script_path)]
    proc = subprocess.Popen(cmd, env=dict(os.environ, **(env or {})), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        raise AssertionError("the interactive Blender timed out:\n" + out[-3000:] + err[-3000:])
    return subprocess.CompletedProcess(cmd, proc.returncode, out, err)


def fcurves(id_block):
    """The F-Curves of ``id_block``'s action: its slot's channel bags in the
    layered actions of Blender 4.4+ (where 5.0 has no Action.fcurves), the
    flat list before."""
    anim = id_block.animation_data
    return nodes._action_fcurves(anim, anim.action)


def compositor_tree(scene):
    """The scene's compositing node tree, emptied, with an image output
    linked from nothing yet: (tree, output node). Blender 5.0 and 5.1 keep
    it in a node group (Scene.compositing_node_group, a Group Output), 5.2
    and later in the node group of a compositor effect (Scene.compositor_effects,
    where compositing_node_group is deprecated), earlier versions on the
    scene (Scene.node_tree, a Composite node)."""
    effects = getattr(scene, "compositor_effects", None)
    if effects is not None or hasattr(scene, "compositing_node_group"):
        tree = bpy.data.node_groups.new("Compositing", "CompositorNodeTree")
        tree.interface.new_socket("Image", in_out='OUTPUT', socket_type='NodeSocketColor')
        if effects is not None:
            effects.clear()
            effects.new("Compositing").node_group = tree
        else:
            scene.compositing_node_group = tree
        tree.nodes.clear()
        return tree, tree.nodes.new("NodeGroupOutput")
    scene.use_nodes = True
    tree = scene.node_tree
    tree.nodes.clear()
    return tree, tree.nodes.new("CompositorNodeComposite")
