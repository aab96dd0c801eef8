"""Files saved by older versions of the add-on: their Rasterize nodes
become Points mark nodes on load, renamed parameters, enum values and
filters take their current names, and they render as they did.

The references were rendered with the add-on from before the change:
tests/data/golden/legacy_<example>.png by tests/blender/example_renders.py,
tests/data/legacy_rasterize_anim.blend and legacy_anim_f<frame>.png by
tests/blender/make_legacy_blend.py.
"""
import os

import bpy
import numpy as np
import pytest
from pointnpr.blender import nodes, versioning

import example_renders
import helpers

ANIM_BLEND = os.path.join(helpers.REPO, "tests", "data", "legacy_rasterize_anim.blend")
ANIM_FRAMES = (1, 6, 11)
LEGACY = nodes.LEGACY_RASTERIZE_IDNAME


def _style_trees():
    return [t for t in bpy.data.node_groups if nodes.is_style_tree(t)]


def _legacy_nodes():
    return [(t.name, n.name) for t in _style_trees() for n in t.nodes if n.bl_idname == LEGACY]


@pytest.fixture
def fresh_file():
    """Leaves an emptied scene behind for the tests that follow."""
    yield
    helpers.reset_scene()


def _stored_legacy_values(path):
    """{tree name: {param: raw stored value}} of the file's Rasterize nodes,
    read from their ID properties (what the old add-on saved; a value never
    set is absent). Read through a library load so no handler runs."""
    helpers.reset_scene()   # no tree of the same name: names stay as in the file
    with bpy.data.libraries.load(path, link=False) as (src, dst):
        dst.node_groups = list(src.node_groups)
    stored = {}
    for tree in dst.node_groups:
        for node in tree.nodes:
            if node.bl_idname == LEGACY:
                stored[tree.name] = {k: node[k] for k in node.keys()}
                stored[tree.name]["_name"] = node.name
        bpy.data.node_groups.remove(tree)
    return stored


@pytest.mark.parametrize("name", ["urban_lidarhd", "warsaw_styles", "lion_benchmark"])
def test_example_file_is_migrated_and_renders_as_before(fresh_file, tmp_path, name):
    path = example_renders.blend_path(name)
    # The committed file really has legacy nodes, with color_source stored.
    stored = _stored_legacy_values(path)
    assert stored and all("color_source" in v and v["_name"] == "Rasterize" for v in stored.values())
    scene = example_renders.open_example(name)
    assert _legacy_nodes() == []
    trees = _style_trees()
    assert trees
    for tree in trees:
        mark = nodes.mark_node(tree)
        assert mark is not None, tree.name
        assert mark.bl_idname == "PointNPRMarkPointsNode"
        assert mark.name == "Rasterize"        # the old name, for its F-Curves
        # The scene's compute: the mark's gl with that method.
        assert scene.pointnpr.rasterizer == "compute"
        assert (mark.rasterizer, mark.gl_method) == ("gl", "compute")
        # make_examples.py set color_source on every Rasterize node.
        assert mark.color_source in ("rgb", "constant")
        assert mark.is_property_set("color_source")
        desc = nodes.read_style(tree, 1.0)
        assert desc["warnings"] == [] and desc["mark"][0] == "points"
    out = example_renders.render_open_example(name, str(tmp_path / (name + ".png")))
    code, output = example_renders.idiff(example_renders.golden_path(name), out, str(tmp_path / "diff.png"))
    assert code == 0, "%s differs from its legacy render:\n%s" % (name, output)


