"""The viewport's frames off the UI thread (blender/viewport_worker.py),
driven directly: order, replacement, stale and cancelled frames, errors.
Requests are held (viewport_worker.hold) to make "in flight" a state the
tests wait on; nothing asserts a timing. The window side (view_draw, Esc,
closing the viewport) is tests/viewport/viewport_test.py."""
import time

import bpy
import numpy as np
import pytest

import pointnpr
from pointnpr.blender import viewport_worker


def wait_for(condition, what, timeout=30.0):
    t0 = time.time()
    while not condition():
        assert time.time() - t0 < timeout, "timed out waiting for " + what
        time.sleep(0.005)


@pytest.fixture
def worker():
    viewport_worker.hold = None
    yield viewport_worker
    viewport_worker.hold = None
    for s in viewport_worker.sessions():
        s.close()


@pytest.fixture(scope="module")
def frame_scene():
    rng = np.random.default_rng(5)
    cloud = pointnpr.PointCloud(rng.uniform(-1, 1, (20000, 3)) + [0, 0, -5],
                                colors=rng.integers(0, 255, (20000, 3)).astype(np.uint8))
    scene = pointnpr.Scene()
    scene.add_segment("a", pointnpr.Style(rasterize={"point_size": 3}), [cloud])
    scene.add_segment("b", pointnpr.Style(filters=["cartoon"]), [cloud])
    return pointnpr.Renderer(), scene


