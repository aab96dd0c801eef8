"""Out-of-core scans in Blender: an import above the threshold writes a cache
and adds a light proxy that references it; renders stream the cache (the
same picture as the scan imported in memory); the import can be undone; a
missing or damaged cache is an error report, and the scene stays as it was."""
import os

import bpy
import numpy as np
import pointnpr
import pytest
from pointnpr.blender import importer, sync

import helpers

SAMPLE_LAS = os.path.join(helpers.IO_DATA, "sample_c.las")          # colours + classes


def _import(tmp_path, **kwargs):
    kwargs.setdefault("out_of_core_threshold", 0)
    return bpy.ops.import_scene.pointnpr_cloud(filepath=SAMPLE_LAS, cache_folder=str(tmp_path), **kwargs)


def _camera_over(obj, lo, hi):
    centre = (np.asarray(lo) + np.asarray(hi)) / 2
    cam = helpers.add_camera(location=(centre[0], centre[1], hi[2] + 50.0), ortho=True)
    cam.data.ortho_scale = float(max(hi[0] - lo[0], hi[1] - lo[1]))
    cam.data.clip_end = 1000.0
    return cam


def _snapshot():
    return (sorted(o.name for o in bpy.data.objects), sorted(m.name for m in bpy.data.meshes),
            sorted(c.name for c in bpy.data.collections))


def test_an_import_above_the_threshold_is_a_proxy_of_a_cache_and_renders_the_whole_scan(scene, tmp_path):
    data = pointnpr.read(SAMPLE_LAS)
    n = len(data.positions)
    proxy_points = importer.PROXY_POINTS
    assert _import(tmp_path) == {'FINISHED'}
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    path = os.path.normpath(bpy.path.abspath(obj["pointnpr_cache"]))  # relative to a saved .blend: //../..
    assert os.path.dirname(path) == str(tmp_path) and path.endswith(importer.CACHE_EXTENSION)
    assert obj["pointnpr_cache_points"] == n
    cached = pointnpr.CachedCloud(path)
    assert cached.num_points == n and cached.has("colors") and cached.has("classification")
    # The proxy: a seeded subsample (all of a small scan), its vertices the scan's, recentred.
    assert len(obj.data.vertices) == min(n, proxy_points)
    co = np.empty(len(obj.data.vertices) * 3, np.float32)
    obj.data.vertices.foreach_get("co", co)
    origin = np.asarray(obj["pointnpr_origin"])
    lo, hi = np.asarray(cached.bounds[0]), np.asarray(cached.bounds[1])
    assert np.allclose(lo + origin, data.positions.min(axis=0), atol=1e-6)
    assert np.all(co.reshape(-1, 3) >= lo - 1e-3) and np.all(co.reshape(-1, 3) <= hi + 1e-3)
    # The render streams the cache (budget above the scan: every point) and
    # equals the render of the same scan imported in memory.
    _camera_over(obj, lo, hi)
    streamed, _ = helpers.render_pixels(tmp_path, "cached.png")
    synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1)
    assert synced.num_points == n
    bpy.data.objects.remove(obj)
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=SAMPLE_LAS, out_of_core=False) == {'FINISHED'}
    memory_obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    assert "pointnpr_cache" not in memory_obj and len(memory_obj.data.vertices) == n
    memory, _ = helpers.render_pixels(tmp_path, "memory.png")
    assert (memory[:, :, :3].max(axis=2) > 0.05).mean() > 0.3
    # The same float coordinates, chunked and ordered the same way (depth ties, common in
    # quantised LiDAR, go to the same points): the same pixels.
    assert np.array_equal(memory, streamed)