def test_migration_keeps_values_links_and_location(fresh_file):
    stored = _stored_legacy_values(ANIM_BLEND)
    assert set(stored) == {"Animated", "Constant"}
    # The old add-on never stored color_source for "Animated" (left at its
    # default "rgb"); "Constant" has index 3 ("constant").
    assert "color_source" not in stored["Animated"]
    assert stored["Constant"]["color_source"] == 3
    bpy.ops.wm.open_mainfile(filepath=ANIM_BLEND, load_ui=False)
    scene = bpy.context.scene
    assert _legacy_nodes() == []
    assert scene.pointnpr.rasterizer == "gl_points"
    animated = bpy.data.node_groups["Animated"]
    constant = bpy.data.node_groups["Constant"]
    a = animated.nodes["Rasterize"]
    c = constant.nodes["Rasterize"]
    for node in (a, c):
        assert node.bl_idname == "PointNPRMarkPointsNode"
        assert (node.rasterizer, node.gl_method) == ("gl", "gl_points")  # was the scene's setting
        assert tuple(node.location) == (-250.0, 0.0)
    # Explicitly "rgb" (the new default is "auto"), not left unset.
    assert a.color_source == "rgb" and a.is_property_set("color_source")
    assert c.color_source == "constant"
    assert c.point_size == pytest.approx(5.0)
    # The chain is intact: mark -> Cartoon -> Output.
    assert [n.name for n in nodes.style_chain(constant)] == ["Rasterize", "Cartoon"]
    assert [n.name for n in nodes.style_chain(animated)] == ["Rasterize"]
    assert nodes.read_style(constant, 1.0)["warnings"] == []
    # Loading again is a no-op (nothing left to migrate).
    assert versioning.migrate_legacy_nodes() == 0


def test_animation_keyed_on_the_rasterize_node_survives(fresh_file, tmp_path):
    bpy.ops.wm.open_mainfile(filepath=ANIM_BLEND, load_ui=False)
    animated = bpy.data.node_groups["Animated"]
    constant = bpy.data.node_groups["Constant"]
    paths = sorted(fc.data_path for fc in helpers.fcurves(animated))
    assert paths == ['nodes["Rasterize"].point_size']
    paths = {fc.data_path for fc in helpers.fcurves(constant)}
    assert paths == {'nodes["Rasterize"].%s' % nodes.property_identifier("color")}
    # point_size 2 -> 9 linear over frames 1..11; colour red -> blue.
    for frame, size in ((1, 2.0), (6, 5.5), (11, 9.0)):
        assert nodes.read_style(animated, frame)["mark"][1]["point_size"] == pytest.approx(size, abs=1e-4)
    assert nodes.read_style(constant, 6)["mark"][1]["color"][:3] == pytest.approx((0.5, 0.0, 0.5), abs=1e-4)
    # And the renders match the old add-on's, frame by frame.
    scene = bpy.context.scene
    scene.render.resolution_percentage = 100
    for frame in ANIM_FRAMES:
        scene.frame_set(frame)
        out = helpers.render_to_png(str(tmp_path / ("f%d.png" % frame)))
        golden = os.path.join(example_renders.GOLDEN, "legacy_anim_f%d.png" % frame)
        code, output = example_renders.idiff(golden, out, str(tmp_path / "diff.png"))
        assert code == 0, "frame %d differs from the legacy render:\n%s" % (frame, output)


def test_migration_when_the_addon_is_enabled_on_an_open_file(fresh_file):
    """A file opened before the add-on was enabled (blender -b old.blend
    --python enable_addon.py) is migrated by register()."""
    import pointnpr

    pointnpr.unregister()
    try:
        # Without the add-on the Rasterize nodes load as undefined nodes
        # that keep their idname and stored values.
        bpy.ops.wm.open_mainfile(filepath=ANIM_BLEND, load_ui=False)
        tree = bpy.data.node_groups["Constant"]
        assert "Rasterize" in tree.nodes and not nodes.is_style_tree(tree)
    finally:
        pointnpr.register()
    tree = bpy.data.node_groups["Constant"]
    node = tree.nodes["Rasterize"]
    assert node.bl_idname == "PointNPRMarkPointsNode"
    assert node.color_source == "constant" and (node.rasterizer, node.gl_method) == ("gl", "gl_points")
    assert [n.name for n in nodes.style_chain(tree)] == ["Rasterize", "Cartoon"]


