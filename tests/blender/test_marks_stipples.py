"""The stipples mark in Blender: its node comes from the schema (Marks
category), it renders dots, and a stipple style reads no point attribute
from the scene but the point ids and, for its default light rule (share:
N.L from each point's normal), the normals."""
import bpy
import numpy as np
import pointnpr
from pointnpr.blender import nodes

import helpers


def _stipple_scene():
    scene = helpers.reset_scene()
    helpers.add_camera(location=(0.0, -6.0, 6.0))
    scene.camera.rotation_euler = (0.785398, 0.0, 0.0)
    scene.world.color = (1.0, 1.0, 1.0)
    coll = helpers.new_collection("Stippled")
    pts = helpers.grid_points(2.0, 0.04, 0.0)
    pts[:, 2] = 0.4 * np.sin(2.0 * pts[:, 0]) * np.cos(2.0 * pts[:, 1])
    helpers.add_points("Surface", coll, pts)
    tree = nodes.new_style("Stipple", mark="stipples")
    coll.pointnpr_style = tree
    return scene, tree


def test_stipples_mark_node_has_its_schema_parameters(scene):
    tree = nodes.new_style("Stipple", mark="stipples")
    node = nodes.mark_node(tree)
    assert node.bl_idname == "PointNPRMarkStipplesNode" and node.name == "Stipples"
    schema = pointnpr.schema("stipples", kind="mark")
    assert [p["name"] for p, _pid in node.pointnpr_params] == [p["name"] for p in schema["params"]]
    desc = nodes.read_style(tree, 1.0)
    assert desc["mark"][0] == "stipples" and desc["warnings"] == []
    style = nodes.make_core_style(desc)
    assert style.mark[0] == "stipples"
    assert style.source_attributes == ["point_index", "normals"]  # no colours
    node.lit_rule = "nearest"  # the paper's rule: positions and ids alone
    style = nodes.make_core_style(nodes.read_style(tree, 1.0))
    assert style.source_attributes == ["point_index"]


def test_stipples_mark_renders_and_level_changes_it(tmp_path):
    scene, tree = _stipple_scene()
    node = nodes.mark_node(tree)
    node.level = 6.0
    coarse, _ = helpers.render_pixels(tmp_path, "coarse.png")
    dark = (coarse[..., :3].mean(axis=2) < 0.5).mean()
    assert 0.01 < dark < 0.9, dark  # dots on white, not empty, not filled
    node.level = 9.0
    fine, _ = helpers.render_pixels(tmp_path, "fine.png")
    assert (fine[..., :3].mean(axis=2) < 0.5).mean() < dark  # a higher LEVEL thins more


def test_level_and_tau_keyframes_animate_smoothly(tmp_path):
    # LEVEL and tau keyframed at frames 1 and 11: frame 6 reads values in
    # between, and its picture lies between the two ends (dots thin as
    # LEVEL rises, fractional levels blended by seeded probability).
    import pytest

    _scene, tree = _stipple_scene()
    node = nodes.mark_node(tree)
    level_id, tau_id = nodes.property_identifier("level"), nodes.property_identifier("tau")
    node.specular = True
    for frame, level, tau in ((1, 6.0, 0.1), (11, 9.0, 0.4)):
        setattr(node, level_id, level)
        setattr(node, tau_id, tau)
        node.keyframe_insert(level_id, frame=frame)
        node.keyframe_insert(tau_id, frame=frame)
    dark = []
    for frame in (1, 6, 11):
        bpy.context.scene.frame_set(frame)
        params = nodes.read_style(tree, float(frame))["mark"][1]
        if frame == 1:
            assert params["level"] == pytest.approx(6.0) and params["tau"] == pytest.approx(0.1)
        elif frame == 6:
            assert 6.0 < params["level"] < 9.0 and 0.1 < params["tau"] < 0.4
        px, _ = helpers.render_pixels(tmp_path, "frame_%d.png" % frame)
        dark.append((px[..., :3].mean(axis=2) < 0.5).mean())
    assert dark[0] > dark[1] > dark[2], dark
