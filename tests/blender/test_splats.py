"""3D Gaussian splat captures in Blender: File > Import > Point Cloud takes
an SPZ and detects a 3DGS PLY; one object carries the splats' parameters as
point attributes (blender/splats.py); a collection styled with the gaussians
mark renders them (the sync reads them back), other marks draw the centres."""
import os

import bpy
import mathutils
import numpy as np
import pointnpr
import pytest
from pointnpr.blender import importer, nodes, splats, sync

import helpers

SPLATS = os.path.join(helpers.IO_DATA, "gaussians")
PLAYBOT = os.path.join(SPLATS, "playbot_lod3.spz")


def _values(data, name, prop, width):
    attr = data.attributes[name]
    values = np.empty(len(attr.data) * width, dtype=np.float32)
    attr.data.foreach_get(prop, values)
    return values.reshape(-1, width)


# Blender 5.3 added its own splat point clouds (PointCloud.type
# 'GAUSSIAN_SPLAT'): there a capture is imported as one, before as a mesh.
NATIVE = bpy.app.version >= (5, 3, 0)


def _capture(objs):
    assert len(objs) == 1
    return objs[0]


def _assert_native_attributes(cloud, data, degree):
    """The attributes Blender's own importers write, with the file's values."""
    A = data.attributes
    n = data.num_points
    assert cloud.type == 'GAUSSIAN_SPLAT' and len(cloud.points) == n
    base = _values(cloud, "radiance:base", "vector", 4)
    assert cloud.attributes["radiance:base"].data_type == 'FLOAT4'
    K = (degree + 1) ** 2
    sh = A["sh"].reshape(n, K, 3)
    assert np.allclose(base[:, :3], sh[:, 0]) and np.allclose(base[:, 3], A["opacity"])
    assert np.allclose(_values(cloud, "scale", "vector", 3), A["scales"])
    assert cloud.attributes["rotation"].data_type == 'QUATERNION'
    assert np.allclose(_values(cloud, "rotation", "value", 4), A["rotations"], atol=1e-6)
    for k in range(1, K):
        assert np.allclose(_values(cloud, "radiance:sh_%d" % (k - 1), "vector", 3), sh[:, k])
    assert "radiance:sh_%d" % (K - 1) not in cloud.attributes
    assert "opacity" not in cloud.attributes and "sh_0" not in cloud.attributes
    # The scan colour every scan gets (the 'auto' colour of the other marks).
    colors = cloud.color_attributes["Col"]
    srgb = np.empty(len(colors.data) * 4, np.float32)
    colors.data.foreach_get("color_srgb", srgb)
    assert np.abs(srgb.reshape(-1, 4)[:, :3] * 255.0 - A["colors"][:, :3]).max() <= 0.5


def test_importing_an_spz_and_a_3dgs_ply_gives_one_object_with_the_splats(scene):
    assert splats.native_point_clouds() == NATIVE
    for name, degree in (("synthetic_v3.spz", 3), ("synthetic_3dgs.ply", 2)):
        path = os.path.join(SPLATS, name)
        before = set(bpy.data.objects)
        assert bpy.ops.import_scene.pointnpr_cloud(filepath=path) == {'FINISHED'}
        obj = _capture([o for o in bpy.data.objects if o not in before])
        data = pointnpr.read(path)
        A = data.attributes
        positions = np.asarray(data.positions) - np.asarray(obj["pointnpr_origin"])
        assert np.allclose(sync.read_positions(obj), positions, atol=1e-6)
        if NATIVE:
            assert obj.type == 'POINTCLOUD'
            _assert_native_attributes(obj.data, data, degree)
        else:
            assert obj.type == 'MESH'
            mesh = obj.data
            assert len(mesh.vertices) == data.num_points == 64
            assert np.allclose(_values(mesh, "opacity", "value", 1)[:, 0], A["opacity"])
            assert np.allclose(_values(mesh, "scale", "vector", 3), A["scales"])
            rotation = mesh.attributes["rotation"]
            prop = "value" if rotation.data_type == 'QUATERNION' else "color"
            assert np.allclose(_values(mesh, "rotation", prop, 4), A["rotations"], atol=1e-6)
            K = (degree + 1) ** 2
            assert "sh_%d" % (K - 1) in mesh.attributes and "sh_%d" % K not in mesh.attributes
            assert np.allclose(_values(mesh, "sh_1", "vector", 3), A["sh"].reshape(64, K, 3)[:, 1])
        back = splats.read(obj)
        assert back["sh_degree"] == degree and np.allclose(back["sh"], A["sh"])
        assert np.allclose(back["opacity"], A["opacity"]) and np.allclose(back["scales"], A["scales"])
        assert obj.data["pointnpr_antialiased"] == 0 and back["antialiased"] is False


