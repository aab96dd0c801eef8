import math

import bpy
import pointnpr
import pytest
from pointnpr.blender import nodes

import helpers


def _schemas():
    return pointnpr.schemas()


def _node_class_for(schema):
    if schema["id"] == "rasterize":
        return nodes.find_node_class(nodes.ROLE_RASTERIZE, "rasterize")
    if schema["id"] == "inpaint":
        return nodes.find_node_class(nodes.ROLE_INPAINT, "inpaint")
    return nodes.find_node_class(nodes.ROLE_FILTER, schema["id"])


def test_every_stage_and_filter_has_a_node():
    ids = {s["id"] for s in _schemas()}
    assert {"rasterize", "inpaint", "composite"} <= ids
    filters = [s for s in _schemas() if s["kind"] == "filter"]
    assert filters, "the core registers no filter"
    for schema in _schemas():
        if schema["id"] == "composite":
            continue
        cls = _node_class_for(schema)
        assert cls is not None, schema["id"]
        assert cls.bl_label == schema["label"]
        assert cls.is_registered
    assert nodes.find_node_class(nodes.ROLE_OUTPUT) is not None


def _check_property(rna, param):
    assert rna is not None, param["name"]
    ptype = param["type"]
    if ptype == "float":
        assert rna.type == 'FLOAT' and rna.array_length == 0
        assert math.isclose(rna.default, param["default"], rel_tol=1e-6, abs_tol=1e-6)
        assert math.isclose(rna.hard_min, param["min"], rel_tol=1e-6, abs_tol=1e-6)
        assert math.isclose(rna.hard_max, param["max"], rel_tol=1e-6, abs_tol=1e-6)
    elif ptype == "int":
        assert rna.type == 'INT'
        assert rna.default == int(param["default"])
        assert rna.hard_min == int(param["min"]) and rna.hard_max == int(param["max"])
    elif ptype == "bool":
        assert rna.type == 'BOOLEAN'
        assert rna.default == bool(param["default"])
    elif ptype == "color":
        assert rna.type == 'FLOAT' and rna.array_length == 4
        assert rna.subtype in {'COLOR', 'COLOR_GAMMA'}
        assert tuple(round(v, 5) for v in rna.default_array) == tuple(round(v, 5) for v in param["default"])
        assert rna.hard_min == 0.0 and rna.hard_max == 1.0
    elif ptype == "enum":
        assert rna.type == 'ENUM'
        assert [i.identifier for i in rna.enum_items] == list(param["items"])
        default = param["default"]
        if not isinstance(default, str):
            default = param["items"][int(default)]
        assert rna.default == default
    elif ptype == "path":
        assert rna.type == 'STRING' and rna.subtype == 'FILE_PATH'
        assert rna.default == "" and param["default"] == ""
    else:
        pytest.fail("unknown type %s" % ptype)
    if param.get("doc"):
        assert param["doc"] in rna.description


def test_node_properties_follow_schemas():
    checked = 0
    for schema in _schemas():
        if schema["id"] == "composite":
            continue
        cls = _node_class_for(schema)
        props = cls.bl_rna.properties
        assert len(cls.pointnpr_params) == len(schema["params"])
        for param in schema["params"]:
            prop = nodes.property_identifier(param["name"])
            _check_property(props.get(prop), param)
            if param.get("unit"):
                assert param["unit"] in props[prop].name or param["unit"] in props[prop].description
            checked += 1
    assert checked > 5


def test_scene_settings_follow_composite_schema():
    schema = pointnpr.schema("composite")
    props = bpy.types.Scene.bl_rna.properties["pointnpr"].fixed_type.properties
    for param in schema["params"]:
        _check_property(props.get(nodes.property_identifier(param["name"])), param)
    assert [i.identifier for i in props["rasterizer"].enum_items] == ["compute", "gl_points"]


def test_new_style_chain_and_defaults(scene):
    tree = nodes.new_style("S")
    chain = nodes.style_chain(tree)
    assert [n.pointnpr_role for n in chain] == [nodes.ROLE_RASTERIZE]
    desc = nodes.read_style(tree, 1.0)
    assert desc["filters"] == [] and desc["inpaint"] is None and desc["warnings"] == []
    rast_schema = pointnpr.schema("rasterize")
    assert set(desc["rasterize"]) == {p["name"] for p in rast_schema["params"]}
    # The description is accepted by the core.
    nodes.make_core_style(desc)