def test_a_proxy_subsample_is_small_and_seeded(scene, tmp_path, monkeypatch):
    monkeypatch.setattr(importer, "PROXY_POINTS", 500)
    job_options = importer.OutOfCore(threshold=0, folder=str(tmp_path), proxy_points=importer.PROXY_POINTS)
    objects = importer.import_point_cloud(bpy.context, SAMPLE_LAS, out_of_core=job_options)
    assert len(objects) == 1 and len(objects[0].data.vertices) <= 500
    first = np.empty(len(objects[0].data.vertices) * 3, np.float32)
    objects[0].data.vertices.foreach_get("co", first)
    again = importer.import_point_cloud(bpy.context, SAMPLE_LAS, out_of_core=importer.OutOfCore(
        threshold=0, folder=str(tmp_path / "again"), proxy_points=500))
    second = np.empty(len(again[0].data.vertices) * 3, np.float32)
    again[0].data.vertices.foreach_get("co", second)
    assert np.array_equal(first, second)  # the same points in every import (queue order, by point id)


def test_below_the_threshold_the_import_stays_in_memory(scene, tmp_path):
    assert _import(tmp_path, out_of_core_threshold=10 ** 9) == {'FINISHED'}
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    assert "pointnpr_cache" not in obj
    assert not any(p.suffix == importer.CACHE_EXTENSION for p in tmp_path.iterdir())


def test_split_by_classification_caches_each_class(scene, tmp_path):
    data = pointnpr.read(SAMPLE_LAS)
    classes = np.asarray(data.attributes["classification"])
    assert _import(tmp_path, split_by_classification=True) == {'FINISHED'}
    objs = [o for o in bpy.data.objects if o.type == 'MESH']
    assert len(objs) == len(np.unique(classes)) > 1
    counts = sorted(o["pointnpr_cache_points"] for o in objs)
    assert counts == sorted(np.unique(classes, return_counts=True)[1].tolist())
    for o in objs:  # each segment's cache holds only its class
        cached = pointnpr.CachedCloud(bpy.path.abspath(o["pointnpr_cache"]))
        assert cached.num_points == o["pointnpr_cache_points"]
    synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1)
    assert len(synced.segment_names) == len(objs) and synced.num_points == len(classes)


def test_splitting_a_proxy_is_refused_and_changes_nothing(scene, tmp_path):
    assert _import(tmp_path) == {'FINISHED'}
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    before = _snapshot()
    with pytest.raises(RuntimeError, match="proxy of an out-of-core scan"):
        bpy.ops.object.pointnpr_segment(method='CONNECTED_COMPONENTS')
    assert _snapshot() == before


# Undo needs a window (ed.undo's poll): a second Blender under Xvfb imports
# out of core, streams the proxy's cache, and undoes the import.
UNDO_SCRIPT = r"""
import os, sys, bpy
sys.path.insert(0, os.environ["POINTNPR_BUILD_DIR"])
import pointnpr
pointnpr.register()
from pointnpr.blender import sync

def snapshot():
    return (sorted(o.name for o in bpy.data.objects), sorted(m.name for m in bpy.data.meshes),
            sorted(c.name for c in bpy.data.collections))

def run():
    try:
        win = bpy.context.window_manager.windows[0]
        with bpy.context.temp_override(window=win, area=win.screen.areas[0]):
            bpy.ops.ed.undo_push(message="before import")
            before = snapshot()
            result = bpy.ops.import_scene.pointnpr_cloud(
                filepath=os.environ["CLOUD"], out_of_core_threshold=0, cache_folder=os.environ["FOLDER"],
                background=False)
            print("IMPORTED", sorted(result), snapshot() != before, flush=True)
            obj = next(o for o in bpy.data.objects if "pointnpr_cache" in o)
            synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1)
            print("STREAMED", synced.num_points, obj["pointnpr_cache_points"], flush=True)
            bpy.ops.ed.undo()
            print("UNDONE", snapshot() == before, flush=True)
    finally:
        os._exit(0)

bpy.app.timers.register(run, first_interval=0.5)
"""


