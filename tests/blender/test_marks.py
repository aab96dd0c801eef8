"""Marks other than Points, and which point attributes sync reads."""
import bpy
import numpy as np
import pointnpr
import pytest
from pointnpr.blender import nodes, sync

import helpers


def _hatching_scene():
    scene = helpers.reset_scene()
    helpers.add_camera(location=(0.0, -6.0, 6.0))
    scene.camera.rotation_euler = (0.785398, 0.0, 0.0)
    scene.world.color = (1.0, 1.0, 1.0)
    coll = helpers.new_collection("Hatched")
    # A bumpy surface, so there is shading for strokes to follow.
    pts = helpers.grid_points(2.0, 0.04, 0.0)
    pts[:, 2] = 0.4 * np.sin(2.0 * pts[:, 0]) * np.cos(2.0 * pts[:, 1])
    rng = np.random.default_rng(1)
    helpers.add_points("Surface", coll, pts, colors=rng.random((len(pts), 3)) * 0.5 + 0.25)
    tree = nodes.new_style("Hatch", mark="hatching")
    coll.pointnpr_style = tree
    return scene, tree


def test_hatching_mark_node_has_its_schema_parameters(scene):
    tree = nodes.new_style("Hatch", mark="hatching")
    node = nodes.mark_node(tree)
    assert node.bl_idname == "PointNPRMarkHatchingNode" and node.name == "Hatching"
    schema = pointnpr.schema("hatching", kind="mark")
    assert [p["name"] for p, _pid in node.pointnpr_params] == [p["name"] for p in schema["params"]]
    for param in schema["params"]:
        assert nodes.property_identifier(param["name"]) in node.bl_rna.properties
    desc = nodes.read_style(tree, 1.0)
    assert desc["mark"][0] == "hatching" and desc["warnings"] == []
    assert set(desc["mark"][1]) == {p["name"] for p in schema["params"]}
    style = nodes.make_core_style(desc)
    assert style.mark[0] == "hatching"
    # The pencil hatching filter (once of the same id) is another node.
    filt = nodes.append_node(tree, nodes.ROLE_FILTER, "pencil_hatching", name="Hatch filter")
    assert filt.bl_idname == "PointNPRFilterPencilHatchingNode"
    desc = nodes.read_style(tree, 1.0)
    assert desc["mark"][0] == "hatching" and [f for f, _v in desc["filters"]] == ["pencil_hatching"]
    nodes.make_core_style(desc)


def test_hatching_mark_renders(tmp_path):
    scene, tree = _hatching_scene()
    hatched, _ = helpers.render_pixels(tmp_path, "hatched.png")
    rgb = hatched[..., :3]
    dark = (rgb.mean(axis=2) < 0.7).mean()
    assert 0.01 < dark < 0.9, dark      # strokes on white, not empty, not filled
    # The same scene with a Points mark looks different.
    points_tree = nodes.new_style("Points")
    bpy.data.collections["Hatched"].pointnpr_style = points_tree
    points, _ = helpers.render_pixels(tmp_path, "points.png")
    assert np.abs(points[..., :3] - rgb).mean() > 0.02
    # A hatching parameter, animated or not, reaches the render.
    bpy.data.collections["Hatched"].pointnpr_style = tree
    node = nodes.mark_node(tree)
    changed = None
    for param, pid in node.pointnpr_params:
        if param["type"] == "float" and nodes.param_applies(node, param) and param["max"] > param["min"]:
            default = getattr(node, pid)
            setattr(node, pid, param["max"] if default < (param["min"] + param["max"]) / 2 else param["min"])
            other, _ = helpers.render_pixels(tmp_path, "changed_%s.png" % pid)
            setattr(node, pid, default)
            if np.abs(other[..., :3] - rgb).mean() > 0.002:
                changed = param["name"]
                break
    assert changed is not None, "no float parameter of the hatching mark changes the image"


# ---------------------------------------------------------------------------
# Which attributes are read

def _attribute_scene(style_setup):
    scene = helpers.reset_scene()
    helpers.add_camera()
    coll = helpers.new_collection("Attrs")
    pts = helpers.grid_points(1.0, 0.1, 0.0)
    obj = helpers.add_points("Obj", coll, pts, colors=np.tile([[1.0, 0.0, 0.0]], (len(pts), 1)),
                             intensity=np.linspace(0.0, 100.0, len(pts)))
    attr = obj.data.attributes.new("classification", 'INT', 'POINT')
    attr.data.foreach_set("value", np.full(len(pts), 6, dtype=np.int32))
    tree = nodes.new_style("S")
    style_setup(nodes.mark_node(tree))
    coll.pointnpr_style = tree
    return scene, tree, obj


def _reads(obj_name="Obj"):
    return sorted(a for o, a in sync.read_log if o == obj_name)


def _sync():
    sync.clear_cache()
    return sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1.0)


