"""Builds the example .blend files from the scans in tests/data/io.

    blender -b --factory-startup --python-exit-code 1 \
        --python blend_examples/make_examples.py -- <builddir> [outdir]

<builddir> holds the assembled add-on package (<builddir>/pointnpr). Writes
<outdir>/warsaw_styles.blend (default outdir: this folder) and a preview
render of frame 1 next to it. Opening or rendering the .blend needs the
add-on enabled, e.g.

    blender -b blend_examples/warsaw_styles.blend \
        --python tests/blender/enable_addon.py -o //render_#### -a
    (with POINTNPR_BUILD_DIR=<builddir>)

The scene shows what the add-on does:
* File > Import > Point Cloud with "Split by classification": one collection
  per ASPRS class under a collection named after the file;
* a style on the file's collection that the classes without their own style
  inherit (Ground);
* one style shared by the three vegetation collections, with a keyframed
  warp;
* composite mode "inpaint", so nearer segments win after the filters.
"""
import os
import sys

import bpy
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if not argv:
    print(__doc__)
    sys.exit(2)
BUILD_DIR = os.path.abspath(argv[0])
HERE = os.path.dirname(os.path.abspath(__file__))
OUT_DIR = os.path.abspath(argv[1]) if len(argv) > 1 else HERE
REPO = os.path.dirname(HERE)
SCAN = os.path.join(REPO, "tests", "data", "io", "warsaw_small.las")

sys.path.insert(0, BUILD_DIR)
import pointnpr  # noqa: E402

pointnpr.register()
from pointnpr.blender import nodes  # noqa: E402


def clear():
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in list(bpy.data.collections):
        bpy.data.collections.remove(coll)
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)


def set_params(node, **values):
    for name, value in values.items():
        setattr(node, nodes.property_identifier(name), value)


def main():
    clear()
    scene = bpy.context.scene
    scene.render.engine = 'POINTNPR'
    scene.render.resolution_x, scene.render.resolution_y = 960, 540
    scene.render.resolution_percentage = 100
    scene.frame_start, scene.frame_end = 1, 48
    scene.render.fps = 24
    scene.view_settings.view_transform = 'Standard'
    if scene.world is None:
        scene.world = bpy.data.worlds.new("World")
    scene.world.color = (0.9, 0.9, 0.85)
    scene.pointnpr.mode = "inpaint"

    bpy.ops.import_scene.pointnpr_cloud(filepath=SCAN, split_by_classification=True)
    root = bpy.data.collections["warsaw_small"]

    # The file's collection: colours from the scan, cartoon look. Classes
    # without a style of their own (Ground, Never Classified) inherit it.
    base = nodes.new_style("Scan Cartoon")
    set_params(base.nodes["Rasterize"], size_mode="world", world_size=0.8, color_source="rgb")
    nodes.append_node(base, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    root.pointnpr_style = base

    # Vegetation: one shared style, a constant green with a keyframed warp.
    veg = nodes.new_style("Vegetation Warp")
    set_params(veg.nodes["Rasterize"], size_mode="world", world_size=0.7, color_source="constant",
               color=(0.25, 0.55, 0.2, 1.0))
    warp = nodes.append_node(veg, nodes.ROLE_FILTER, "warp", name="Warp")
    nodes.append_node(veg, nodes.ROLE_INPAINT, "inpaint", name="Inpaint Depth")
    set_params(warp, amplitude=0.0)
    warp.keyframe_insert(nodes.property_identifier("amplitude"), frame=1)
    set_params(warp, amplitude=12.0)
    warp.keyframe_insert(nodes.property_identifier("amplitude"), frame=48)
    for coll in root.children:
        if "Vegetation" in coll.name:
            coll.pointnpr_style = veg

    # Camera looking at the scan from the south-west, above.
    points = [o.matrix_world @ v.co for o in bpy.data.objects if o.type == 'MESH'
              for v in list(o.data.vertices)[::10]]
    lo = Vector(tuple(min(p[i] for p in points) for i in range(3)))
    hi = Vector(tuple(max(p[i] for p in points) for i in range(3)))
    centre = (lo + hi) / 2
    extent = max((hi - lo).x, (hi - lo).y)
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 35.0
    cam_data.clip_start, cam_data.clip_end = 0.1, 10.0 * extent
    cam = bpy.data.objects.new("Camera", cam_data)
    cam.location = centre + Vector((-0.8 * extent, -0.9 * extent, 0.7 * extent))
    cam.rotation_euler = (centre - cam.location).to_track_quat('-Z', 'Y').to_euler()
    scene.collection.objects.link(cam)
    scene.camera = cam

    os.makedirs(OUT_DIR, exist_ok=True)
    blend = os.path.join(OUT_DIR, "warsaw_styles.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, compress=True)
    scene.render.filepath = os.path.join(OUT_DIR, "warsaw_styles_preview.png")
    scene.frame_set(24)
    scene.render.resolution_percentage = 50   # small preview; the .blend keeps 100 %
    bpy.ops.render.render(write_still=True)
    print("wrote", blend, scene.render.filepath)


main()
