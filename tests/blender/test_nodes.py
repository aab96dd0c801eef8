import math

import bpy
import pointnpr
import pytest
from pointnpr import presets
from pointnpr.blender import conditions, nodes

import helpers


def _schemas():
    return pointnpr.schemas()


def _node_class_for(schema):
    if schema["kind"] == "stage":
        return nodes.find_node_class(nodes.ROLE_INPAINT, "inpaint") if schema["id"] == "inpaint" else None
    role = nodes.ROLE_MARK if schema["kind"] == "mark" else nodes.ROLE_FILTER
    return nodes.find_node_class(role, schema["id"])


def _node_schemas():
    return [s for s in _schemas() if s["id"] != "composite"]


def test_every_mark_stage_and_filter_has_a_node():
    by_kind = {}
    for s in _schemas():
        by_kind.setdefault(s["kind"], set()).add(s["id"])
    assert {"points", "hatching"} <= by_kind["mark"]
    assert by_kind["stage"] == {"inpaint", "composite"}
    assert "rasterize" not in {s["id"] for s in _schemas()}
    assert by_kind["filter"], "the core registers no filter"
    for schema in _node_schemas():
        cls = _node_class_for(schema)
        assert cls is not None, schema["id"]
        assert cls.bl_label == schema["label"]
        assert cls.is_registered
    assert nodes.find_node_class(nodes.ROLE_OUTPUT) is not None
    assert nodes.find_node_class(nodes.ROLE_MARK, "points").bl_idname == "PointNPRMarkPointsNode"
    assert nodes.find_node_class(nodes.ROLE_MARK, "hatching").bl_idname == "PointNPRMarkHatchingNode"


def test_node_idnames_are_unique_and_the_former_hatching_filter_id_finds_pencil_hatching():
    assert "hatching" not in {s["id"] for s in _schemas() if s["kind"] == "filter"}
    filt = nodes.find_node_class(nodes.ROLE_FILTER, "pencil_hatching")
    mark = nodes.find_node_class(nodes.ROLE_MARK, "hatching")
    assert filt is not None and mark is not None and filt is not mark
    assert filt.pointnpr_role == nodes.ROLE_FILTER and mark.pointnpr_role == nodes.ROLE_MARK
    assert filt.bl_idname == "PointNPRFilterPencilHatchingNode"
    # Files saved before the rename have nodes of the former class: it stays
    # registered (versioning replaces them) and names the current one.
    former = bpy.types.Node.bl_rna_get_subclass_py("PointNPRFilterHatchingNode")
    assert former is not None and former.pointnpr_current_class is filt
    assert nodes.find_node_class(nodes.ROLE_FILTER, "hatching") is filt
    idnames = [c.bl_idname for c in nodes.node_classes()]
    assert len(idnames) == len(set(idnames)), idnames
    for cls in nodes.node_classes():
        assert bpy.types.Node.bl_rna_get_subclass_py(cls.bl_idname) is cls


def test_add_menu_has_a_marks_category_and_no_legacy_node():
    cats = {label: idnames for _id, label, idnames in nodes.node_categories()}
    marks = [s["id"] for s in _schemas() if s["kind"] == "mark"]
    assert cats["Marks"] == [nodes.find_node_class(nodes.ROLE_MARK, m).bl_idname for m in marks]
    assert "PointNPRFilterPencilHatchingNode" in cats["Filters"]
    assert not any(i.startswith("PointNPRMark") for i in cats["Filters"] + cats["Stages"])
    offered = {i for idnames in cats.values() for i in idnames}
    # The legacy Rasterize node, and the node of a filter's former id, stay
    # registered (old files) but are not offered.
    assert nodes.LEGACY_RASTERIZE_IDNAME not in offered and "PointNPRFilterHatchingNode" not in offered
    assert nodes.find_node_class(nodes.ROLE_RASTERIZE, "rasterize").is_registered
    assert offered == {c.bl_idname for c in nodes.node_classes()} - {nodes.LEGACY_RASTERIZE_IDNAME,
                                                                      "PointNPRFilterHatchingNode"}