def _frame_warnings():
    """The warnings of a rendered frame (the core reports missing colours,
    each cause once, naming the objects)."""
    from pointnpr.blender import engine

    sync.clear_cache()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    camera = engine.make_camera(depsgraph, bpy.context.scene.camera, 64, 48)
    result, synced = engine.do_render(depsgraph, camera, 64, 48)
    return list(synced.warnings) + list(result.warnings)


def _source(node, value):
    node.color_source = value


def test_constant_colour_reads_no_colour_attribute():
    _scene, tree, _obj = _attribute_scene(lambda n: _source(n, "constant"))
    result = _sync()
    assert _reads() == [] and result.warnings == []
    assert sync.source_attributes(nodes.make_core_style(nodes.read_style(tree, 1.0))) == ()


@pytest.mark.parametrize("source,attribute", [("rgb", "colors"), ("intensity", "intensity"),
                                              ("classification", "classification")])
def test_one_colour_source_reads_only_its_attribute(source, attribute):
    _attribute_scene(lambda n: _source(n, source))
    result = _sync()
    assert _reads() == [attribute] and result.warnings == []


def test_auto_colour_reads_the_colour_attributes_present():
    _scene, tree, obj = _attribute_scene(lambda n: _source(n, "auto"))
    attrs = nodes.make_core_style(nodes.read_style(tree, 1.0)).source_attributes
    assert {"colors", "intensity", "classification"} <= set(attrs)
    # "auto" draws the first the object has: with colours, the intensity and
    # classification are not read (nor kept in the core's cloud).
    result = _sync()
    assert _reads() == ["colors"] and result.warnings == []
    cloud = next(iter(sync._cloud_cache.values())).cloud
    assert cloud.has("colors") and not cloud.has("intensity") and not cloud.has("classification")
    # Without colours the next one, the intensity, is read; an object with
    # only an intensity is fine for "auto": no warning.
    obj.data.color_attributes.remove(obj.data.color_attributes["Col"])
    _sync()
    assert _reads() == ["colors", "intensity"]
    obj.data.attributes.remove(obj.data.attributes["classification"])
    assert _frame_warnings() == []
    # With none of them, auto takes the constant colour: nothing to warn about.
    obj.data.attributes.remove(obj.data.attributes["intensity"])
    assert _frame_warnings() == []


def test_missing_attribute_is_one_warning_per_cause():
    _scene, _tree, obj = _attribute_scene(lambda n: _source(n, "rgb"))
    obj.data.color_attributes.remove(obj.data.color_attributes["Col"])
    for k in range(5):  # four more uncoloured objects in the same collection
        other = obj.copy()
        other.data = obj.data.copy()
        other.name = "Obj.%d" % k
        obj.users_collection[0].objects.link(other)
    assert _sync().warnings == []  # the sync itself does not repeat it
    warnings = _frame_warnings()
    assert warnings == ["6 objects have no colors for their style's colour source ('Obj', 'Obj.0', 'Obj.1' and 3 "
                        "more); drawn in the constant colour"], warnings


def test_auto_colour_with_an_explicit_intensity_reads_both():
    # An intensity the style uses besides "auto" colour (not a fallback) is
    # read; the classification, a fallback, is skipped when colours are there.
    style = pointnpr.Style(rasterize={"color_source": "auto"})
    assert sync.fallback_attributes(style) == ("colors", "intensity", "classification")
    assert sync.fallback_attributes(pointnpr.Style(rasterize={"color_source": "rgb"})) == ()
    _scene, _tree, obj = _attribute_scene(lambda n: _source(n, "auto"))
    sync.clear_cache()
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    attributes = ("classification", "colors", "intensity")
    cloud = sync.cloud_for(evaluated, attributes, fallbacks=("colors", "classification"))
    assert cloud.has("colors") and cloud.has("intensity") and not cloud.has("classification")
    # Another set of fallbacks is another cloud, not the cached one.
    everything = sync.cloud_for(evaluated, attributes)
    assert everything is not cloud and everything.has("classification")


def test_cloud_cache_is_keyed_on_the_attribute_set():
    _scene, tree, _obj = _attribute_scene(lambda n: _source(n, "constant"))
    node = nodes.mark_node(tree)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    sync.clear_cache()
    sync.build_scene(depsgraph, 1.0)
    assert sync.cache_stats()["uploads"] == 1
    sync.build_scene(depsgraph, 1.0)
    assert sync.cache_stats()["uploads"] == 1
    node.color_source = "rgb"           # another attribute set: another cloud
    sync.build_scene(depsgraph, 1.0, trust_cache=True)
    assert sync.cache_stats()["uploads"] == 2
    assert sync.cache_stats()["objects"] == 1     # the constant-colour one is dropped
    assert ("Obj", "colors") in sync.read_log