def test_chain_follows_links_not_creation_order(scene):
    tree = nodes.new_style("Order")
    filters = [s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"]
    a = nodes.append_node(tree, nodes.ROLE_FILTER, filters[0], name="A")
    b = nodes.append_node(tree, nodes.ROLE_FILTER, filters[-1], name="B")
    assert [n.name for n in nodes.style_chain(tree)] == ["Rasterize", "A", "B"]
    # Relink Rasterize -> B -> A -> Output.
    out = nodes.find_output_node(tree)
    rast = tree.nodes["Rasterize"]
    for link in list(tree.links):
        tree.links.remove(link)
    tree.links.new(rast.outputs[0], b.inputs[0])
    tree.links.new(b.outputs[0], a.inputs[0])
    tree.links.new(a.outputs[0], out.inputs[0])
    assert [n.name for n in nodes.style_chain(tree)] == ["Rasterize", "B", "A"]
    desc = nodes.read_style(tree, 1.0)
    assert [f[0] for f in desc["filters"]] == [filters[-1], filters[0]]
    # A muted node is skipped.
    b.mute = True
    assert [f[0] for f in nodes.read_style(tree, 1.0)["filters"]] == [filters[0]]
    # Unlinked output: no rasterize -> warning, defaults.
    for link in list(out.inputs[0].links):
        tree.links.remove(link)
    desc = nodes.read_style(tree, 1.0)
    assert desc["warnings"] and desc["filters"] == []


def test_animation_is_evaluated_by_node_name(scene):
    tree = nodes.new_style("Anim")
    rast = tree.nodes["Rasterize"]
    rast.point_size = 2.0
    rast.keyframe_insert("point_size", frame=1)
    rast.point_size = 20.0
    rast.keyframe_insert("point_size", frame=11)
    color = nodes.property_identifier("color")
    setattr(rast, color, (0.0, 0.0, 0.0, 1.0))
    rast.keyframe_insert(color, frame=1)
    setattr(rast, color, (1.0, 0.5, 0.25, 1.0))
    rast.keyframe_insert(color, frame=11)
    rast.color_source = "rgb"
    rast.keyframe_insert("color_source", frame=1)
    rast.color_source = "constant"
    rast.keyframe_insert("color_source", frame=11)
    for fc in tree.animation_data.action.fcurves:
        for kp in fc.keyframe_points:
            kp.interpolation = 'LINEAR'
    # The static value is whatever was set last; read_style must not use it.
    rast.point_size = 5.0
    d1 = nodes.read_style(tree, 1.0)["rasterize"]
    d6 = nodes.read_style(tree, 6.0)["rasterize"]
    d11 = nodes.read_style(tree, 11.0)["rasterize"]
    d50 = nodes.read_style(tree, 50.0)["rasterize"]
    assert math.isclose(d1["point_size"], 2.0, abs_tol=1e-4)
    assert math.isclose(d6["point_size"], 11.0, abs_tol=1e-4)
    assert math.isclose(d11["point_size"], 20.0, abs_tol=1e-4)
    assert math.isclose(d6["color"][1], 0.25, abs_tol=1e-4)
    assert d1["color_source"] == "rgb" and d11["color_source"] == "constant"
    assert d50["point_size"] == 20.0
    # Renaming the node keeps its animation (paths are re-keyed by name).
    rast.name = "Renamed"
    assert any('nodes["Renamed"]' in fc.data_path for fc in tree.animation_data.action.fcurves)
    assert math.isclose(nodes.read_style(tree, 6.0)["rasterize"]["point_size"], 11.0, abs_tol=1e-4)


def test_animation_clamped_to_hard_range(scene):
    tree = nodes.new_style("Clamp")
    rast = tree.nodes["Rasterize"]
    rast.point_size = 30.0
    rast.keyframe_insert("point_size", frame=1)
    rast.point_size = 32.0
    rast.keyframe_insert("point_size", frame=2)
    fc = tree.animation_data.action.fcurves[0]
    fc.extrapolation = 'LINEAR'
    for kp in fc.keyframe_points:
        kp.interpolation = 'LINEAR'
    hi = pointnpr.schema("rasterize")["params"]
    hi = next(p for p in hi if p["name"] == "point_size")["max"]
    assert fc.evaluate(10.0) > hi
    assert nodes.read_style(tree, 10.0)["rasterize"]["point_size"] == hi


def test_style_operators(scene):
    coll = helpers.new_collection("OpColl")
    layer = bpy.context.view_layer.layer_collection.children["OpColl"]
    bpy.context.view_layer.active_layer_collection = layer
    assert bpy.ops.pointnpr.new_style(target='COLLECTION') == {'FINISHED'}
    tree = coll.pointnpr_style
    assert nodes.is_style_tree(tree)
    assert [n.pointnpr_role for n in nodes.style_chain(tree)] == [nodes.ROLE_RASTERIZE]
    assert bpy.ops.pointnpr.new_style(target='SCENE') == {'FINISHED'}
    assert nodes.is_style_tree(scene.pointnpr_default_style)
    assert scene.pointnpr_default_style != tree
    filters = [s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"]
    for step in filters + ["inpaint"]:
        assert bpy.ops.pointnpr.add_step(tree=tree.name, step=step) == {'FINISHED'}
    chain = nodes.style_chain(tree)
    assert [n.pointnpr_schema_id for n in chain] == ["rasterize"] + filters + ["inpaint"]
    # Removing a middle step relinks its neighbours.
    middle = chain[1]
    assert bpy.ops.pointnpr.remove_step(tree=tree.name, node=middle.name) == {'FINISHED'}
    assert [n.pointnpr_schema_id for n in nodes.style_chain(tree)] == \
        ["rasterize"] + filters[1:] + ["inpaint"]
    with pytest.raises(RuntimeError):
        bpy.ops.pointnpr.add_step(tree="no such style", step=filters[0])


def test_collection_style_pointer_accepts_only_style_trees(scene):
    coll = helpers.new_collection("PollColl")
    other = bpy.data.node_groups.new("Geometry", 'GeometryNodeTree')
    assert not nodes.poll_style_tree(None, other)
    assert nodes.poll_style_tree(None, nodes.new_style("Ok"))
    # Python can bypass the UI's poll: such a tree is ignored (the parent's
    # style, here the scene default, applies).
    default = nodes.new_style("Default")
    scene.pointnpr_default_style = default
    try:
        coll.pointnpr_style = other
    except (TypeError, ValueError):
        pass
    from pointnpr.blender import sync
    assert sync.resolve_style(scene, coll) == default