def test_migrated_node_name_and_drivers(fresh_file):
    """A Rasterize node made now (the class is still registered) with an
    odd name, a driver and a frame parent migrates with all of them."""
    helpers.reset_scene()
    tree = bpy.data.node_groups.new("Odd", nodes.TREE_IDNAME)
    frame = tree.nodes.new("NodeFrame")
    old = tree.nodes.new(LEGACY)
    old.name = 'Ras "terize"'
    old.parent = frame
    old.location = (12.0, 34.0)
    old.point_size = 4.0
    out = tree.nodes.new(nodes.OUTPUT_IDNAME)
    out.name = "Output"
    tree.links.new(old.outputs[0], out.inputs[0])
    driver = old.driver_add("point_size").driver
    driver.expression = "3.0"
    old.keyframe_insert(nodes.property_identifier("color"), frame=1)
    bpy.context.scene.pointnpr.rasterizer = "gl_points"
    bpy.context.scene.pointnpr_default_style = tree
    assert versioning.migrate_legacy_nodes() == 1
    new = tree.nodes['Ras "terize"']
    assert new.bl_idname == "PointNPRMarkPointsNode"
    assert new.parent == frame and tuple(new.location) == (12.0, 34.0)
    assert (new.rasterizer, new.gl_method) == ("gl", "gl_points")
    assert new.color_source == "rgb"
    assert [d.data_path for d in tree.animation_data.drivers] == ['nodes["Ras \\"terize\\""].point_size']
    assert {fc.data_path for fc in helpers.fcurves(tree)} == \
        {'nodes["Ras \\"terize\\""].%s' % nodes.property_identifier("color")}
    assert nodes.style_chain(tree) == [new]


def test_a_value_saved_under_a_former_parameter_name_moves_to_the_current_one(fresh_file):
    """The stipples mark's `implementation` is `rasterizer` now (the name
    every mark with two backends uses): a file saved before keeps the value
    and its animation; a tree that is not migrated (a library's) reads them
    as they are."""
    tree = nodes.new_style("Saved Stipples", mark="stipples")
    node = nodes.mark_node(tree)
    assert node.rasterizer == "auto"
    node["implementation"] = 1  # what the add-on stored before: the enum's index ("native")
    assert nodes.read_style(tree, 1)["mark"][1]["rasterizer"] == "native"
    # A curve keyed on the old name (made on another property, then moved there).
    node.dot_size = 1.0
    node.keyframe_insert("dot_size", frame=1)
    node.dot_size = 2.0
    node.keyframe_insert("dot_size", frame=9)
    (curve,) = helpers.fcurves(tree)
    prefix = 'nodes["%s"].' % node.name
    curve.data_path = prefix + "implementation"
    assert nodes.read_style(tree, 9)["mark"][1]["rasterizer"] == "auto"  # index 2 at frame 9
    assert versioning.migrate_former_names(tree) == 2
    assert "implementation" not in node.keys() and node.rasterizer == "native"
    assert [fc.data_path for fc in helpers.fcurves(tree)] == [prefix + "rasterizer"]
    assert nodes.read_style(tree, 1)["mark"][1]["rasterizer"] == "native"
    assert nodes.read_style(tree, 9)["mark"][1]["rasterizer"] == "auto"
    assert versioning.migrate_former_names(tree) == 0  # once


