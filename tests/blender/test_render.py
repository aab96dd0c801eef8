import math
import os
import subprocess
import sys

import bpy
import numpy as np
import pointnpr
import pytest
from pointnpr.blender import engine, nodes, sync

import helpers
from helpers import BLUE, GREEN, HEIGHT, RED, WIDTH, is_color

CENTRE = (HEIGHT // 2, WIDTH // 2)   # (row, column)
FAR_ONLY = (HEIGHT // 2, 10)         # inside the far plane, outside the near one
CORNER = (1, 1)                      # outside both planes


@pytest.mark.parametrize("mode", ["depth_test", "inpaint"])
def test_nearer_segment_wins(tmp_path, mode):
    helpers.two_planes_scene(mode)
    px, _ = helpers.render_pixels(tmp_path)
    assert px.shape == (HEIGHT, WIDTH, 4)
    assert is_color(px[CENTRE], RED), px[CENTRE]
    assert is_color(px[FAR_ONLY], BLUE), px[FAR_ONLY]
    assert is_color(px[CORNER], (0, 0, 0)), px[CORNER]
    assert px[CORNER][3] > 0.99  # opaque world background


def test_layering_puts_later_segment_on_top(tmp_path):
    # Same scene, composite by order only: 'Far' comes after 'Near'.
    helpers.two_planes_scene("layering")
    px, _ = helpers.render_pixels(tmp_path)
    assert is_color(px[CENTRE], BLUE), px[CENTRE]


def test_segment_order_is_collection_order():
    scene, near, far = helpers.two_planes_scene()
    sub = helpers.new_collection("Sub", near)
    helpers.add_points("B", sub, helpers.grid_points(0.2, 0.1, 1.0))
    helpers.add_points("A", sub, helpers.grid_points(0.2, 0.1, 1.0))
    helpers.add_points("Loose", scene.collection, helpers.grid_points(0.2, 0.1, 1.0))
    depsgraph = bpy.context.evaluated_depsgraph_get()
    synced = sync.build_scene(depsgraph, 1.0)
    assert synced.segment_names == [scene.collection.name, "Near", "Sub", "Far"]
    assert synced.num_objects == 5


def test_background_world_color_and_transparency(tmp_path):
    scene, _, _ = helpers.two_planes_scene()
    scene.world.color = (0.0, 1.0, 0.0)
    px, _ = helpers.render_pixels(tmp_path, "world.png")
    assert is_color(px[CORNER], GREEN), px[CORNER]
    scene.render.film_transparent = True
    px, _ = helpers.render_pixels(tmp_path, "transparent.png")
    assert px[CORNER][3] < 0.01
    assert px[CENTRE][3] > 0.99


def test_child_inherits_parent_style(tmp_path):
    scene = helpers.reset_scene()
    helpers.add_camera()
    parent = helpers.new_collection("Parent")
    child = helpers.new_collection("Child", parent)
    helpers.add_points("P", child, helpers.grid_points(1.5, 0.05, 0.0),
                       colors=np.tile([[1.0, 0.0, 1.0]], (61 * 61, 1)))
    style = helpers.constant_style("Green", GREEN, point_size=5.0)
    parent.pointnpr_style = style
    inherited, inherited_bytes = helpers.render_pixels(tmp_path, "inherited.png")
    assert is_color(inherited[CENTRE], GREEN), inherited[CENTRE]
    child.pointnpr_style = style
    explicit, explicit_bytes = helpers.render_pixels(tmp_path, "explicit.png")
    assert np.array_equal(inherited, explicit)
    # Without any style, the points' own (magenta) colours are used.
    child.pointnpr_style = None
    parent.pointnpr_style = None
    default, _ = helpers.render_pixels(tmp_path, "default.png")
    assert is_color(default[CENTRE], (1.0, 0.0, 1.0)), default[CENTRE]
    # The scene's default style applies when no collection has one.
    scene.pointnpr_default_style = style
    scene_default, _ = helpers.render_pixels(tmp_path, "scene_default.png")
    assert np.array_equal(scene_default, explicit)


def _warp_schema():
    schema = pointnpr.schema("warp")
    params = [p for p in schema["params"] if p["type"] == "float" and p["max"] > p["min"]]
    assert params, "warp has no float parameter"
    return schema, params


def _animated_warp_scene():
    scene = helpers.reset_scene()
    helpers.add_camera()
    coll = helpers.new_collection("Warped")
    rng = np.random.default_rng(3)
    helpers.add_points("W", coll, helpers.grid_points(1.2, 0.05, 0.0),
                       colors=rng.random((49 * 49, 3)))
    tree = nodes.new_style("Warp Style")
    tree.nodes["Points"].point_size = 4.0
    warp = nodes.append_node(tree, nodes.ROLE_FILTER, "warp", name="Warp")
    coll.pointnpr_style = tree
    _schema, params = _warp_schema()
    # Keyframe every float parameter from its low end to its high end.
    for p in params:
        prop = nodes.property_identifier(p["name"])
        lo = p["min"] + 0.1 * (p["max"] - p["min"])
        hi = p["min"] + 0.6 * (p["max"] - p["min"])
        setattr(warp, prop, lo)
        warp.keyframe_insert(prop, frame=1)
        setattr(warp, prop, hi)
        warp.keyframe_insert(prop, frame=10)
    return scene, tree, params


def test_keyframed_warp_changes_between_frames(tmp_path):
    scene, tree, params = _animated_warp_scene()
    scene.frame_set(1)
    f1, f1_bytes = helpers.render_pixels(tmp_path, "f1.png")
    scene.frame_set(10)
    f10, f10_bytes = helpers.render_pixels(tmp_path, "f10.png")
    scene.frame_set(1)
    again, again_bytes = helpers.render_pixels(tmp_path, "f1b.png")
    assert f1_bytes == again_bytes
    assert f1_bytes != f10_bytes
    assert np.abs(f1 - f10).max() > 0.1
    # The style read for each frame follows the keyframes.
    p = params[0]
    v1 = nodes.read_style(tree, 1.0)["filters"][0][1][p["name"]]
    v10 = nodes.read_style(tree, 10.0)["filters"][0][1][p["name"]]
    assert math.isclose(v1, p["min"] + 0.1 * (p["max"] - p["min"]), rel_tol=1e-4, abs_tol=1e-5)
    assert math.isclose(v10, p["min"] + 0.6 * (p["max"] - p["min"]), rel_tol=1e-4, abs_tol=1e-5)


def _pass_pixels(scene, socket_name, tmp_path):
    """Render, writing one Render Layers output to a float EXR through a
    File Output node; returns its first channel (H, W), bottom row first."""
    tree, comp = helpers.compositor_tree(scene)
    rl = tree.nodes.new("CompositorNodeRLayers")
    out = tree.nodes.new("CompositorNodeOutputFile")
    if hasattr(out.format, "media_type"):  # Blender 5.0: multilayer by default
        out.format.media_type = 'IMAGE'
    out.format.file_format = 'OPEN_EXR'
    out.format.color_depth = '32'
    prefix = socket_name.replace(" ", "_") + "_"
    if hasattr(out, "file_slots"):
        out.base_path = str(tmp_path)
        out.file_slots[0].path = prefix
    else:  # Blender 5.0: a directory, a file name, and items for the inputs
        out.directory, out.file_name = str(tmp_path), ""
        out.file_output_items.new('FLOAT', prefix)
    tree.links.new(rl.outputs["Image"], comp.inputs[0])
    names = [o.name for o in rl.outputs if o.enabled]
    assert socket_name in names, names
    tree.links.new(rl.outputs[socket_name], out.inputs[0])
    bpy.ops.render.render()
    # <prefix><frame>.exr; Blender 5.0 leaves the frame out of a still.
    names = [prefix + "%04d.exr" % scene.frame_current, prefix + ".exr"]
    paths = [str(tmp_path / n) for n in names if os.path.exists(str(tmp_path / n))]
    assert len(paths) == 1, os.listdir(str(tmp_path))
    path = paths[0]
    img = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = img.size
        assert (w, h) == (WIDTH, HEIGHT)
        px = np.empty(w * h * 4, dtype=np.float32)
        img.pixels.foreach_get(px)
    finally:
        bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[:, :, 0]


def test_depth_and_segment_index_passes(tmp_path):
    scene, _, _ = helpers.two_planes_scene()
    scene.view_layers[0].use_pass_z = True
    depth = _pass_pixels(scene, "Depth", tmp_path)
    # Camera at z=10: the near plane (z=2) is 8 units away, the far one 10.
    assert abs(depth[CENTRE] - 8.0) < 0.05, depth[CENTRE]
    assert abs(depth[FAR_ONLY] - 10.0) < 0.05, depth[FAR_ONLY]
    assert depth[CORNER] > 1e6
    index = _pass_pixels(scene, "Segment Index", tmp_path)
    assert index[CENTRE] == 0.0     # Near is the first segment
    assert index[FAR_ONLY] == 1.0   # Far the second
    assert index[CORNER] == -1.0    # background
    assert set(np.unique(index)) <= {-1.0, 0.0, 1.0}


def test_depth_pass_absent_when_disabled():
    scene, _, _ = helpers.two_planes_scene()
    scene.view_layers[0].use_pass_z = False
    tree, _output = helpers.compositor_tree(scene)
    rl = tree.nodes.new("CompositorNodeRLayers")
    names = [o.name for o in rl.outputs if o.enabled]
    assert "Segment Index" in names
    assert "Depth" not in names


def test_render_error_is_reported_not_raised(tmp_path):
    scene, _, _ = helpers.two_planes_scene()
    scene.camera.data.type = 'PANO'
    scene.render.filepath = str(tmp_path / "pano.png")
    # Must not crash Blender; the operator reports the error.
    try:
        bpy.ops.render.render(write_still=True)
    except RuntimeError as exc:
        assert "Panoramic" in str(exc)
    scene.camera.data.type = 'PERSP'
    px, _ = helpers.render_pixels(tmp_path, "after.png")
    assert is_color(px[CENTRE], RED)


def test_cloud_cache_reuses_uploads():
    helpers.two_planes_scene()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    sync.clear_cache()
    sync.build_scene(depsgraph, 1.0)
    uploads = sync.cache_stats()["uploads"]
    assert uploads == 2
    sync.build_scene(depsgraph, 2.0)
    assert sync.cache_stats()["uploads"] == uploads
    # Changing coordinates gives a new cloud.
    obj = bpy.data.objects["NearPoints"]
    obj.data.vertices[0].co.z += 0.5
    obj.data.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    sync.build_scene(depsgraph, 2.0)
    assert sync.cache_stats()["uploads"] == uploads + 1
    # Deleted objects leave the cache.
    bpy.data.objects.remove(obj)
    sync.build_scene(bpy.context.evaluated_depsgraph_get(), 2.0)
    assert sync.cache_stats()["objects"] == 1


def test_orthographic_camera(tmp_path):
    scene, _, _ = helpers.two_planes_scene()
    scene.camera.data.type = 'ORTHO'
    scene.camera.data.ortho_scale = 4.0   # 4 units across: the far plane fills it
    px, _ = helpers.render_pixels(tmp_path, "ortho.png")
    assert is_color(px[CENTRE], RED), px[CENTRE]
    assert is_color(px[CORNER], BLUE), px[CORNER]


def test_resolution_percentage(tmp_path):
    scene, _, _ = helpers.two_planes_scene()
    scene.render.resolution_percentage = 50
    px, _ = helpers.render_pixels(tmp_path, "half.png")
    assert px.shape[:2] == (HEIGHT // 2, WIDTH // 2)
    assert is_color(px[HEIGHT // 4, WIDTH // 4], RED)


def _blender_render(blend, out_pattern, frame_args):
    env = dict(os.environ)
    env["POINTNPR_BUILD_DIR"] = os.environ["POINTNPR_BUILD_DIR"]
    # The add-on before the file, as scripts/render_example.sh does.
    cmd = helpers.blender_command() + ["-b", "--factory-startup", "--python-exit-code", "1",
                                       *helpers.addon_args(), blend, "-o", out_pattern, "-F", "PNG"] + frame_args
    proc = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          timeout=300)
    assert proc.returncode == 0, proc.stdout.decode(errors="replace")[-3000:]
    return proc.stdout.decode(errors="replace")


def test_same_blend_renders_identically_in_two_processes(tmp_path):
    scene, tree, _params = _animated_warp_scene()
    scene.frame_end = 2
    blend = str(tmp_path / "scene.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
    outputs = []
    for run in range(2):
        pattern = str(tmp_path / ("run%d_####" % run))
        log = _blender_render(blend, pattern, ["-f", "1"])
        # Loading a file that uses PointNPR, the add-on enabled, is silent.
        assert "not available" not in log and "Error" not in log, log[-3000:]
        path = str(tmp_path / ("run%d_0001.png" % run))
        assert os.path.exists(path), log[-3000:]
        with open(path, "rb") as f:
            outputs.append(f.read())
    assert outputs[0] == outputs[1]
    # The same frame rendered in this process matches too (pixels).
    scene.frame_set(1)
    here, _ = helpers.render_pixels(tmp_path, "here.png")
    assert np.array_equal(here, helpers.load_png(str(tmp_path / "run0_0001.png")))


def test_animation_render_writes_every_frame(tmp_path):
    scene, _, _ = _animated_warp_scene()
    scene.frame_start, scene.frame_end = 1, 3
    blend = str(tmp_path / "anim.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
    _blender_render(blend, str(tmp_path / "anim_####"), ["-a"])
    frames = [str(tmp_path / ("anim_%04d.png" % f)) for f in (1, 2, 3)]
    assert all(os.path.exists(f) for f in frames)
    images = [helpers.load_png(f) for f in frames]
    assert not np.array_equal(images[0], images[2])


@pytest.mark.parametrize("rasterizer,gl_method", [("gl", "compute"), ("gl", "gl_points"), ("native", "compute"),
                                                  ("auto", "compute")])
def test_rasterizer_choice(tmp_path, rasterizer, gl_method):
    """The rasterizer (and GL method) is the Points mark's parameter; the
    legacy scene setting is ignored."""
    scene, near, far = helpers.two_planes_scene("depth_test")
    for coll in (near, far):
        node = coll.pointnpr_style.nodes["Points"]
        node.rasterizer, node.gl_method = rasterizer, gl_method
    values = nodes.read_style(near.pointnpr_style, 1.0)["mark"][1]
    assert (values["rasterizer"], values["gl_method"]) == (rasterizer, gl_method)
    scene.pointnpr.rasterizer = "compute" if gl_method == "gl_points" else "gl_points"
    px, _ = helpers.render_pixels(tmp_path, rasterizer + gl_method + ".png")
    assert is_color(px[CENTRE], RED), px[CENTRE]
    assert is_color(px[FAR_ONLY], BLUE), px[FAR_ONLY]


def _schema_filters():
    return [s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"]


@pytest.mark.parametrize("filter_id", _schema_filters())
def test_every_filter_node_renders(tmp_path, filter_id):
    """Points -> <filter> -> Inpaint Depth -> Output with default values."""
    scene, near, far = helpers.two_planes_scene("inpaint")
    tree = near.pointnpr_style
    nodes.append_node(tree, nodes.ROLE_FILTER, filter_id, name="F")
    nodes.append_node(tree, nodes.ROLE_INPAINT, "inpaint", name="Inpaint")
    desc = nodes.read_style(tree, 1.0)
    assert [f[0] for f in desc["filters"]] == [filter_id] and desc["inpaint"] is not None
    px, _ = helpers.render_pixels(tmp_path, filter_id + ".png")
    # The far segment is untouched by the near one's filter.
    assert is_color(px[FAR_ONLY], BLUE), px[FAR_ONLY]
    assert bpy.context.scene.render.engine == 'POINTNPR'


def _red_columns(px, row):
    return np.nonzero([is_color(p, RED) for p in px[row]])[0]


def test_camera_shift_and_pixel_aspect(tmp_path):
    scene, near, _ = helpers.two_planes_scene()
    base, _ = helpers.render_pixels(tmp_path, "base.png")
    cols = _red_columns(base, CENTRE[0])
    assert len(cols) > 4
    # shift_x = 0.25 moves the view right by a quarter of the width: the
    # image content moves left by 16 px.
    scene.camera.data.shift_x = 0.25
    shifted, _ = helpers.render_pixels(tmp_path, "shift.png")
    moved = _red_columns(shifted, CENTRE[0])
    assert abs((cols.mean() - moved.mean()) - WIDTH * 0.25) < 1.5
    scene.camera.data.shift_x = 0.0
    # Pixels twice as wide as tall, horizontal sensor fit (Blender's
    # viewplane): the same columns, twice the rows.
    scene.camera.location.z = 20.0
    near.pointnpr_style.nodes["Points"].point_size = 1.0   # measure geometry, not splats
    square, _ = helpers.render_pixels(tmp_path, "square.png")
    scene.render.pixel_aspect_x = 2.0
    wide, _ = helpers.render_pixels(tmp_path, "aspect.png")
    rows = lambda px: np.nonzero([is_color(p, RED) for p in px[:, WIDTH // 2]])[0]  # noqa: E731
    assert abs(len(_red_columns(wide, CENTRE[0])) - len(_red_columns(square, CENTRE[0]))) <= 1
    assert abs(len(rows(wide)) - 2 * len(rows(square))) <= 2, (len(rows(wide)), len(rows(square)))


def test_hidden_and_excluded_objects_are_not_rendered(tmp_path):
    scene, near, far = helpers.two_planes_scene()
    bpy.data.objects["NearPoints"].hide_render = True
    px, _ = helpers.render_pixels(tmp_path, "hidden.png")
    assert is_color(px[CENTRE], BLUE), px[CENTRE]
    bpy.data.objects["NearPoints"].hide_render = False
    layer = bpy.context.view_layer.layer_collection.children["Far"]
    layer.exclude = True
    px, _ = helpers.render_pixels(tmp_path, "excluded.png")
    assert is_color(px[CENTRE], RED) and is_color(px[FAR_ONLY], (0, 0, 0)), px[FAR_ONLY]
    layer.exclude = False


def test_intensity_attribute_is_read_only_when_needed(tmp_path):
    scene = helpers.reset_scene()
    helpers.add_camera()
    coll = helpers.new_collection("I")
    pts = helpers.grid_points(1.5, 0.05, 0.0)
    ramp = (pts[:, 0] - pts[:, 0].min()) / np.ptp(pts[:, 0])
    helpers.add_points("Ramp", coll, pts, colors=np.tile([[1.0, 0.0, 0.0]], (len(pts), 1)),
                       intensity=ramp * 1000.0)
    tree = nodes.new_style("Intensity")
    tree.nodes["Points"].color_source = "intensity"
    tree.nodes["Points"].point_size = 5.0
    coll.pointnpr_style = tree
    sync.clear_cache()
    px, _ = helpers.render_pixels(tmp_path, "intensity.png")
    row = px[CENTRE[0]]
    left, right = row[WIDTH // 2 - 12][:3], row[WIDTH // 2 + 12][:3]
    # Grey levels from intensity, increasing to the right; not the red colours.
    assert abs(left[0] - left[2]) < 0.05 and abs(right[0] - right[2]) < 0.05
    assert right.mean() > left.mean() + 0.1
    assert sync.source_attributes(nodes.make_core_style(nodes.read_style(tree, 1.0))) == ("intensity",)
    # Only the intensity was read, not the colours the object also has.
    assert [a for o, a in sync.read_log if o == "Ramp"][-1:] == ["intensity"]
    assert ("Ramp", "colors") not in sync.read_log


def test_sync_reads_float32_vertices_without_a_float64_copy():
    # numpy's arrays are traced by tracemalloc: the sync's temporaries are
    # Blender's float32 vertices (12 B a point) and, before them, one float32
    # RGBA read of the colours (16 B, gone when the vertices are read); a
    # float64 copy of the positions (24 B), float temporaries per colour
    # channel or both reads held at once would exceed the bound.
    import tracemalloc

    helpers.reset_scene()
    coll = helpers.new_collection("Big")
    pts = helpers.grid_points(10.0, 0.02, 0.0)   # 1M points
    n = len(pts)
    obj = helpers.add_points("Big", coll, pts, colors=np.tile([[0.2, 0.4, 0.6]], (n, 1)))
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    for attributes, bound in (((), 16 * n), (("colors",), 24 * n)):
        sync.clear_cache()
        tracemalloc.start()
        try:
            cloud = sync.cloud_for(evaluated, attributes)
            _size, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        assert cloud.num_points == n
        assert peak < bound, (attributes, peak / n)
    # The float32 cloud is the cloud of the same values in float64.
    reference = pointnpr.PointCloud(sync.read_positions(evaluated).astype(np.float64),
                                    colors=sync.read_colors(evaluated))
    assert np.array_equal(cloud.point_index, reference.point_index)
    assert cloud.bounds == reference.bounds and cloud.num_chunks == reference.num_chunks


def _red_box(color):
    red = (color[..., 0] > 0.8) & (color[..., 1] < 0.2) & (color[..., 2] < 0.2)
    ys, xs = np.nonzero(red)
    assert len(xs), "no red pixel"
    return xs.min(), xs.max(), ys.min(), ys.max()


@pytest.mark.parametrize("config", [
    {},
    {"sensor_fit": 'VERTICAL'},
    {"sensor_fit": 'HORIZONTAL', "lens": 35.0},
    {"shift_x": 0.2, "shift_y": -0.1},
    {"pixel_aspect_x": 2.0},
    {"pixel_aspect_y": 1.5, "sensor_fit": 'VERTICAL'},
    {"type": 'ORTHO', "ortho_scale": 5.0},
    {"type": 'ORTHO', "ortho_scale": 5.0, "shift_x": 0.1, "pixel_aspect_x": 1.5},
    {"resolution": (48, 64)},
])
def test_camera_matches_blender_projection(config):
    """The engine's camera frames the scene exactly like Blender's own
    projection (Object.calc_matrix_camera) for the same settings."""
    scene, near, _ = helpers.two_planes_scene("depth_test")
    scene.camera.location.z = 20.0
    near.pointnpr_style.nodes["Points"].point_size = 1.0
    cam = scene.camera.data
    w, h = config.get("resolution", (WIDTH, HEIGHT))
    scene.render.resolution_x, scene.render.resolution_y = w, h
    for key, value in config.items():
        if key.startswith("pixel_aspect"):
            setattr(scene.render, key, value)
        elif key != "resolution":
            setattr(cam, key, value)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    synced = sync.build_scene(depsgraph, 1.0)
    ours = engine.make_camera(depsgraph, scene.camera, w, h)
    proj = scene.camera.calc_matrix_camera(depsgraph, x=w, y=h, scale_x=scene.render.pixel_aspect_x,
                                           scale_y=scene.render.pixel_aspect_y)
    view = np.linalg.inv(engine._camera_world_matrix(scene.camera))
    blender = pointnpr.Camera.from_matrices(view, np.array(proj, dtype=np.float64))
    kwargs = dict(composite={"mode": "depth_test"})
    a = engine.renderer().render(synced.scene, ours, w, h, **kwargs)
    b = engine.renderer().render(synced.scene, blender, w, h, **kwargs)
    box_a, box_b = _red_box(a.color), _red_box(b.color)
    assert all(abs(int(p) - int(q)) <= 1 for p, q in zip(box_a, box_b)), (box_a, box_b)


def _mesh_to_points_modifier(obj):
    tree = bpy.data.node_groups.new("To Points", 'GeometryNodeTree')
    if hasattr(tree, "interface"):  # Blender 4.x
        tree.interface.new_socket("Geometry", in_out='INPUT', socket_type='NodeSocketGeometry')
        tree.interface.new_socket("Geometry", in_out='OUTPUT', socket_type='NodeSocketGeometry')
    else:
        tree.inputs.new('NodeSocketGeometry', "Geometry")
        tree.outputs.new('NodeSocketGeometry', "Geometry")
    gin = tree.nodes.new('NodeGroupInput')
    gout = tree.nodes.new('NodeGroupOutput')
    to_points = tree.nodes.new('GeometryNodeMeshToPoints')
    tree.links.new(gin.outputs[0], to_points.inputs["Mesh"])
    tree.links.new(to_points.outputs["Points"], gout.inputs[0])
    mod = obj.modifiers.new("To Points", 'NODES')
    mod.node_group = tree
    return mod


def test_geometry_nodes_point_cloud_is_rendered(tmp_path):
    """A mesh turned into a point cloud by geometry nodes renders in its
    object's collection (Blender's PointCloud geometry)."""
    scene, near, far = helpers.two_planes_scene()
    obj = bpy.data.objects["NearPoints"]
    _mesh_to_points_modifier(obj)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    types = {(o.type, o.name) for o, _m, _owner in sync.visible_instances(depsgraph)}
    assert ('POINTCLOUD', "NearPoints") in types
    synced = sync.build_scene(depsgraph, 1.0)
    assert synced.segment_names == ["Near", "Far"]
    px, _ = helpers.render_pixels(tmp_path, "gn.png")
    assert is_color(px[CENTRE], RED), px[CENTRE]


def test_a_pointcloud_object_is_a_segment_member(tmp_path):
    """Blender's own PointCloud object (not a mesh) is a member of its
    collection's segment: made directly where Python can give a PointCloud
    points (PointCloud.resize, Blender 5.1+), through geometry nodes before."""
    scene, near, far = helpers.two_planes_scene()
    old = bpy.data.objects["NearPoints"]
    if hasattr(bpy.types.PointCloud, "resize"):
        positions = helpers.grid_points(1.0, 0.05, 2.0).astype(np.float32)
        cloud = bpy.data.pointclouds.new("NearCloud")
        cloud.resize(len(positions))
        cloud.attributes["position"].data.foreach_set("vector", positions.ravel())
        bpy.data.objects.remove(old)
        obj = bpy.data.objects.new("NearCloud", cloud)
        near.objects.link(obj)
        assert obj.type == 'POINTCLOUD'
    else:
        obj = old
        _mesh_to_points_modifier(obj)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    types = {(o.type, o.name) for o, _m, _owner in sync.visible_instances(depsgraph)}
    assert ('POINTCLOUD', obj.name) in types, types
    assert sync.build_scene(depsgraph, 1.0).segment_names == ["Near", "Far"]
    px, _ = helpers.render_pixels(tmp_path, "pointcloud.png")
    assert is_color(px[CENTRE], RED), px[CENTRE]
    assert is_color(px[FAR_ONLY], BLUE), px[FAR_ONLY]


def test_passes_written_with_foreach_set(tmp_path):
    helpers.two_planes_scene()
    bpy.context.scene.view_layers[0].use_pass_z = True
    before = dict(engine.stats)
    helpers.render_pixels(tmp_path)
    assert engine.stats["final_renders"] == before["final_renders"] + 1
    assert engine.stats["slow_pass_writes"] == 0


def test_scene_without_points_renders_background(tmp_path):
    scene = helpers.reset_scene()
    helpers.add_camera()
    scene.world.color = (0.0, 0.0, 1.0)
    helpers.new_collection("Empty")
    px, _ = helpers.render_pixels(tmp_path, "empty.png")
    assert all(is_color(px[rc], BLUE) for rc in (CENTRE, CORNER, FAR_ONLY))


def test_style_without_output_falls_back_to_default(tmp_path):
    scene, near, far = helpers.two_planes_scene()
    tree = near.pointnpr_style
    tree.nodes.remove(tree.nodes["Output"])
    desc = nodes.read_style(tree, 1.0)
    assert desc["warnings"] and desc["mark"] == ("points", {})
    px, _ = helpers.render_pixels(tmp_path, "no_output.png")
    # Default style: the points' own colours; these have none -> not red.
    assert not is_color(px[CENTRE], RED)


@pytest.mark.parametrize("crop", [True, False])
def test_border_render(tmp_path, crop):
    scene, _, _ = helpers.two_planes_scene()
    full, _ = helpers.render_pixels(tmp_path, "full.png")
    r = scene.render
    r.use_border = True
    r.use_crop_to_border = crop
    r.border_min_x, r.border_max_x = 0.25, 0.75
    r.border_min_y, r.border_max_y = 0.125, 0.5
    x0, x1, y0, y1 = 16, 48, 6, 24
    part, _ = helpers.render_pixels(tmp_path, "border.png")
    if crop:
        assert part.shape[:2] == (y1 - y0, x1 - x0)
        assert np.array_equal(part, full[y0:y1, x0:x1])
    else:
        assert part.shape == full.shape
        assert np.array_equal(part[y0:y1, x0:x1], full[y0:y1, x0:x1])
        assert part[CORNER][3] == 0.0   # outside the border: nothing rendered


def test_a_frame_over_the_memory_budget_renders_in_tiles_the_same_pixels(tmp_path, monkeypatch):
    scene, _, _ = helpers.two_planes_scene("inpaint")
    scene.render.resolution_x, scene.render.resolution_y = 800, 760  # 155 MB of GL images at 256 B/px
    scene.render.resolution_percentage = 100
    assert scene.pointnpr.memory_budget_gb == 2.0
    whole, _ = helpers.render_pixels(tmp_path, "whole.png")
    calls = []
    real = engine.do_render

    def spy(*args, progress=None, **kwargs):
        def recorded(fraction, text):
            calls.append((fraction, text))
            return progress(fraction, text)
        return real(*args, progress=recorded, **kwargs)

    monkeypatch.setattr(engine, "do_render", spy)
    scene.pointnpr.memory_budget_gb = 0.125
    tiled, _ = helpers.render_pixels(tmp_path, "tiled.png")
    assert np.array_equal(whole, tiled)
    # The progress bar moves per tile.
    tiles = {text.split(":")[0] for _, text in calls if text.startswith("tile ")}
    assert len(tiles) > 1 and "tile 1/%d" % len(tiles) in tiles, calls
    assert [f for f, _ in calls] == sorted(f for f, _ in calls)


def test_the_point_budget_thins_final_renders_and_the_viewport_has_its_own(tmp_path, monkeypatch):
    scene, _, _ = helpers.two_planes_scene()
    assert scene.pointnpr.point_budget_millions == 0.0       # F12: every point by default
    assert scene.pointnpr.viewport_point_budget_millions == 3.0
    assert engine.point_budget(scene) == 0
    assert engine.point_budget(scene, viewport=True) == 3000000
    full, _ = helpers.render_pixels(tmp_path, "full.png")
    budgets = []
    real = engine.renderer().render

    class Spy:
        def render(self, *args, point_budget=0, **kwargs):
            budgets.append(point_budget)
            return real(*args, point_budget=point_budget, **kwargs)

    monkeypatch.setattr(engine, "renderer", lambda: Spy())
    scene.pointnpr.point_budget_millions = 0.0005            # 500 of the planes' 16,000 points
    thinned, _ = helpers.render_pixels(tmp_path, "thinned.png")
    assert budgets == [500]
    covered = lambda px: int((px[..., :3].sum(axis=-1) > 0.1).sum())  # red or blue, not the black world
    assert 0 < covered(thinned) < covered(full)


def test_the_viewport_header_says_when_the_point_budget_thinned_the_frame():
    from types import SimpleNamespace
    synced = SimpleNamespace(segment_names=["a", "b"], num_points=12_000_000)
    whole = SimpleNamespace(stats={"point_budget_points": 12_000_000.0})
    thinned = SimpleNamespace(stats={"point_budget_points": 2_999_871.0, "point_budget_level": 0.4})
    assert engine.stats_line(synced, whole) == "PointNPR: 2 segments, 12,000,000 points"
    assert engine.stats_line(synced, thinned) == \
        "PointNPR: 2 segments, 12,000,000 points (2,999,871 drawn: point budget)"