def test_an_import_cancelled_after_the_capture_is_made_leaves_the_scene_as_it_was(scene):
    snapshot = lambda: [sorted(c.name for c in blocks) for blocks in (  # noqa: E731
        bpy.data.objects, bpy.data.meshes, bpy.data.pointclouds, bpy.data.collections)]
    before = snapshot()
    stages = []

    def cancelled():  # at the last step, with the object made
        return bool(stages) and stages[-1] == "adding to the scene"

    with pytest.raises(importer.ImportCancelled):
        importer.import_point_cloud(bpy.context, PLAYBOT, cancelled=cancelled,
                                    progress=lambda done, total, stage: stages.append(stage))
    assert stages[-1] == "adding to the scene"
    assert snapshot() == before


def _look_at_capture(obj):
    """A camera on the capture's side (its up is +y in its file)."""
    corners = np.array([obj.matrix_world @ mathutils.Vector(c) for c in obj.bound_box])
    centre = corners.mean(axis=0)
    offset = np.array([1.0, -1.4, -3.6])
    cam = helpers.add_camera(location=tuple(centre + offset))
    forward = -offset / np.linalg.norm(offset)
    right = np.cross(forward, (0.0, 1.0, 0.0))
    right /= np.linalg.norm(right)
    basis = np.column_stack([right, np.cross(right, forward), -forward])
    cam.rotation_euler = mathutils.Matrix(basis.tolist()).to_euler()


def _import_playbot():
    scene = helpers.reset_scene()
    scene.render.resolution_x, scene.render.resolution_y = 160, 120
    scene.render.film_transparent = True
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=PLAYBOT) == {'FINISHED'}
    obj = next(o for o in bpy.data.objects if o.type in ('MESH', 'POINTCLOUD'))
    assert obj.type == ('POINTCLOUD' if NATIVE else 'MESH')
    _look_at_capture(obj)
    return obj


def test_the_point_cloud_renders_what_the_mesh_of_the_same_capture_renders(tmp_path):
    obj = _import_playbot()
    coll = obj.users_collection[0]
    gaussians = nodes.new_style("Splats", mark="gaussians")
    weighted = nodes.new_style("Points")  # sized by the footprints, drawn by opacity
    node = nodes.mark_node(weighted)
    setattr(node, helpers.pid("size_mode"), "splat")
    setattr(node, helpers.pid("opacity_draws"), True)
    brushes = nodes.new_style("Brushes", mark="brush_splats")  # sized by the footprints, weighed by opacity
    node = nodes.mark_node(brushes)
    setattr(node, helpers.pid("size_mode"), "splat")
    setattr(node, helpers.pid("opacity_weight"), True)
    styles = (gaussians, weighted, brushes)
    renders = []
    for style in styles:
        coll.pointnpr_style = style
        renders.append(helpers.render_pixels(tmp_path, "%s.png" % style.name)[0])
    assert all((r[..., 3] > 0.5).mean() > 0.01 for r in renders)
    # The mesh a Blender without splat point clouds gets (importer.create_point_mesh, splats.write)
    # in its place: the same pixels.
    data = pointnpr.read(PLAYBOT)
    A = data.attributes
    mesh = importer.create_point_mesh("Mesh twin", importer.local_positions(data.positions, obj["pointnpr_origin"]),
                                      A["colors"])
    splats.write(mesh, A["opacity"], A["scales"], A["rotations"], A["sh"],
                 antialiased=bool(dict(data.metadata).get("antialiased", 0)))
    twin = bpy.data.objects.new("Mesh twin", mesh)
    coll.objects.link(twin)
    coll.objects.unlink(obj)
    for style, before in zip(styles, renders):
        coll.pointnpr_style = style
        after = helpers.render_pixels(tmp_path, "twin %s.png" % style.name)[0]
        assert np.array_equal(after, before), np.abs(after - before).max()


