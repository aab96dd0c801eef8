"""The segmentation operator: split a point object into collections."""
import os

import bpy
import numpy as np
import pointnpr
import pytest
from pointnpr.blender import background, importer, segment

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
                               progress=lambda fraction, stage: seen.append((fraction, stage)),
                               cancelled=lambda: sum(s == "creating" for _, s in seen) > 2)
    assert (len(bpy.data.collections), len(bpy.data.objects), len(bpy.data.meshes)) == before
    creating = [f for f, s in seen if s == "creating"]
    assert len(creating) == 3 and creating == sorted(creating) and creating[0] >= segment.LABELLING_SHARE
    assert all(f <= segment.LABELLING_SHARE for f, s in seen if s == "labelling")
    assert not obj.hide_get()
    created = segment.segment_object(bpy.context, obj, 'CONNECTED_COMPONENTS', octree_level=4, min_points=1)
    assert len(created) == 3 and sum(len(o.data.vertices) for o in created) == 501


def test_cancel_while_labelling_stops_the_core_call(scene):
    # Region growing on 400k points takes the core a good second: the cancel,
    # asked as soon as the core reports progress, must stop it well before
    # its end, and nothing may be left behind.
    rng = np.random.default_rng(1)
    pos = rng.uniform(0, 50, (400000, 3)) * [1, 1, 0.02]
    colors = rng.integers(0, 255, (400000, 3)).astype(np.uint8)
    obj = _point_object("Big", pos, colors=colors)
    before = (len(bpy.data.collections), len(bpy.data.objects), len(bpy.data.meshes))
    seen = []
    with pytest.raises(segment.SegmentCancelled, match="while labelling"):
        segment.segment_object(bpy.context, obj, 'REGION_GROWING_RGB',
                               progress=lambda fraction, stage: seen.append(fraction),
                               cancelled=lambda: bool(seen) and seen[-1] > 0)
    assert 0 < seen[-1] < 0.9 * segment.LABELLING_SHARE
    assert (len(bpy.data.collections), len(bpy.data.objects), len(bpy.data.meshes)) == before
    assert not background.running()


def test_max_segments_pools_the_smallest(scene):
    pts = np.array([[i * 10.0, 0.0, 0.0] for i in range(6)])  # six isolated points
    obj = _point_object("Dots", pts)
    created = segment.segment_object(bpy.context, obj, 'CONNECTED_COMPONENTS', octree_level=10, min_points=1,
                                     max_segments=4)
    names = sorted(c.users_collection[0].name for c in created)
    assert len(created) == 5 and "Other segments" in names
    assert sum(len(o.data.vertices) for o in created) == 6


# The modal path (labelling on a worker thread, progress bar, Esc) needs a
# window: a second Blender under Xvfb starts a long region growing, presses
# Esc while the core labels, and reports what the core call did.
INTERACTIVE_SCRIPT = r"""
import os, sys, bpy
import numpy as np
sys.path.insert(0, os.environ["POINTNPR_BUILD_DIR"])
import pointnpr
pointnpr.register()
from pointnpr.blender import background, importer

rng = np.random.default_rng(1)
pos = rng.uniform(0, 50, (400000, 3)) * [1, 1, 0.02]
colors = rng.integers(0, 255, (400000, 3)).astype(np.uint8)
obj = bpy.data.objects.new("Big", importer.create_point_mesh("Big", pos, colors=colors))
bpy.context.scene.collection.objects.link(obj)
bpy.context.view_layer.objects.active = obj
state = {"ticks": 0}

def snapshot():
    return (sorted(o.name for o in bpy.data.objects), sorted(m.name for m in bpy.data.meshes),
            sorted(c.name for c in bpy.data.collections))

def start():
    state["before"] = snapshot()
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == 'VIEW_3D')
    with bpy.context.temp_override(window=win, area=area, active_object=obj):
        result = bpy.ops.object.pointnpr_segment('INVOKE_DEFAULT', method='REGION_GROWING_RGB')
    print("STARTED", sorted(result), len(background.running()), flush=True)

def tick():
    state["ticks"] += 1
    if state["ticks"] > 400:
        print("RESULT timeout", flush=True)
        os._exit(1)
    if "call" not in state:
        calls = background.running()
        if not calls or calls[0].fraction == 0.0:
            return 0.01  # the core has not reported work yet
        state["call"] = calls[0]
        bpy.context.window_manager.windows[0].event_simulate(type='ESC', value='PRESS')
        return 0.05
    call = state["call"]
    if not call.done:
        return 0.05
    try:
        call.result()
        outcome = "completed"
    except pointnpr.Cancelled:
        outcome = "cancelled"
    print("CANCEL", outcome, "%.2f" % call.fraction, "unchanged" if snapshot() == state["before"] else "changed",
          len(background.running()), flush=True)
    os._exit(0)

def guarded(fn):
    def run():
        try:
            return fn()
        except BaseException as exc:  # a failing timer would otherwise leave Blender running
            print("RESULT error", repr(exc), flush=True)
            os._exit(1)
    return run

bpy.app.timers.register(guarded(start), first_interval=0.5)
bpy.app.timers.register(guarded(tick), first_interval=0.6)
"""


@pytest.mark.window
def test_interactive_segment_cancels_the_core_call_with_esc(tmp_path):
    script = tmp_path / "interactive_segment.py"
    script.write_text(INTERACTIVE_SCRIPT)
    proc = helpers.run_blender_in_window(script)
    out = proc.stdout
    assert proc.returncode == 0, out[-3000:] + proc.stderr[-3000:]
    assert "STARTED ['RUNNING_MODAL'] 1" in out, out[-3000:]
    line = next(l for l in out.splitlines() if l.startswith("CANCEL"))
    _, outcome, fraction, scene_state, still_running = line.split()
    assert (outcome, scene_state, still_running) == ("cancelled", "unchanged", "0"), line
    assert float(fraction) < 0.9, line  # stopped well before the end of the core's work
