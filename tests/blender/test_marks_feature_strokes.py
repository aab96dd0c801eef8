"""The feature_strokes mark in Blender: its node (generated from the
schema, Marks category), keyframed LEVEL and tau read per frame, a render."""
import bpy
import numpy as np
import pointnpr
from pointnpr.blender import nodes

import helpers


def test_feature_strokes_node_has_its_schema_parameters(scene):
    tree = nodes.new_style("Features", mark="feature_strokes")
    node = nodes.mark_node(tree)
    assert node.bl_idname == "PointNPRMarkFeatureStrokesNode" and node.name == "Feature strokes"
    schema = pointnpr.schema("feature_strokes", kind="mark")
    assert [p["name"] for p, _pid in node.pointnpr_params] == [p["name"] for p in schema["params"]]
    desc = nodes.read_style(tree, 1.0)
    assert desc["mark"][0] == "feature_strokes" and desc["warnings"] == []
    assert nodes.make_core_style(desc).mark[0] == "feature_strokes"


def test_level_and_threshold_keyframes_interpolate(scene):
    tree = nodes.new_style("Features", mark="feature_strokes")
    node = nodes.mark_node(tree)
    level_id, tau_id = nodes.property_identifier("queue_level"), nodes.property_identifier("feature_threshold")
    setattr(node, nodes.property_identifier("density_mode"), "constant_on_screen")
    for frame, level, tau in ((1, 0.05, 0.3), (11, 0.25, 0.5)):
        setattr(node, level_id, level)
        setattr(node, tau_id, tau)
        node.keyframe_insert(level_id, frame=frame)
        node.keyframe_insert(tau_id, frame=frame)
    values = []
    for frame in (1, 6, 11):
        bpy.context.scene.frame_set(frame)
        params = nodes.read_style(tree, float(frame))["mark"][1]
        values.append((params["queue_level"], params["feature_threshold"]))
    assert values[0] == (pytest_approx(0.05), pytest_approx(0.3))
    assert 0.05 < values[1][0] < 0.25 and 0.3 < values[1][1] < 0.5  # in between: animated smoothly
    assert values[2] == (pytest_approx(0.25), pytest_approx(0.5))


def pytest_approx(v):
    import pytest

    return pytest.approx(v, abs=1e-6)


def test_feature_strokes_mark_renders(tmp_path):
    scene = helpers.reset_scene()
    helpers.add_camera(location=(0.0, -6.0, 6.0))
    scene.camera.rotation_euler = (0.785398, 0.0, 0.0)
    scene.world.color = (1.0, 1.0, 1.0)
    coll = helpers.new_collection("Featured")
    pts = helpers.grid_points(2.0, 0.04, 0.0)
    pts[:, 2] = np.where(pts[:, 0] > 0.0, 0.5, 0.0)  # a step: an edge for the strokes
    helpers.add_points("Step", coll, pts)
    coll.pointnpr_style = nodes.new_style("Features", mark="feature_strokes")
    img, _ = helpers.render_pixels(tmp_path, "features.png")
    dark = (img[..., :3].mean(axis=2) < 0.5).mean()
    assert 0.001 < dark < 0.5, dark