def test_a_parameter_added_later_keeps_older_files_as_they_rendered(fresh_file, tmp_path):
    """The brush splats' `shading` came after files were saved without it:
    a node made before it (no record of the parameters it knew) renders
    unlit as it did (`none`) when its file opens; a node made now takes the
    default (`auto`) and keeps it; a value set by hand is never replaced."""
    old_tree = nodes.new_style("Old Brushes", mark="brush_splats")
    del nodes.mark_node(old_tree)[nodes.KNOWN_PARAMS_KEY]  # as a node of an earlier add-on version
    set_tree = nodes.new_style("Set Brushes", mark="brush_splats")
    set_node = nodes.mark_node(set_tree)
    set_node.shading = "diffuse"
    del set_node[nodes.KNOWN_PARAMS_KEY]
    new_tree = nodes.new_style("New Brushes", mark="brush_splats")
    for tree in (old_tree, set_tree, new_tree):
        tree.use_fake_user = True
    assert nodes.mark_node(old_tree).shading == "auto"
    path = str(tmp_path / "brushes.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)  # the load handler migrates
    old = nodes.mark_node(bpy.data.node_groups["Old Brushes"])
    assert old.shading == "none"
    assert nodes.read_style(old.id_data, 1)["mark"][1]["shading"] == "none"
    assert nodes.mark_node(bpy.data.node_groups["Set Brushes"]).shading == "diffuse"
    assert nodes.mark_node(bpy.data.node_groups["New Brushes"]).shading == "auto"
    # Once: every node now records the parameters it knows.
    assert sum(versioning.migrate_added_params(t) for t in bpy.data.node_groups) == 0


def test_a_changed_default_keeps_older_files_as_they_rendered(fresh_file, tmp_path):
    """The hatching mark's light came from the world (Z up), with the scan's
    own normal orientation, until its defaults became a key light with the
    camera and normals turned toward it: a node made before (it recorded
    the parameters by name alone) keeps `world` and one-sided light; one
    whose light was set by hand keeps it; a node made now keeps the new
    defaults."""
    old_tree = nodes.new_style("Old Hatching", mark="hatching")
    old_node = nodes.mark_node(old_tree)
    old_node[nodes.KNOWN_PARAMS_KEY] = " ".join(p["name"] for p, _pid in old_node.pointnpr_params)
    set_tree = nodes.new_style("Set Hatching", mark="hatching")
    set_node = nodes.mark_node(set_tree)
    set_node.light_space = "camera"
    set_node[nodes.KNOWN_PARAMS_KEY] = old_node[nodes.KNOWN_PARAMS_KEY]
    new_tree = nodes.new_style("New Hatching", mark="hatching")
    for tree in (old_tree, set_tree, new_tree):
        tree.use_fake_user = True
    path = str(tmp_path / "hatching.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)  # the load handler migrates
    old = nodes.mark_node(bpy.data.node_groups["Old Hatching"])
    assert (old.light_space, old.two_sided) == ("world", False)
    assert nodes.read_style(old.id_data, 1)["mark"][1]["light_space"] == "world"
    kept = nodes.mark_node(bpy.data.node_groups["Set Hatching"])
    assert (kept.light_space, kept.two_sided) == ("camera", False)
    new = nodes.mark_node(bpy.data.node_groups["New Hatching"])
    assert (new.light_space, new.two_sided) == ("camera", True)
    assert sum(versioning.migrate_added_params(t) for t in bpy.data.node_groups) == 0


def _store_raw(node, pid, value):
    """Stores ``value`` for property ``pid`` as Blender saves it (an enum:
    its index), past the property's own checks, as an older add-on did."""
    system = getattr(node, "bl_system_properties_get", None)
    (system(do_create=True) if system is not None else node)[pid] = value


def _as_made_before_items_changed(node):
    """The record of known parameters that a node made by the add-on before
    the rasterizer items changed has: names alone, no gl_method."""
    node[nodes.KNOWN_PARAMS_KEY] = " ".join(p["name"] for p, _pid in node.pointnpr_params if p["name"] != "gl_method")


# Tree name: (mark, index saved into the items of the time, what it reads as now).
OLD_RASTERIZERS = {
    "Points compute": ("points", 0, ("gl", "compute")),
    "Points gl_points": ("points", 1, ("gl", "gl_points")),
    "Points native": ("points", 2, ("native", "compute")),
    "Points auto": ("points", 3, ("auto", "compute")),
    "Gaussians native": ("gaussians", 0, ("native",)),
    "Gaussians compute": ("gaussians", 1, ("gl",)),
}


def test_rasterizer_values_saved_before_the_items_changed_keep_their_meaning(fresh_file, tmp_path):
    """Every mark's rasterizer is gl / native / auto now; the points' were
    compute / gl_points / native / auto (gl with gl_method now), the
    gaussians' native / compute / auto. Blender saved the index: a node made
    before opens with the value it had, keyframes too; a node made now
    keeps its own."""
    for name, (mark, index, _now) in OLD_RASTERIZERS.items():
        node = nodes.mark_node(nodes.new_style(name, mark=mark))
        _as_made_before_items_changed(node)
        _store_raw(node, "rasterizer", index)
        node.id_data.use_fake_user = True
    animated = nodes.mark_node(nodes.new_style("Animated", mark="points"))
    _as_made_before_items_changed(animated)
    for frame in (1, 9):
        animated.keyframe_insert("rasterizer", frame=frame)
    (curve,) = helpers.fcurves(animated.id_data)
    for key, old_index in zip(curve.keyframe_points, (0, 2)):  # compute, then native
        key.co[1] = key.handle_left[1] = key.handle_right[1] = old_index
    made_now = nodes.mark_node(nodes.new_style("Made now", mark="points"))
    made_now.rasterizer, made_now.gl_method = "native", "gl_points"
    for node in (animated, made_now):
        node.id_data.use_fake_user = True
    path = str(tmp_path / "rasterizers.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)  # the load handler migrates
    for name, (mark, _index, now) in OLD_RASTERIZERS.items():
        node = nodes.mark_node(bpy.data.node_groups[name])
        values = nodes.read_style(node.id_data, 1)["mark"][1]
        assert (values["rasterizer"], values.get("gl_method"))[:len(now)] == now, name
        assert (node.rasterizer, getattr(node, "gl_method", None))[:len(now)] == now, name
    animated = bpy.data.node_groups["Animated"]
    assert [nodes.read_style(animated, f)["mark"][1]["rasterizer"] for f in (1, 9)] == ["gl", "native"]
    made_now = nodes.mark_node(bpy.data.node_groups["Made now"])
    assert (made_now.rasterizer, made_now.gl_method) == ("native", "gl_points")
    assert versioning.migrate_legacy_nodes() == 0  # once: every node records the current items


def test_a_node_of_the_filter_once_named_hatching_becomes_pencil_hatching_and_renders_the_same(fresh_file, tmp_path):
    """The pencil hatching filter was `hatching`, the hatching mark's id
    too: a file saved before has nodes of PointNPRFilterHatchingNode, which
    load with their values, render as they did while not migrated (a
    library's tree), and are replaced by the current node with the same
    name, values, links and animation."""
    scene, near, _far = helpers.two_planes_scene("inpaint")
    tree = near.pointnpr_style
    mark = nodes.mark_node(tree)
    old = tree.nodes.new("PointNPRFilterHatchingNode")
    old.name = "Pencil"
    tree.links.new(mark.outputs[0], old.inputs[0])
    tree.links.new(old.outputs[0], nodes.find_output_node(tree).inputs[0])
    old.space, old.layers = "screen", 2
    old.keyframe_insert("spacing", frame=1)
    desc = nodes.read_style(tree, 1)
    assert [f for f, _v in desc["filters"]] == ["hatching"]
    assert nodes.make_core_style(desc).filters[0][0] == "pencil_hatching"
    before, _ = helpers.render_pixels(tmp_path, "before.png")
    assert versioning.migrate_legacy_nodes() == 1
    new = tree.nodes["Pencil"]
    assert new.bl_idname == "PointNPRFilterPencilHatchingNode"
    assert (new.space, new.layers) == ("screen", 2) and not new.is_property_set("angle")
    assert nodes.style_chain(tree) == [mark, new]
    assert [fc.data_path for fc in helpers.fcurves(tree)] == ['nodes["Pencil"].spacing']
    assert [f for f, _v in nodes.read_style(tree, 1)["filters"]] == ["pencil_hatching"]
    after, _ = helpers.render_pixels(tmp_path, "after.png")
    assert np.array_equal(before, after)
    assert versioning.migrate_legacy_nodes() == 0


def _gl_method_curve(tree):
    return [fc for fc in helpers.fcurves(tree) if fc.data_path.endswith(".gl_method")]


def test_keyframes_of_a_former_item_that_set_two_parameters_animate_both(fresh_file, tmp_path):
    """The points' gl_points was one rasterizer key; it is rasterizer gl and
    gl_method gl_points now: gl_method is keyed beside it, stepping at the
    same frames, so the animation renders as it did. At a key whose former
    item sets no gl_method (native, auto), gl_method holds what the node
    had before (the default: the old auto was GL's compute on a GPU), not
    the static gl_points the migration gave the node."""
    node = nodes.mark_node(nodes.new_style("Keyed", mark="points"))
    _as_made_before_items_changed(node)
    _store_raw(node, "rasterizer", 1)  # static gl_points: the static gl_method becomes gl_points
    frames = (1, 5, 9, 13)
    for frame in frames:
        node.keyframe_insert("rasterizer", frame=frame)
    (curve,) = helpers.fcurves(node.id_data)
    for key, old_index in zip(curve.keyframe_points, (1, 3, 0, 2)):  # gl_points, auto, compute, native
        key.co[1] = key.handle_left[1] = key.handle_right[1] = old_index
    node.id_data.use_fake_user = True
    path = str(tmp_path / "keyed.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)  # the load handler migrates
    tree = bpy.data.node_groups["Keyed"]
    node = nodes.mark_node(tree)
    assert (node.rasterizer, node.gl_method) == ("gl", "gl_points")
    (method,) = _gl_method_curve(tree)
    assert method.data_path == 'nodes["%s"].gl_method' % node.name
    assert [k.co[0] for k in method.keyframe_points] == list(frames)
    assert [k.co[1] for k in method.keyframe_points] == [1.0, 0.0, 0.0, 0.0]  # gl_points, compute...
    assert {k.interpolation for k in method.keyframe_points} == {'CONSTANT'}
    read = [(v["rasterizer"], v["gl_method"]) for v in
            (nodes.read_style(tree, f)["mark"][1] for f in (1, 4, 5, 9, 12, 13))]
    assert read == [("gl", "gl_points"), ("gl", "gl_points"), ("auto", "compute"),
                    ("gl", "compute"), ("gl", "compute"), ("native", "compute")]
    assert versioning.migrate_legacy_nodes() == 0
    assert len(_gl_method_curve(tree)) == 1


def test_a_linked_tree_saved_before_the_items_changed_renders_with_the_old_meaning(fresh_file, tmp_path):
    """A style linked from a library file saved before the rasterizer items
    changed cannot be migrated (linked data is read-only): its saved index
    and keys are read through the older items when the style is read for a
    render, gl_method too, and it renders as a node made now with the
    values they mean (gl_points, not native, which index 1 is now)."""
    helpers.reset_scene()
    helpers.add_camera()
    points = helpers.new_collection("Points")
    rng = np.random.default_rng(1)
    positions = rng.uniform(-2.0, 2.0, (4000, 3))
    positions[:, 2] = 0.0
    # Overlapping splats of many colours: GL points and the compute rules
    # settle their ties otherwise.
    helpers.add_points("Cloud", points, positions, colors=rng.uniform(0.0, 1.0, (4000, 3)))
    library_trees = set()
    for name, keyed in (("Library static", ()), ("Library keyed", (1, 3))):  # gl_points; auto
        tree = nodes.new_style(name, mark="points")
        node = nodes.mark_node(tree)
        node.color_source, node.point_size = "rgb", 9.0
        _as_made_before_items_changed(node)
        _store_raw(node, "rasterizer", 1)  # gl_points
        for frame in (1, 9)[:len(keyed)]:
            node.keyframe_insert("rasterizer", frame=frame)
        for key, index in zip(helpers.fcurves(tree)[0].keyframe_points if keyed else (), keyed):
            key.co[1] = key.handle_left[1] = key.handle_right[1] = index
        library_trees.add(tree)
    library = str(tmp_path / "library.blend")
    bpy.data.libraries.write(library, library_trees, fake_user=True)
    for tree in library_trees:
        bpy.data.node_groups.remove(tree)
    with bpy.data.libraries.load(library, link=True) as (_src, dst):
        dst.node_groups = ["Library static", "Library keyed"]
    linked = {tree.name: tree for tree in dst.node_groups}
    assert all(tree.library is not None for tree in linked.values())
    assert versioning.migrate_legacy_nodes() == 0  # read-only: left as saved

    def mark(tree, frame):
        values = nodes.read_style(tree, frame)["mark"][1]
        return values["rasterizer"], values["gl_method"]

    assert mark(linked["Library static"], 1) == ("gl", "gl_points")
    assert [mark(linked["Library keyed"], f) for f in (1, 9)] == [("gl", "gl_points"), ("auto", "compute")]
    points.pointnpr_style = linked["Library static"]
    from_library, _ = helpers.render_pixels(tmp_path, "linked.png")
    made_now = nodes.new_style("Made now", mark="points")
    nodes.set_node_values(nodes.mark_node(made_now), {"color_source": "rgb", "point_size": 9.0,
                                                      "rasterizer": "gl", "gl_method": "gl_points"})
    points.pointnpr_style = made_now
    assert np.array_equal(from_library, helpers.render_pixels(tmp_path, "gl_points.png")[0])
    # What index 1 is among the current items (native) draws otherwise.
    nodes.mark_node(made_now).rasterizer = "native"
    assert not np.array_equal(from_library, helpers.render_pixels(tmp_path, "native.png")[0])
    for tree in linked.values():
        bpy.data.node_groups.remove(tree)
    bpy.data.libraries.remove(bpy.data.libraries[0])