def test_legacy_rasterize_node_has_the_old_parameters_and_defaults():
    legacy = nodes.find_node_class(nodes.ROLE_RASTERIZE, "rasterize")
    points = pointnpr.schema("points", kind="mark")
    names = [p["name"] for p, _pid in legacy.pointnpr_params]
    assert names == [p["name"] for p in points["params"] if p["name"] not in ("rasterizer", "gl_method")]
    props = legacy.bl_rna.properties
    assert props["color_source"].default == "rgb"
    # Stored enum indices of old files: the first four items are unchanged.
    assert [i.identifier for i in props["color_source"].enum_items][:4] == \
        ["rgb", "intensity", "classification", "constant"]


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
    for schema in _node_schemas():
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
    # The legacy scene-wide rasterizer stays registered (old files keep it;
    # versioning moves it into their Points nodes) but is not drawn.
    assert [i.identifier for i in props["rasterizer"].enum_items] == ["compute", "gl_points"]
    import inspect
    from pointnpr.blender import ui
    assert '"rasterizer"' not in inspect.getsource(ui.RENDER_PT_pointnpr.draw)
    points = pointnpr.schema("points", kind="mark")
    rasterizer = next(p for p in points["params"] if p["name"] == "rasterizer")
    assert rasterizer["items"] == ["gl", "native", "auto"] and rasterizer["default"] == "auto"
    # Its former values are the mark's rasterizer gl with that gl_method.
    assert {f["name"]: f["also"] for f in rasterizer["former_items"]} == \
        {"compute": ("gl_method", "compute"), "gl_points": ("gl_method", "gl_points")}


def test_new_style_chain_and_defaults(scene):
    tree = nodes.new_style("S")
    chain = nodes.style_chain(tree)
    assert [n.pointnpr_role for n in chain] == [nodes.ROLE_MARK]
    assert chain[0].bl_idname == "PointNPRMarkPointsNode" and chain[0].name == "Points"
    assert nodes.mark_node(tree) == chain[0]
    desc = nodes.read_style(tree, 1.0)
    assert desc["filters"] == [] and desc["inpaint"] is None and desc["warnings"] == []
    mark_id, values = desc["mark"]
    assert mark_id == "points"
    points_schema = pointnpr.schema("points", kind="mark")
    assert set(values) == {p["name"] for p in points_schema["params"]}
    assert values["color_source"] == "auto" and values["rasterizer"] == "auto"
    # The description is accepted by the core, as the points mark.
    style = nodes.make_core_style(desc)
    assert style.mark[0] == "points"
    assert style.mark[1]["color_source"] == "auto"