def test_blender_s_own_spz_import_renders_as_ours_turned_z_up(tmp_path):
    # Blender 5.3 brought its own SPZ importer with its splat point clouds.
    assert ("spz_import" in dir(bpy.ops.wm)) == NATIVE
    if not NATIVE:
        return
    scene = helpers.reset_scene()
    scene.render.resolution_x, scene.render.resolution_y = 160, 120
    scene.render.film_transparent = True
    before = set(bpy.data.objects)
    assert bpy.ops.wm.spz_import(filepath=PLAYBOT) == {'FINISHED'}
    theirs = _capture([o for o in bpy.data.objects if o not in before])
    assert theirs.type == 'POINTCLOUD' and theirs.data.type == 'GAUSSIAN_SPLAT'
    coll = helpers.new_collection("Captures")
    for c in list(theirs.users_collection):
        c.objects.unlink(theirs)
    coll.objects.link(theirs)
    coll.pointnpr_style = nodes.new_style("Splats", mark="gaussians")
    _look_at_capture(theirs)
    blender_s, _ = helpers.render_pixels(tmp_path, "theirs.png")
    coll.objects.unlink(theirs)
    before = set(bpy.data.objects)
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=PLAYBOT) == {'FINISHED'}
    ours = _capture([o for o in bpy.data.objects if o not in before])
    for c in list(ours.users_collection):
        c.objects.unlink(ours)
    coll.objects.link(ours)
    # Ours keeps the file's (3DGS PLY, y down) axes and is recentred; Blender's is z up, not recentred.
    z_up = mathutils.Matrix.Rotation(-np.pi / 2, 4, 'X')
    ours.matrix_world = z_up @ mathutils.Matrix.Translation(ours["pointnpr_origin"])
    positions = (sync.read_positions(ours) + np.asarray(ours["pointnpr_origin"])) @ np.asarray(z_up.to_3x3()).T
    assert np.abs(positions - sync.read_positions(theirs)).max() < 1e-6
    ours_turned, _ = helpers.render_pixels(tmp_path, "ours.png")
    assert (blender_s[..., 3] > 0.5).mean() > 0.05
    difference = np.abs(ours_turned - blender_s).max(axis=-1)
    assert difference.max() <= 10 / 255 and (difference > 1.5 / 255).mean() < 0.001, difference.max()


def test_stipples_and_feature_strokes_draw_an_imported_capture_by_its_opacity(tmp_path):
    obj = _import_playbot()
    coll = obj.users_collection[0]
    for mark in ("stipples", "feature_strokes"):
        coll.pointnpr_style = nodes.new_style(mark, mark=mark)
        plain, _ = helpers.render_pixels(tmp_path, "%s.png" % mark)
        setattr(nodes.mark_node(coll.pointnpr_style), helpers.pid("opacity_draws"), True)
        sync.read_log.clear()
        drawn, _ = helpers.render_pixels(tmp_path, "%s by opacity.png" % mark)
        assert (obj.name, splats.SOURCE) in sync.read_log
        ink = lambda image: ((image[..., 3] > 0.5) & (image[..., :3].mean(axis=-1) < 0.5)).sum()  # noqa: E731
        assert 0 < ink(drawn) < ink(plain), (mark, ink(drawn), ink(plain))


def test_an_out_of_core_capture_is_a_proxy_mesh_like_other_scans(scene, tmp_path):
    warnings = []
    objs = importer.import_point_cloud(bpy.context, PLAYBOT, warnings=warnings,
                                       out_of_core=importer.OutOfCore(0, str(tmp_path), proxy_points=100))
    obj = _capture(objs)
    assert obj.type == 'MESH' and "pointnpr_cache" in obj and len(obj.data.vertices) <= 100
    assert obj["pointnpr_cache_points"] == pointnpr.read(PLAYBOT).num_points
    assert splats.read(obj) is None
    assert any("gaussians mark cannot draw" in w for w in warnings)


