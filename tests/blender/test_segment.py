"""The segmentation operator: split a point object into collections."""
import os

import bpy
import numpy as np
import pointnpr
import pytest
from pointnpr.blender import importer, segment

import helpers

CLASSIFIED_LAS = os.path.join(helpers.IO_DATA, "laspy_nebraska_classified.las")


def _point_object(name, positions, colors=None, classification=None):
    mesh = importer.create_point_mesh(name, np.asarray(positions, np.float64), colors=colors,
                                      classification=classification)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    return obj


def _blobs():
    rng = np.random.default_rng(0)
    a = rng.uniform(0, 1, (300, 3))
    b = rng.uniform(0, 1, (200, 3)) + [5.0, 0, 0]
    lone = np.array([[2.5, 4.0, 4.0]])
    return np.vstack([a, b, lone])


def _segments(root_name):
    root = bpy.data.collections[root_name]
    return {c.name: c for c in root.children}


def test_connected_components_operator_splits_into_named_collections(scene):
    obj = _point_object("Blobs", _blobs())
    assert bpy.ops.object.pointnpr_segment(method='CONNECTED_COMPONENTS', octree_level=4,
                                           min_points=5) == {'FINISHED'}
    parts = _segments("Blobs segments")
    assert set(parts) == {"Component 1", "Component 2", "Small components (< 5 points)"}
    counts = {name: len(c.objects[0].data.vertices) for name, c in parts.items()}
    assert counts == {"Component 1": 300, "Component 2": 200, "Small components (< 5 points)": 1}
    assert obj.hide_get() and obj.hide_render  # the original is hidden, not deleted
    # The same partition as the core's.
    labels = pointnpr.connected_components(_blobs(), level=4, min_points=5)
    assert np.bincount(labels[labels >= 0]).tolist() == [300, 200]


def test_split_by_classification_uses_asprs_class_names(scene):
    data = pointnpr.read(CLASSIFIED_LAS)
    cls = np.asarray(dict(data.attributes)["classification"])
    pos = np.asarray(data.positions, np.float64)
    _point_object("Nebraska", pos - pos.mean(axis=0), classification=cls)
    assert bpy.ops.object.pointnpr_segment(method='ATTRIBUTE', attribute="classification") == {'FINISHED'}
    parts = _segments("Nebraska segments")
    assert set(parts) == {importer.class_name(c) for c in np.unique(cls)}
    for code in np.unique(cls):
        coll = parts[importer.class_name(code)]
        mesh = coll.objects[0].data
        assert len(mesh.vertices) == int(np.count_nonzero(cls == code))
        values = np.empty(len(mesh.vertices), np.int32)
        mesh.attributes["classification"].data.foreach_get("value", values)
        assert np.all(values == code)


def test_colour_region_growing_operator(scene):
    xs, ys = np.meshgrid(np.arange(30) * 0.02, np.arange(10) * 0.02)
    pos = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)])
    colors = np.where(pos[:, :1] < 0.29, [[220, 20, 20]], [[20, 20, 220]]).astype(np.uint8)
    _point_object("Wall", pos, colors=colors)
    assert bpy.ops.object.pointnpr_segment(method='REGION_GROWING_RGB', distance_threshold=0.05,
                                           point_color_threshold=10, region_color_threshold=10,
                                           min_cluster_size=5) == {'FINISHED'}
    parts = _segments("Wall segments")
    assert set(parts) == {"Region 1", "Region 2"}
    assert sorted(len(c.objects[0].data.vertices) for c in parts.values()) == [150, 150]


def test_errors_are_reported_and_leave_the_scene_unchanged(scene):
    _point_object("NoColours", _blobs())
    before = (len(bpy.data.collections), len(bpy.data.objects), len(bpy.data.meshes))
    with pytest.raises(RuntimeError, match="no point colours"):
        bpy.ops.object.pointnpr_segment(method='REGION_GROWING_RGB')
    with pytest.raises(RuntimeError, match="no integer point attribute 'label'"):
        bpy.ops.object.pointnpr_segment(method='ATTRIBUTE', attribute="label")
    assert (len(bpy.data.collections), len(bpy.data.objects), len(bpy.data.meshes)) == before


def test_cancel_removes_everything_created_and_progress_moves(scene):
    obj = _point_object("Blobs", _blobs())
    before = (len(bpy.data.collections), len(bpy.data.objects), len(bpy.data.meshes))
    seen = []
    with pytest.raises(segment.SegmentCancelled):
        segment.segment_object(bpy.context, obj, 'CONNECTED_COMPONENTS', octree_level=4, min_points=1,
                               progress=lambda done, total: seen.append((done, total)),
                               cancelled=lambda: len(seen) > 2)
    assert (len(bpy.data.collections), len(bpy.data.objects), len(bpy.data.meshes)) == before
    assert [d for d, _ in seen] == [0, 1, 2] and len({t for _, t in seen}) == 1
    assert not obj.hide_get()
    created = segment.segment_object(bpy.context, obj, 'CONNECTED_COMPONENTS', octree_level=4, min_points=1)
    assert len(created) == 3 and sum(len(o.data.vertices) for o in created) == 501


def test_max_segments_pools_the_smallest(scene):
    pts = np.array([[i * 10.0, 0.0, 0.0] for i in range(6)])  # six isolated points
    obj = _point_object("Dots", pts)
    created = segment.segment_object(bpy.context, obj, 'CONNECTED_COMPONENTS', octree_level=10, min_points=1,
                                     max_segments=4)
    names = sorted(c.users_collection[0].name for c in created)
    assert len(created) == 5 and "Other segments" in names
    assert sum(len(o.data.vertices) for o in created) == 6