def test_chain_follows_links_not_creation_order(scene):
    tree = nodes.new_style("Order")
    filters = [s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"]
    a = nodes.append_node(tree, nodes.ROLE_FILTER, filters[0], name="A")
    b = nodes.append_node(tree, nodes.ROLE_FILTER, filters[-1], name="B")
    assert [n.name for n in nodes.style_chain(tree)] == ["Points", "A", "B"]
    # Relink Points -> B -> A -> Output.
    out = nodes.find_output_node(tree)
    rast = tree.nodes["Points"]
    for link in list(tree.links):
        tree.links.remove(link)
    tree.links.new(rast.outputs[0], b.inputs[0])
    tree.links.new(b.outputs[0], a.inputs[0])
    tree.links.new(a.outputs[0], out.inputs[0])
    assert [n.name for n in nodes.style_chain(tree)] == ["Points", "B", "A"]
    desc = nodes.read_style(tree, 1.0)
    assert [f[0] for f in desc["filters"]] == [filters[-1], filters[0]]
    # A muted node is skipped.
    b.mute = True
    assert [f[0] for f in nodes.read_style(tree, 1.0)["filters"]] == [filters[0]]
    # Unlinked output: no mark -> warning, the default points mark.
    for link in list(out.inputs[0].links):
        tree.links.remove(link)
    desc = nodes.read_style(tree, 1.0)
    assert desc["warnings"] and desc["filters"] == [] and desc["mark"] == ("points", {})
    assert "no mark node" in desc["warnings"][0]
    assert nodes.make_core_style(desc).mark[0] == "points"


def test_animation_is_evaluated_by_node_name(scene):
    tree = nodes.new_style("Anim")
    rast = tree.nodes["Points"]
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
    for fc in helpers.fcurves(tree):
        for kp in fc.keyframe_points:
            kp.interpolation = 'LINEAR'
    # The static value is whatever was set last; read_style must not use it.
    rast.point_size = 5.0
    d1 = nodes.read_style(tree, 1.0)["mark"][1]
    d6 = nodes.read_style(tree, 6.0)["mark"][1]
    d11 = nodes.read_style(tree, 11.0)["mark"][1]
    d50 = nodes.read_style(tree, 50.0)["mark"][1]
    assert math.isclose(d1["point_size"], 2.0, abs_tol=1e-4)
    assert math.isclose(d6["point_size"], 11.0, abs_tol=1e-4)
    assert math.isclose(d11["point_size"], 20.0, abs_tol=1e-4)
    assert math.isclose(d6["color"][1], 0.25, abs_tol=1e-4)
    assert d1["color_source"] == "rgb" and d11["color_source"] == "constant"
    assert d50["point_size"] == 20.0
    # Renaming the node keeps its animation (paths are re-keyed by name).
    rast.name = "Renamed"
    assert any('nodes["Renamed"]' in fc.data_path for fc in helpers.fcurves(tree))
    assert math.isclose(nodes.read_style(tree, 6.0)["mark"][1]["point_size"], 11.0, abs_tol=1e-4)


def test_animation_clamped_to_hard_range(scene):
    tree = nodes.new_style("Clamp")
    rast = tree.nodes["Points"]
    rast.point_size = 30.0
    rast.keyframe_insert("point_size", frame=1)
    rast.point_size = 32.0
    rast.keyframe_insert("point_size", frame=2)
    fc = helpers.fcurves(tree)[0]
    fc.extrapolation = 'LINEAR'
    for kp in fc.keyframe_points:
        kp.interpolation = 'LINEAR'
    hi = pointnpr.schema("points", kind="mark")["params"]
    hi = next(p for p in hi if p["name"] == "point_size")["max"]
    assert fc.evaluate(10.0) > hi
    assert nodes.read_style(tree, 10.0)["mark"][1]["point_size"] == hi


def test_style_operators(scene):
    coll = helpers.new_collection("OpColl")
    layer = bpy.context.view_layer.layer_collection.children["OpColl"]
    bpy.context.view_layer.active_layer_collection = layer
    assert bpy.ops.pointnpr.new_style(target='COLLECTION') == {'FINISHED'}
    tree = coll.pointnpr_style
    assert nodes.is_style_tree(tree)
    assert [n.pointnpr_role for n in nodes.style_chain(tree)] == [nodes.ROLE_MARK]
    assert bpy.ops.pointnpr.new_style(target='SCENE') == {'FINISHED'}
    assert nodes.is_style_tree(scene.pointnpr_default_style)
    assert scene.pointnpr_default_style != tree
    filters = [s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"]
    for step in filters + ["inpaint"]:
        assert bpy.ops.pointnpr.add_step(tree=tree.name, step=step) == {'FINISHED'}
    chain = nodes.style_chain(tree)
    assert [n.pointnpr_schema_id for n in chain] == ["points"] + filters + ["inpaint"]
    assert [n.pointnpr_role for n in chain[1:-1]] == [nodes.ROLE_FILTER] * len(filters)
    # Removing a middle step relinks its neighbours.
    middle = chain[1]
    assert bpy.ops.pointnpr.remove_step(tree=tree.name, node=middle.name) == {'FINISHED'}
    assert [n.pointnpr_schema_id for n in nodes.style_chain(tree)] == \
        ["points"] + filters[1:] + ["inpaint"]
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


# ---------------------------------------------------------------------------
# "when": parameters that apply only for some values of another parameter

def test_when_rule():
    when = {"param": "color_source", "values": ["constant"]}
    assert nodes.when_holds(None, "anything")
    assert nodes.when_holds(when, "constant")
    assert not nodes.when_holds(when, "rgb")
    assert not nodes.when_holds(when, None)
    on = {"param": "enabled", "values": ["true"]}
    assert nodes.when_holds(on, True) and nodes.when_holds(on, "true")
    assert not nodes.when_holds(on, False) and not nodes.when_holds(on, "false")


def _other_values(param):
    """All values a controlling (enum, bool or number) parameter can take,
    as the "when" conditions spell them."""
    if param["type"] == "bool":
        return ["true", "false"]
    if param["type"] in ("float", "int"):
        return ["zero", "nonzero"]
    assert param["type"] == "enum", param
    return list(param["items"])


def _set_when_value(node, param, value):
    pid = nodes.property_identifier(param["name"])
    if param["type"] in ("float", "int"):
        assert param["min"] <= 0 < param["max"], param  # both states reachable
        # The schema's range is given as floats; an int property takes an int.
        setattr(node, pid, type(param["default"])(param["max"] if value == "nonzero" else 0))
    else:
        setattr(node, pid, (value == "true") if param["type"] == "bool" else value)


class _FakeRow:
    def __init__(self, rows):
        self.active = True
        self.props = []
        rows.append(self)

    def prop(self, data, pid, **_kw):
        self.props.append(pid)


class _FakeLayout:
    def __init__(self):
        self.rows = []

    def row(self, **_kw):
        return _FakeRow(self.rows)


def test_parameters_are_greyed_out_when_their_condition_does_not_hold(scene):
    checked = required = 0
    tree = bpy.data.node_groups.new("When", nodes.TREE_IDNAME)
    for schema in _node_schemas():
        cls = _node_class_for(schema)
        by_name = {p["name"]: p for p in schema["params"]}
        node = tree.nodes.new(cls.bl_idname)
        for param in schema["params"]:
            when = param.get("when")
            if not when:
                assert nodes.param_applies(node, param)
                continue
            alternatives = [when] + list(when.get("or", ()))
            for condition in alternatives:
                other = by_name[condition["param"]]
                assert other["type"] in ("enum", "bool", "float", "int"), (schema["id"], param["name"])
                assert set(condition["values"]) <= set(_other_values(other)), (schema["id"], param["name"])
            for i, condition in enumerate(alternatives):
                # The other alternatives made not to hold, this one's
                # parameter takes each of its values.
                for alternative in alternatives[:i] + alternatives[i + 1:]:
                    alt = by_name[alternative["param"]]
                    _set_when_value(node, alt, next(v for v in _other_values(alt) if v not in alternative["values"]))
                other = by_name[condition["param"]]
                for value in _other_values(other):
                    _set_when_value(node, other, value)
                    # A condition on a parameter that does not apply itself
                    # does not hold either (chains of conditions).
                    expected = value in condition["values"] and nodes.param_applies(node, other)
                    assert nodes.param_applies(node, param) == expected, (schema["id"], param["name"], value)
                    # The drawn row is greyed out exactly then.
                    layout = _FakeLayout()
                    nodes.draw_node_properties(node, layout)
                    pid = nodes.property_identifier(param["name"])
                    row = next(r for r in layout.rows if r.props == [pid])
                    assert row.active == expected
                    checked += 1
                for alternative in alternatives:  # back to the defaults for the next parameter
                    _set_when_value(node, by_name[alternative["param"]],
                                    conditions.when_spelling(by_name[alternative["param"]]["default"]))
            # A condition that must hold as well ("and"): with the first
            # alternative holding (the others as the defaults leave them),
            # its parameter takes each of its values.
            first = by_name[when["param"]]
            for condition in when.get("and", ()):
                _set_when_value(node, first, when["values"][0])
                other = by_name[condition["param"]]
                assert set(condition["values"]) <= set(_other_values(other)), (schema["id"], param["name"])
                for value in _other_values(other):
                    _set_when_value(node, other, value)
                    expected = (value in condition["values"] and nodes.param_applies(node, other) and
                                nodes.param_applies(node, first))
                    assert nodes.param_applies(node, param) == expected, (schema["id"], param["name"], value)
                    checked += 1
                    required += expected is False
                for p in (other, first):
                    _set_when_value(node, p, conditions.when_spelling(p["default"]))
    assert checked >= 2, "no schema parameter has a 'when' condition"
    assert required >= 1, "no 'and' condition greyed a parameter out"


def test_chained_conditions(scene):
    """hatching: pencil_image applies when pencil_set is 'image', which
    applies when pencil_quantize is on, which applies to the points' or
    X-Toon's colours."""
    node = nodes.new_style("Chain", mark="hatching").nodes["Hatching"]
    params = {p["name"]: p for p, _pid in node.pointnpr_params}
    assert params["pencil_image"]["when"] == {"param": "pencil_set", "values": ["image"]}
    assert params["pencil_set"]["when"] == {"param": "pencil_quantize", "values": ["true"]}
    node.pencil_set = "image"
    node.pencil_quantize = True
    assert not nodes.param_applies(node, params["pencil_image"])  # a constant colour
    node.coloring = "point"
    assert nodes.param_applies(node, params["pencil_image"])
    node.pencil_quantize = False
    assert not nodes.param_applies(node, params["pencil_set"])
    assert not nodes.param_applies(node, params["pencil_image"])
    node.pencil_quantize = True
    assert nodes.param_applies(node, params["pencil_image"])
    node.pencil_set = "box_12"
    assert not nodes.param_applies(node, params["pencil_image"])
    # The hatching mark's colour source matters only for point colouring.
    node.coloring = "constant"
    assert not nodes.param_applies(node, params["color_source"])
    node.coloring = "point"
    assert nodes.param_applies(node, params["color_source"])


def test_points_size_parameters_follow_size_mode(scene):
    """The rule on known parameters: the points mark's point_size applies in
    size_mode 'pixels' and 'spacing' (its least size there), world_size in
    'world'."""
    points = nodes.new_style("Sizes").nodes["Points"]
    params = {p["name"]: p for p, _pid in points.pointnpr_params}
    assert params["point_size"]["when"] == {"param": "size_mode", "values": ["pixels", "spacing"]}
    assert params["world_size"]["when"] == {"param": "size_mode", "values": ["world"]}
    points.size_mode = "pixels"
    assert nodes.param_applies(points, params["point_size"])
    assert not nodes.param_applies(points, params["world_size"])
    points.size_mode = "world"
    assert not nodes.param_applies(points, params["point_size"])
    assert nodes.param_applies(points, params["world_size"])
    points.size_mode = "spacing"
    assert nodes.param_applies(points, params["point_size"])
    assert not nodes.param_applies(points, params["world_size"])


# ---------------------------------------------------------------------------
# Presets

def _preset_mark(preset):
    if "mark" in preset:
        mark = preset["mark"]
        return (mark, {}) if isinstance(mark, str) else (mark[0], dict(mark[1]))
    return "points", dict(preset["rasterize"])


def _assert_tree_is_preset(tree, preset):
    desc = nodes.read_style(tree, 1.0)
    mark_id, mark_values = _preset_mark(preset)
    assert desc["mark"][0] == mark_id
    for name, value in mark_values.items():
        got = desc["mark"][1][name]
        assert got == pytest.approx(value) if isinstance(value, (float, tuple)) else got == value, name
    assert [f for f, _v in desc["filters"]] == [f for f, _v in preset["filters"]]
    for (fid, got), (_fid, want) in zip(desc["filters"], preset["filters"]):
        for name, value in want.items():
            assert (got[name] == pytest.approx(value)) if isinstance(value, (int, float, tuple)) and not isinstance(value, bool) else got[name] == value, (fid, name)
    assert desc["warnings"] == []
    nodes.make_core_style(desc)


@pytest.mark.parametrize("name", sorted(presets.PRESETS))
def test_style_from_every_preset(scene, name):
    tree = nodes.new_style_from_preset(name)
    assert tree.name == name
    _assert_tree_is_preset(tree, presets.PRESETS[name])


def test_style_from_preset_accepts_both_keys(scene, monkeypatch):
    monkeypatch.setitem(presets.PRESETS, "_old", {"rasterize": {"point_size": 7.0, "color_source": "intensity"},
                                                  "filters": [("cartoon", {"levels": 3})]})
    monkeypatch.setitem(presets.PRESETS, "_hatch", {"mark": ("hatching", {}), "filters": []})
    monkeypatch.setitem(presets.PRESETS, "_named", {"mark": "hatching", "filters": [("cartoon", {})]})
    for key in ("_old", "_hatch", "_named"):
        _assert_tree_is_preset(nodes.new_style_from_preset(key), presets.PRESETS[key])
    assert nodes.mark_node(bpy.data.node_groups["_old"]).bl_idname == "PointNPRMarkPointsNode"
    assert nodes.mark_node(bpy.data.node_groups["_hatch"]).bl_idname == "PointNPRMarkHatchingNode"


def test_new_style_operator_with_a_preset(scene):
    name = sorted(presets.PRESETS)[0]
    before = set(bpy.data.node_groups.keys())
    assert bpy.ops.pointnpr.new_style(target='SCENE', preset=name) == {'FINISHED'}
    tree = scene.pointnpr_default_style
    assert tree.name not in before
    _assert_tree_is_preset(tree, presets.PRESETS[name])


def test_set_mark_operator_replaces_the_mark(scene):
    tree = nodes.new_style("Swap")
    points = tree.nodes["Points"]
    points.point_size = 7.0
    nodes.append_node(tree, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    assert bpy.ops.pointnpr.set_mark(tree=tree.name, mark="hatching") == {'FINISHED'}
    chain = nodes.style_chain(tree)
    assert [n.bl_idname for n in chain] == ["PointNPRMarkHatchingNode", "PointNPRFilterCartoonNode"]
    assert "Points" not in tree.nodes
    assert bpy.ops.pointnpr.set_mark(tree=tree.name, mark="points") == {'FINISHED'}
    chain = nodes.style_chain(tree)
    assert chain[0].bl_idname == "PointNPRMarkPointsNode" and chain[1].name == "Cartoon"
    assert nodes.read_style(tree, 1.0)["warnings"] == []
    # A style whose mark was deleted gets one in front of its first step.
    tree.nodes.remove(chain[0])
    assert nodes.read_style(tree, 1.0)["warnings"]
    assert bpy.ops.pointnpr.set_mark(tree=tree.name, mark="points") == {'FINISHED'}
    assert [n.name for n in nodes.style_chain(tree)] == ["Points", "Cartoon"]
    assert nodes.read_style(tree, 1.0)["warnings"] == []


def test_replacing_a_mark_keeps_shared_values_and_their_animation(scene):
    tree = nodes.new_style("Keep")
    old = tree.nodes["Points"]
    old.point_size = 2.0
    old.keyframe_insert("point_size", frame=1)
    old.point_size = 12.0
    old.keyframe_insert("point_size", frame=11)
    old.color_source = "intensity"
    nodes.append_node(tree, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
    new = nodes.replace_mark(tree, "points")
    assert new.name == "Points" and len(tree.nodes) == 3
    assert new.color_source == "intensity"
    assert [n.name for n in nodes.style_chain(tree)] == ["Points", "Cartoon"]
    assert [fc.data_path for fc in helpers.fcurves(tree)] == ['nodes["Points"].point_size']
    assert nodes.read_style(tree, 6.0)["mark"][1]["point_size"] == pytest.approx(7.0, abs=0.6)


def test_the_style_panel_header_offers_every_preset(scene):
    from pointnpr.blender import ui

    class Recorder:
        def __init__(self):
            self.calls = []

        def menu(self, idname, **kwargs):
            self.calls.append(("menu", idname, kwargs))

        def operator(self, idname, **kwargs):
            op = type("Props", (), {})()
            self.calls.append(("operator", idname, kwargs, op))
            return op

    header = type("Panel", (), {"layout": Recorder()})()
    ui.COLLECTION_PT_pointnpr_style.draw_header_preset(header, bpy.context)
    assert header.layout.calls == [("menu", "POINTNPR_MT_style_presets", {"text": "", "icon": "PRESET"})]
    assert hasattr(bpy.types, "POINTNPR_MT_style_presets")
    menu = type("Menu", (), {"layout": Recorder()})()
    ui.POINTNPR_MT_style_presets.draw(menu, bpy.context)
    entries = [(c[1], c[2]["text"], c[3].preset, c[3].target) for c in menu.layout.calls]
    # What an entry does (the operator with a preset): test_new_style_operator_with_a_preset.
    assert entries == [("pointnpr.new_style", name, name, "COLLECTION") for name in presets.PRESETS]