def test_the_gaussians_mark_renders_an_imported_capture(tmp_path):
    obj = _import_playbot()
    coll = obj.users_collection[0]
    coll.pointnpr_style = nodes.new_style("Splats", mark="gaussians")
    sync.read_log.clear()
    splat, _ = helpers.render_pixels(tmp_path, "gaussians.png")
    assert (obj.name, "gaussians") in sync.read_log
    covered = splat[..., 3] > 0.5
    assert 0.05 < covered.mean() < 0.9, covered.mean()
    # Floaters: a keyframeable threshold reaches the render.
    node = nodes.mark_node(coll.pointnpr_style)
    setattr(node, helpers.pid("min_opacity"), 0.9)
    fewer, _ = helpers.render_pixels(tmp_path, "fewer.png")
    assert (fewer[..., 3] > 0.5).mean() < covered.mean()
    node.keyframe_insert(helpers.pid("min_opacity"), frame=1)
    # The Points mark draws the same object's centres.
    coll.pointnpr_style = nodes.new_style("Points")
    points, _ = helpers.render_pixels(tmp_path, "points.png")
    assert (points[..., 3] > 0.5).mean() > 0.01
    assert np.abs(points - splat).mean() > 0.01
    # A points style sized by the splats' footprints and drawn with their
    # opacity as chance reads the splats too.
    node = nodes.mark_node(coll.pointnpr_style)
    setattr(node, helpers.pid("size_mode"), "splat")
    setattr(node, helpers.pid("opacity_draws"), True)
    sync.read_log.clear()
    sized, _ = helpers.render_pixels(tmp_path, "sized.png")
    assert (obj.name, splats.SOURCE) in sync.read_log
    assert (sized[..., 3] > 0.5).mean() > 0.01
    assert np.abs(sized - points).mean() > 0.01


def test_blender_5_3_splat_attributes_are_read_as_splats(tmp_path):
    # Blender 5.3's GAUSSIAN_SPLAT point clouds carry "rotation", "scale",
    # "radiance:base" (DC + opacity) and "radiance:sh_N"; built here on a
    # mesh (the reader looks at attributes, whatever holds them), with
    # FLOAT_COLOR standing in for FLOAT4 where this Blender lacks it.
    data = pointnpr.read(os.path.join(SPLATS, "synthetic_v3.spz"))
    A = data.attributes
    n = data.num_points
    mesh = bpy.data.meshes.new("Blender splats")
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", np.asarray(data.positions, np.float32).ravel())
    sh = A["sh"].reshape(n, 16, 3)
    try:
        base = mesh.attributes.new("radiance:base", 'FLOAT4', 'POINT')
        prop = "vector"
    except TypeError:
        base = mesh.attributes.new("radiance:base", 'FLOAT_COLOR', 'POINT')
        prop = "color"
    base.data.foreach_set(prop, np.column_stack([sh[:, 0], A["opacity"]]).astype(np.float32).ravel())
    mesh.attributes.new("scale", 'FLOAT_VECTOR', 'POINT').data.foreach_set("vector", A["scales"].ravel())
    try:
        rot, prop = mesh.attributes.new("rotation", 'QUATERNION', 'POINT'), "value"
    except TypeError:
        rot, prop = mesh.attributes.new("rotation", 'FLOAT_COLOR', 'POINT'), "color"
    rot.data.foreach_set(prop, A["rotations"].ravel())
    for k in range(1, 16):
        mesh.attributes.new("radiance:sh_%d" % (k - 1), 'FLOAT_VECTOR', 'POINT').data.foreach_set(
            "vector", np.ascontiguousarray(sh[:, k]).ravel())
    obj = bpy.data.objects.new("Blender splats", mesh)
    bpy.context.scene.collection.objects.link(obj)
    back = splats.read(obj)
    assert back["sh_degree"] == 3
    assert np.allclose(back["sh"], A["sh"]) and np.allclose(back["opacity"], A["opacity"])
    assert np.allclose(back["scales"], A["scales"]) and np.allclose(back["rotations"], A["rotations"], atol=1e-6)