@pytest.mark.window
def test_an_out_of_core_import_can_be_undone(tmp_path):
    script = tmp_path / "undo.py"
    script.write_text(UNDO_SCRIPT)
    proc = helpers.run_blender_in_window(script, env={"CLOUD": SAMPLE_LAS, "FOLDER": str(tmp_path)})
    out = proc.stdout
    assert proc.returncode == 0, out[-3000:] + proc.stderr[-3000:]
    n = len(pointnpr.read(SAMPLE_LAS).positions)
    assert "IMPORTED ['FINISHED'] True" in out, out[-3000:]
    assert "UNDONE True" in out, out[-3000:]
    assert "STREAMED %d %d" % (n, n) in out, out[-3000:]


@pytest.mark.parametrize("damage", ["missing", "truncated", "altered"])
def test_a_missing_or_damaged_cache_is_an_error_report_and_changes_nothing(scene, tmp_path, damage):
    assert _import(tmp_path) == {'FINISHED'}
    obj = next(o for o in bpy.data.objects if o.type == 'MESH')
    path = bpy.path.abspath(obj["pointnpr_cache"])
    _camera_over(obj, *[np.asarray(b) for b in pointnpr.CachedCloud(path).bounds])
    sync.clear_cache()
    data = open(path, "rb").read()
    if damage == "missing":
        os.remove(path)
    elif damage == "truncated":
        open(path, "wb").write(data[:len(data) // 2])
    else:
        altered = bytearray(data)
        altered[len(data) - 100] ^= 0xFF  # a point of the last chunk: found by its checksum
        open(path, "wb").write(bytes(altered))
    before = _snapshot()
    with pytest.raises(pointnpr.ReadError) as info:
        sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1) if damage != "altered" else \
            _render_directly()
    assert obj.name in str(info.value) or damage == "altered"
    expected = {"missing": "No such file", "truncated": "truncated scan cache",
                "altered": "checksum does not match"}[damage]
    assert expected in str(info.value)
    # F12 in Blender: the engine reports the error instead of raising.
    with pytest.raises(RuntimeError):
        bpy.ops.render.render(write_still=False)
    assert _snapshot() == before


def _render_directly():
    synced = sync.build_scene(bpy.context.evaluated_depsgraph_get(), 1)
    cam = bpy.context.scene.camera
    w, h = 64, 48
    core_cam = pointnpr.Camera.orthographic(np.array(cam.matrix_world, dtype=np.float64),
                                            ortho_scale=cam.data.ortho_scale, clip_end=1000.0, width=w, height=h)
    return pointnpr.Renderer().render(synced.scene, core_cam, w, h)


@pytest.mark.parametrize("split", [False, True])
def test_a_scan_streamed_to_caches_is_the_scan_read_whole_then_cached(scene, tmp_path, monkeypatch, split):
    # LAS/LAZ above the threshold go to caches straight from the file (never held
    # whole); the caches are the bytes of the path that reads the file first.
    streamed = importer.import_point_cloud(bpy.context, SAMPLE_LAS, split_by_classification=split,
                                           out_of_core=importer.OutOfCore(0, str(tmp_path / "streamed")))
    monkeypatch.setattr(importer.ImportJob, "streams", lambda job: False)
    whole = importer.import_point_cloud(bpy.context, SAMPLE_LAS, split_by_classification=split,
                                        out_of_core=importer.OutOfCore(0, str(tmp_path / "whole")))
    assert len(streamed) == len(whole) == (len(np.unique(pointnpr.read(SAMPLE_LAS).attributes["classification"]))
                                           if split else 1)
    for a, b in zip(streamed, whole):
        assert list(a["pointnpr_origin"]) == list(b["pointnpr_origin"])
        with open(bpy.path.abspath(a["pointnpr_cache"]), "rb") as fa, open(bpy.path.abspath(b["pointnpr_cache"]),
                                                                             "rb") as fb:
            assert fa.read() == fb.read()
        assert len(a.data.vertices) == len(b.data.vertices)
    assert not [f for f in os.listdir(tmp_path / "streamed") if not f.endswith(importer.CACHE_EXTENSION)]