def test_point_index_and_normals_are_read_from_their_attributes():
    _scene, _tree, obj = _attribute_scene(lambda n: _source(n, "constant"))
    n = len(obj.data.vertices)
    assert sync.read_point_index(obj) is None and sync.read_normals(obj) is None
    attr = obj.data.attributes.new("point_index", 'INT', 'POINT')
    attr.data.foreach_set("value", np.arange(n, dtype=np.int32)[::-1].copy())
    assert list(sync.read_point_index(obj)[:3]) == [n - 1, n - 2, n - 3]
    normals = np.tile(np.array([0.0, 0.6, 0.8], dtype=np.float32), (n, 1))
    attr = obj.data.attributes.new("N", 'FLOAT_VECTOR', 'POINT')
    attr.data.foreach_set("vector", normals.ravel())
    assert np.allclose(sync.read_normals(obj), normals)
    # A mesh with faces has shading normals of its own: not read as point normals.
    mesh = bpy.data.meshes.new("Faces")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    attr = mesh.attributes.new("N", 'FLOAT_VECTOR', 'POINT')
    face_obj = bpy.data.objects.new("Faces", mesh)
    assert sync.read_normals(face_obj) is None


def test_a_style_asking_for_normals_reads_them():
    scene, tree = _hatching_scene()
    obj = bpy.data.objects["Surface"]
    attrs = set(nodes.make_core_style(nodes.read_style(tree, 1.0)).source_attributes)
    assert "normals" in attrs            # hatching follows the surface
    assert not {"colors", "intensity", "classification"} & attrs   # constant stroke colour
    n = len(obj.data.vertices)
    # ("normal" is a name Blender reserves on meshes; "N" is the other one read.)
    attr = obj.data.attributes.new("N", 'FLOAT_VECTOR', 'POINT')
    attr.data.foreach_set("vector", np.tile([0.0, 0.0, 1.0], n).astype(np.float32))
    _sync()
    assert set(_reads("Surface")) == attrs
    # Without a normal attribute the core estimates them: no warning.
    obj.data.attributes.remove(obj.data.attributes["N"])
    assert _sync().warnings == []
    # A Points style with constant colour and no shading reads none of them.
    points = nodes.new_style("Flat")
    nodes.mark_node(points).color_source = "constant"
    bpy.data.collections["Hatched"].pointnpr_style = points
    _sync()
    assert _reads("Surface") == []


def test_non_finite_points_are_skipped_with_one_warning_per_object():
    _scene, _tree, obj = _attribute_scene(lambda n: _source(n, "rgb"))
    co = np.empty(len(obj.data.vertices) * 3, np.float32)
    obj.data.vertices.foreach_get("co", co)
    co[3 * 5] = np.nan
    co[3 * 9 + 2] = np.inf
    obj.data.vertices.foreach_set("co", co)
    obj.data.update()
    n = len(obj.data.vertices)
    warnings = _frame_warnings()
    assert warnings == ["object 'Obj': 2 of %s points have non-finite coordinates and were skipped" % f"{n:,}"], \
        warnings


def _add_sun(rotation):
    data = bpy.data.lights.new("Sun", 'SUN')
    sun = bpy.data.objects.new("Sun", data)
    bpy.context.scene.collection.objects.link(sun)
    sun.rotation_euler = rotation
    return sun


def test_scene_sun_drives_the_light_of_a_scene_sun_style():
    _scene, tree, _obj = _attribute_scene(lambda n: None)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    desc = {"mark": ("hatching", {"light_space": "scene_sun", "light_azimuth": 10.0, "light_elevation": 20.0})}
    warnings = []
    sync._apply_scene_sun(desc, depsgraph, warnings, tree)
    assert desc["mark"][1]["light_azimuth"] == 10.0 and len(warnings) == 1 and "has none" in warnings[0]
    # A sun tilted 30 degrees from straight down, toward +Y: it shines from
    # azimuth 90 (its +Z axis), elevation 60.
    _add_sun((-0.5235988, 0.0, 0.0))
    depsgraph = bpy.context.evaluated_depsgraph_get()
    warnings = []
    sync._apply_scene_sun(desc, depsgraph, warnings, tree)
    assert warnings == []
    assert desc["mark"][1]["light_azimuth"] == pytest.approx(90.0, abs=1e-4)
    assert desc["mark"][1]["light_elevation"] == pytest.approx(60.0, abs=1e-4)
    # A world light is left as it is.
    world = {"mark": ("hatching", {"light_space": "world", "light_azimuth": 10.0})}
    sync._apply_scene_sun(world, depsgraph, warnings, tree)
    assert world["mark"][1]["light_azimuth"] == 10.0


def test_turning_the_sun_relights_a_hatched_render(tmp_path):
    _hatching_scene()
    node = nodes.mark_node(bpy.data.collections["Hatched"].pointnpr_style)
    node.light_space = "scene_sun"
    sun = _add_sun((0.3, 0.0, 0.0))
    first, _ = helpers.render_pixels(tmp_path, "sun_a.png")
    sun.rotation_euler = (1.2, 0.0, 2.5)
    second, _ = helpers.render_pixels(tmp_path, "sun_b.png")
    assert np.abs(first[..., :3] - second[..., :3]).mean() > 0.005
