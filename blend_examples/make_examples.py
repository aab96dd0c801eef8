"""Builds the example .blend files from real scans in data/ and tests/data/io.

    blender -b --factory-startup --python-exit-code 1 \
        --python blend_examples/make_examples.py -- <builddir> [outdir [name ...]]

<builddir> holds the assembled add-on package (<builddir>/pointnpr). Writes,
into <outdir> (default: this folder), each scene's .blend and a preview
render next to it:
* urban_lidarhd.blend: aerial LiDAR (IGN LiDAR HD), ground / buildings /
  vegetation as three differently styled segments that overlap in depth;
* warsaw_styles.blend: style inheritance and a keyframed warp;
* lion_benchmark.blend: 342k points, three styled segments, 1920x1080
  (the benchmark scene of docs/performance.md; no preview);
* site_proposal.blend: a proposed building (a Blender mesh) on the LiDAR HD
  tile, the scan and the mesh styled differently, lit by one sun.
With names (urban_lidarhd, warsaw_styles, lion_benchmark, site_proposal)
only those are made.
Opening or rendering a .blend needs the add-on enabled, e.g.

    POINTNPR_BUILD_DIR=<builddir> blender -b blend_examples/urban_lidarhd.blend \
        --python scripts/enable_addon.py -o //render_#### -a

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
URBAN_SCAN = os.path.join(REPO, "data", "lidarhd_myria3d_870000_6618000_subset.las")
LION_SCAN = os.path.join(REPO, "data", "lion_takanawa.ply")

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


def new_scene(width, height, world_color, frames=48):
    """Empties the file and sets up a PointNPR scene (Standard view transform,
    so scan colours come out as authored)."""
    clear()
    scene = bpy.context.scene
    scene.render.engine = 'POINTNPR'
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.frame_start, scene.frame_end = 1, frames
    scene.render.fps = 24
    scene.view_settings.view_transform = 'Standard'
    if scene.world is None:
        scene.world = bpy.data.worlds.new("World")
    scene.world.color = world_color
    scene.pointnpr.mode = "inpaint"
    return scene


def add_camera(scene, target, offset, lens=35.0, clip_end=1000.0):
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = lens
    cam_data.clip_start, cam_data.clip_end = 0.1, clip_end
    cam = bpy.data.objects.new("Camera", cam_data)
    cam.location = Vector(target) + Vector(offset)
    cam.rotation_euler = (Vector(target) - cam.location).to_track_quat('-Z', 'Y').to_euler()
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


def save(scene, name, preview_frame=None):
    os.makedirs(OUT_DIR, exist_ok=True)
    blend = os.path.join(OUT_DIR, name + ".blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, compress=True)
    print("wrote", blend)
    if preview_frame is not None:
        scene.render.filepath = os.path.join(OUT_DIR, name + "_preview.png")
        scene.frame_set(preview_frame)
        scene.render.resolution_percentage = 50   # small preview; the .blend keeps 100 %
        bpy.ops.render.render(write_still=True)
        print("wrote", scene.render.filepath)


def make_urban():
    """Seed 000's urban map in small: the three classes of an IGN LiDAR HD
    tile as segments. From the oblique camera, trees stand in front of roofs
    and roofs in front of the ground, so depth compositing matters."""
    scene = new_scene(1280, 720, (0.93, 0.91, 0.86))
    bpy.ops.import_scene.pointnpr_cloud(filepath=URBAN_SCAN, split_by_classification=True)
    root = bpy.data.collections["lidarhd_myria3d_870000_6618000_subset"]

    ground = nodes.new_style("Ground Toon")
    set_params(nodes.mark_node(ground), size_mode="world", world_size=0.55, color_source="rgb")
    cartoon = nodes.append_node(ground, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    set_params(cartoon, levels=6, outline_width=0, edge_strength=0.6)
    root.pointnpr_style = ground  # "Ground (2)" has none of its own: it inherits this

    buildings = nodes.new_style("Ink Buildings")
    set_params(nodes.mark_node(buildings), size_mode="world", world_size=0.5, color_source="rgb")
    ink = nodes.append_node(buildings, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    set_params(ink, levels=4, outline_width=2, edge_color=(0.1, 0.08, 0.08, 1.0))
    nodes.append_node(buildings, nodes.ROLE_INPAINT, "inpaint", name="Inpaint Depth")

    trees = nodes.new_style("Trees White Outline")
    set_params(nodes.mark_node(trees), size_mode="world", world_size=0.6, color_source="rgb")
    toon = nodes.append_node(trees, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    set_params(toon, levels=4, outline_width=1, fill_gaps=4, edge_color=(1.0, 1.0, 1.0, 1.0))
    warp = nodes.append_node(trees, nodes.ROLE_FILTER, "warp", name="Warp")
    set_params(warp, amplitude=2.0, wavelength=90.0, speed=0.5)
    nodes.append_node(trees, nodes.ROLE_INPAINT, "inpaint", name="Inpaint Depth")

    for coll in root.children:
        if coll.name.startswith("Building"):
            coll.pointnpr_style = buildings
        elif coll.name.startswith("Unclassified"):
            coll.pointnpr_style = trees

    lo, hi = scene_bounds()
    centre = (lo + hi) / 2
    extent = max((hi - lo).x, (hi - lo).y)
    add_camera(scene, centre, (-0.45 * extent, -0.6 * extent, 0.38 * extent), lens=35.0,
               clip_end=10.0 * extent)
    save(scene, "urban_lidarhd", preview_frame=1)


def make_lion_benchmark():
    """The 300k+ point benchmark scene: the lion scan split by height into
    three segments (plinth, body, head) with three styles, at 1920x1080."""
    scene = new_scene(1920, 1080, (1.0, 1.0, 1.0), frames=24)
    data = pointnpr.read(LION_SCAN)
    positions = data.positions
    colors = data.attributes["colors"]
    z = positions[:, 2]
    parts = [("Plinth", z < -2.6, None), ("Body", (z >= -2.6) & (z < -1.0), "cartoon"),
             ("Head", z >= -1.0, "warp")]
    from pointnpr.blender import importer
    root = bpy.data.collections.new("lion_takanawa")
    scene.collection.children.link(root)
    for name, mask, filter_id in parts:
        coll = bpy.data.collections.new(name)
        root.children.link(coll)
        mesh = importer.create_point_mesh(name, positions[mask], colors[mask])
        coll.objects.link(bpy.data.objects.new(name, mesh))
        style = nodes.new_style(name + " Style")
        set_params(nodes.mark_node(style), point_size=3.0, color_source="rgb")
        if filter_id:
            nodes.append_node(style, nodes.ROLE_FILTER, filter_id, name=filter_id.title())
        coll.pointnpr_style = style
    add_camera(scene, (-2.9, 3.9, -1.2), (5.5, -5.5, 2.7), lens=35.0, clip_end=100.0)
    save(scene, "lion_benchmark")


def scene_bounds():
    points = [o.matrix_world @ v.co for o in bpy.data.objects if o.type == 'MESH'
              for v in list(o.data.vertices)[::10]]
    lo = Vector(tuple(min(p[i] for p in points) for i in range(3)))
    hi = Vector(tuple(max(p[i] for p in points) for i in range(3)))
    return lo, hi


def make_warsaw():
    scene = new_scene(960, 540, (0.9, 0.9, 0.85))

    bpy.ops.import_scene.pointnpr_cloud(filepath=SCAN, split_by_classification=True)
    root = bpy.data.collections["warsaw_small"]

    # The file's collection: colours from the scan, cartoon look. Classes
    # without a style of their own (Ground, Never Classified) inherit it.
    base = nodes.new_style("Scan Cartoon")
    set_params(nodes.mark_node(base), size_mode="world", world_size=0.8, color_source="rgb")
    nodes.append_node(base, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    root.pointnpr_style = base

    # Vegetation: one shared style, a constant green with a keyframed warp.
    veg = nodes.new_style("Vegetation Warp")
    set_params(nodes.mark_node(veg), size_mode="world", world_size=0.7, color_source="constant",
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
    lo, hi = scene_bounds()
    centre = (lo + hi) / 2
    extent = max((hi - lo).x, (hi - lo).y)
    add_camera(scene, centre, (-0.8 * extent, -0.9 * extent, 0.7 * extent), clip_end=10.0 * extent)
    save(scene, "warsaw_styles", preview_frame=24)


def make_site_proposal():
    """Seed 001's architects: a proposed building (an ordinary Blender mesh
    with two materials) designed against a scanned site (the LiDAR HD
    tile). The scan keeps a soft cartoon look; the building is drawn as
    flat-shaded faces with ink outlines; both take their light from the
    scene's sun lamp, and composite mode inpaint lets trees of the scan
    stand in front of the building and the building in front of the ground."""
    scene = new_scene(1280, 720, (0.93, 0.91, 0.86))
    bpy.ops.import_scene.pointnpr_cloud(filepath=URBAN_SCAN, split_by_classification=True)
    root = bpy.data.collections["lidarhd_myria3d_870000_6618000_subset"]
    site = nodes.new_style("Site Soft")
    set_params(nodes.mark_node(site), size_mode="world", world_size=0.55, color_source="rgb")
    cartoon = nodes.append_node(site, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    set_params(cartoon, levels=6, outline_width=0, edge_strength=0.4)
    nodes.append_node(site, nodes.ROLE_INPAINT, "inpaint", name="Inpaint Depth")
    root.pointnpr_style = site

    lo, hi = scene_bounds()
    # An open patch of the tile (mostly ground class), 40-60 m east and
    # 20-40 m north of its corner; the ground there is 0.7 m above the lowest point.
    base = lo + Vector((50.0, 30.0, 0.7))
    w, d, h, ridge = 14.0, 9.0, 8.0, 4.0
    x0, x1, y0, y1 = -w / 2, w / 2, -d / 2, d / 2
    verts = [(x0, y0, 0), (x1, y0, 0), (x1, y1, 0), (x0, y1, 0), (x0, y0, h), (x1, y0, h), (x1, y1, h),
             (x0, y1, h), (x0, 0, h + ridge), (x1, 0, h + ridge)]
    faces = [(0, 3, 2, 1), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 9, 5), (3, 0, 4, 8, 7), (4, 5, 9, 8), (6, 7, 8, 9)]
    mesh = bpy.data.meshes.new("Proposal")
    mesh.from_pydata(verts, [], faces)
    walls = bpy.data.materials.new("Walls")
    walls.use_nodes = True
    walls.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.85, 0.83, 0.78, 1.0)
    roof = bpy.data.materials.new("Roof")
    roof.use_nodes = True
    roof.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.45, 0.12, 0.07, 1.0)
    mesh.materials.append(walls)
    mesh.materials.append(roof)
    for poly in mesh.polygons[5:]:
        poly.material_index = 1
    mesh.update()
    building = bpy.data.collections.new("Proposed building")
    scene.collection.children.link(building)
    obj = bpy.data.objects.new("Proposal", mesh)
    obj.location = base
    obj.rotation_euler = (0.0, 0.0, 0.35)
    building.objects.link(obj)
    ink = nodes.new_style("Proposal Ink")
    surface = nodes.append_node(ink, nodes.ROLE_MARK, nodes.SURFACE_MARK, name="Mesh Surface")
    set_params(surface, shading="flat", shading_strength=0.55, light_space="scene_sun")
    outline = nodes.append_node(ink, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    set_params(outline, levels=4, outline_width=4, edge_color=(0.08, 0.08, 0.1, 1.0))
    nodes.append_node(ink, nodes.ROLE_INPAINT, "inpaint", name="Inpaint Depth")
    building.pointnpr_style = ink

    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
    # Toward the light: from the south-west, 40 degrees up (a sun shines along its -Z).
    sun.rotation_euler = Vector((-0.55, -0.55, 0.63)).to_track_quat('Z', 'Y').to_euler()
    scene.collection.objects.link(sun)
    centre = base + Vector((0.0, 0.0, 5.0))
    add_camera(scene, centre, (-26.0, -34.0, 20.0), lens=35.0, clip_end=1000.0)
    save(scene, "site_proposal", preview_frame=1)


MAKERS = {"urban_lidarhd": make_urban, "warsaw_styles": make_warsaw, "lion_benchmark": make_lion_benchmark,
          "site_proposal": make_site_proposal}
for name in argv[2:] or MAKERS:
    MAKERS[name]()