def request(frame_scene, key, scale=1, width=96, height=64, angle=0.0):
    renderer, scene = frame_scene
    c, s = np.cos(angle), np.sin(angle)
    world_from_camera = np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]], dtype=np.float64)
    camera = pointnpr.Camera.perspective(world_from_camera, width=width // scale, height=height // scale)
    return viewport_worker.Request(renderer, scene, camera, width // scale, height // scale, scale, key,
                                   dict(background=(0.1, 0.1, 0.1, 1.0)))


def events_of(generation):
    return [e for e in viewport_worker.events if e[1] == generation]


def test_a_frame_is_the_render_of_its_snapshot(worker, frame_scene):
    session = worker.Session()
    req = request(frame_scene, "k", angle=0.2)
    session.submit(req)
    wait_for(lambda: session.frame() is not None, "the frame")
    frame = session.frame()
    assert (frame.key, frame.scale, frame.generation) == ("k", 1, req.generation)
    direct = frame_scene[0].render(req.scene, req.camera, req.width, req.height, **req.render_args)
    assert np.asarray(frame.color).tobytes() == np.asarray(direct.color).tobytes()


def test_a_newer_request_replaces_the_pending_one_and_frames_come_in_order(worker, frame_scene):
    session = worker.Session()
    worker.hold = lambda r: True
    first, replaced, last = (request(frame_scene, k, scale=4) for k in "abc")
    session.submit(first)
    wait_for(lambda: session.running is first, "the first request in flight")
    session.submit(replaced)
    session.submit(last)
    assert ("dropped", replaced.generation, 4, "replaced") in worker.events
    worker.hold = None
    wait_for(lambda: session.frame() is not None and session.frame().key == "c", "the last frame")
    # The reduced frame in flight is a moving view's preview: shown before the newer one.
    assert [e[0] for e in events_of(first.generation)] == ["submitted", "published"]
    assert [e[0] for e in events_of(replaced.generation)] == ["submitted", "dropped"]
    assert not session.busy()


def test_a_full_frame_whose_view_moved_on_is_cancelled_and_never_shown(worker, frame_scene):
    session = worker.Session()
    worker.hold = lambda r: r.full
    stale = request(frame_scene, "rest", angle=0.1)
    session.submit(stale)
    wait_for(lambda: session.running is stale, "the full frame in flight")
    session.submit(request(frame_scene, "moved", scale=4, angle=0.3))
    wait_for(lambda: ("dropped", stale.generation, 1, "superseded") in worker.events, "the stale frame dropped")
    wait_for(lambda: session.frame() is not None, "the newer frame")
    assert session.frame().key == "moved"
    assert "published" not in [e[0] for e in events_of(stale.generation)]


def test_the_same_view_at_full_quality_is_not_superseded(worker, frame_scene):
    session = worker.Session()
    worker.hold = lambda r: r.full
    full = request(frame_scene, "same")
    session.submit(full)
    wait_for(lambda: session.running is full, "the full frame in flight")
    session.submit(request(frame_scene, "same", scale=2))   # e.g. the factor changed: same view
    assert full.cancelled is None
    worker.hold = None
    wait_for(lambda: session.frame() is not None and session.frame().scale == 2, "both frames")
    assert "published" in [e[0] for e in events_of(full.generation)]


def test_the_deferred_full_frame_starts_by_itself_unless_a_newer_request_comes(worker, frame_scene):
    session = worker.Session()
    reduced, full = request(frame_scene, "v", scale=4), request(frame_scene, "v")
    session.submit(reduced, deferred=full, deferred_at=time.perf_counter() + 0.1)
    wait_for(lambda: session.frame() is not None and session.frame().full, "the deferred full frame")
    assert [e[0] for e in events_of(reduced.generation)] == ["submitted", "published"]
    assert [e[0] for e in events_of(full.generation)] == ["deferred", "published"]
    assert full.generation > reduced.generation
    # Moving on before it is due replaces it: it never renders.
    moved, never = request(frame_scene, "w", scale=4), request(frame_scene, "w")
    session.submit(moved, deferred=never, deferred_at=time.perf_counter() + 3600.0)
    session.submit(request(frame_scene, "x", scale=4))
    assert ("dropped", never.generation, 1, "replaced") in worker.events
    wait_for(lambda: session.frame().key == "x", "the newest frame")
    assert "published" not in [e[0] for e in events_of(never.generation)]


def test_cancel_drops_pending_and_running_work_and_keeps_what_was_shown(worker, frame_scene):
    session = worker.Session()
    shown = request(frame_scene, "shown", scale=4)
    session.submit(shown)
    wait_for(lambda: session.frame() is not None, "a first frame")
    worker.hold = lambda r: True
    # A reduced frame in flight (a full one would be superseded by the next request).
    running, pending = request(frame_scene, "r", scale=4), request(frame_scene, "p")
    session.submit(running)
    wait_for(lambda: session.running is running, "a frame in flight")
    later = request(frame_scene, "p")
    session.submit(pending, deferred=later, deferred_at=time.perf_counter() + 3600.0)
    session.last_key = "p"
    assert session.cancel()
    wait_for(lambda: not session.busy(), "the cancelled frame to stop")
    assert ("dropped", running.generation, 4, "cancelled") in worker.events
    assert ("dropped", pending.generation, 1, "cancelled") in worker.events
    assert ("dropped", later.generation, 1, "cancelled") in worker.events
    assert session.frame().key == "shown"
    # Nothing renders again until the view changes (engine.view_draw reads it).
    assert session.halted_key == "p"


def test_closing_cancels_and_forgets_the_session(worker, frame_scene):
    session = worker.Session()
    worker.hold = lambda r: True
    req = request(frame_scene, "x")
    session.submit(req)
    wait_for(lambda: session.running is req, "a frame in flight")
    session.close()
    assert session not in worker.sessions()
    wait_for(lambda: ("dropped", req.generation, 1, "closed") in worker.events, "the closed session's frame dropped")
    assert session.frame() is None
    session.submit(request(frame_scene, "y"))   # a late draw of a closed viewport renders nothing
    assert not session.busy()


def test_a_failing_frame_reports_its_error_and_publishes_nothing(worker, frame_scene):
    session = worker.Session()
    bad = request(frame_scene, "bad")
    bad.render_args = dict(background=(0.0, 0.0))   # not RGBA: the core refuses it
    session.submit(bad)
    wait_for(lambda: session.error is not None, "the error")
    assert "background" in session.error
    assert session.frame() is None
    good = request(frame_scene, "good")
    session.submit(good)
    wait_for(lambda: session.frame() is not None, "a good frame after the error")
    assert session.error is None


def test_shutdown_stops_the_worker_and_a_new_request_starts_it_again(worker, frame_scene):
    session = worker.Session()
    session.submit(request(frame_scene, "before"))
    wait_for(lambda: session.frame() is not None, "a frame")
    thread = worker._worker[0]
    worker.shutdown()
    assert not thread.is_alive() and worker._worker[0] is None
    assert not worker.sessions()
    again = worker.Session()
    again.submit(request(frame_scene, "after"))
    wait_for(lambda: again.frame() is not None, "a frame after the restart")


def test_the_viewport_settings_and_the_cancel_operator(worker, frame_scene, scene):
    from pointnpr.blender import engine
    assert scene.pointnpr.navigation_resolution == "4" and engine.navigation_factor(scene) == 4
    assert scene.pointnpr.refine_delay == 0.5 and engine.refine_delay(scene) == 0.5
    scene.pointnpr.navigation_resolution = "1"
    assert engine.navigation_factor(scene) == 1
    # Esc passes through when nothing is in flight (the operator's poll fails).
    assert not bpy.ops.pointnpr.viewport_cancel.poll()
    session = worker.Session()
    worker.hold = lambda r: True
    req = request(frame_scene, "esc")
    session.submit(req)
    assert bpy.ops.pointnpr.viewport_cancel.poll()
    assert bpy.ops.pointnpr.viewport_cancel() == {'PASS_THROUGH'}
    wait_for(lambda: ("dropped", req.generation, 1, "cancelled") in worker.events, "Esc to cancel")


def test_navigation_frames_keep_the_full_frames_points_per_pixel():
    from pointnpr.blender import engine
    synced = engine._SyncedScene(None, state=None)
    synced.render_args = {"time": 0.0}
    synced.point_budget = 3_000_000                 # the Viewport Point Budget's default
    assert synced.render_args_at(1) == {"time": 0.0, "point_budget": 3_000_000}
    assert synced.render_args_at(4)["point_budget"] == 3_000_000 // 16
    assert synced.render_args_at(8)["point_budget"] == 3_000_000 // 64
    synced.point_budget = 0                         # every point, at any resolution
    assert synced.render_args_at(4)["point_budget"] == 0


def _scan_in_view():
    """A cloud with colours in front of a camera, synced from Blender's depsgraph."""
    import helpers
    helpers.reset_scene()
    helpers.add_camera(location=(0.0, 0.0, 10.0), ortho=True)
    coll = helpers.new_collection("Scan")
    pts = helpers.grid_points(3.0, 0.1, 0.0)
    rng = np.random.default_rng(3)
    helpers.add_points("Scan", coll, pts, colors=rng.random((len(pts), 3)))
    tree = helpers.constant_style("Colours", helpers.RED, point_size=3.0)
    tree.nodes["Points"].color_source = "rgb"
    coll.pointnpr_style = tree
    return bpy.context.evaluated_depsgraph_get()


def test_the_first_viewport_sync_reads_on_the_main_thread_and_builds_its_clouds_on_the_worker(worker, monkeypatch):
    import threading
    from pointnpr.blender import engine, sync
    depsgraph = _scan_in_view()
    sync.clear_cache()
    built_on = []
    resolve = sync.PendingCloud.resolve

    def recorded(self):
        if self.built() is None:
            built_on.append(threading.current_thread().name)
        return resolve(self)

    monkeypatch.setattr(sync.PendingCloud, "resolve", recorded)
    synced = engine._SyncedScene(depsgraph, state=None)
    # Read (the object's data can only be read here), not built.
    assert sync.cache_stats()["reads"] == 1 and built_on == []
    assert synced.result.scene is None and synced.result.num_points == 61 * 61
    camera = engine.make_camera(depsgraph, bpy.context.scene.camera, 96, 64)
    session = worker.Session()
    req = viewport_worker.Request(engine.renderer(), lambda: synced.scene_at(4), camera, 24, 16, 4, "k",
                                  synced.render_args_at(4))
    full = viewport_worker.Request(engine.renderer(), lambda: synced.scene_at(1), camera, 96, 64, 1, "k",
                                   synced.render_args_at(1))
    session.submit(req, deferred=full, deferred_at=time.perf_counter())
    wait_for(lambda: session.frame() is not None and session.frame().full, "the full frame")
    assert built_on == ["PointNPR viewport"]          # once, on the worker, for both frames
    # The same picture as a sync that builds its clouds at once, from an empty cache.
    sync.clear_cache()
    direct = sync.build_scene(depsgraph, 1.0, trust_cache=True)
    assert sync.cache_stats()["reads"] == 1 and built_on == ["PointNPR viewport", "MainThread"]
    expected = engine.renderer().render(direct.scene, camera, 96, 64, **synced.render_args_at(1))
    assert np.asarray(session.frame().color).tobytes() == np.asarray(expected.color).tobytes()
    # A later sync of the unchanged object reuses the built cloud: nothing read or built.
    again = engine._SyncedScene(depsgraph, state=None)
    assert sync.cache_stats()["reads"] == 1 and len(built_on) == 2
    assert again.scene_at(1) is not None and len(built_on) == 2


def test_a_cloud_that_cannot_be_built_is_the_viewports_error_not_the_ui_threads(worker, monkeypatch):
    from pointnpr.blender import engine, sync
    depsgraph = _scan_in_view()
    sync.clear_cache()

    def refused(self):
        raise pointnpr.Error("no cloud for you")

    monkeypatch.setattr(sync.PendingCloud, "resolve", refused)
    synced = engine._SyncedScene(depsgraph, state=None)   # the main thread's part succeeds
    assert synced.error is None
    camera = engine.make_camera(depsgraph, bpy.context.scene.camera, 32, 24)
    session = worker.Session()
    session.submit(viewport_worker.Request(engine.renderer(), lambda: synced.scene_at(1), camera, 32, 24, 1, "k",
                                           synced.render_args_at(1)))
    wait_for(lambda: session.error is not None, "the error")
    assert "no cloud for you" in session.error and session.frame() is None
