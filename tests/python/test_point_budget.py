"""The frame's point budget (issue 14, level of detail): every mark draws a
prefix of each visible chunk's resolution queue, one density on screen for
the whole frame; a budget that covers the frame changes no byte."""
import os
import subprocess
import sys

import numpy as np
import pytest

import pointnpr

W, H = 240, 180
MARKS = {
    "points": {"point_size": 3},
    "hatching": {},
    "stipples": {},
    "feature_strokes": {},
    "brush_splats": {"blending": "none"},
}


def wavy(n, seed):
    rng = np.random.default_rng(seed)
    x, y = rng.uniform(-2, 2, n), rng.uniform(-1.5, 1.5, n)
    z = -6.0 + 0.4 * np.sin(3 * x) * np.cos(2 * y)
    return pointnpr.PointCloud(np.column_stack([x, y, z]), colors=rng.integers(0, 255, (n, 3)).astype(np.uint8))


@pytest.fixture(scope="module")
def cloud():
    return wavy(40000, 5)


def camera():
    return pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=W, height=H)


def scene_of(mark, cloud, params=None):
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=(mark, params if params is not None else MARKS[mark])), [cloud])
    return scene


def same_bytes(a, b):
    return all(np.asarray(getattr(a, n)).tobytes() == np.asarray(getattr(b, n)).tobytes()
               for n in ("color", "depth", "segment_index"))


@pytest.mark.parametrize("mark", sorted(MARKS))
def test_a_budget_covering_the_frame_changes_no_byte_and_a_small_one_draws_fewer(renderer, cloud, mark):
    scene = scene_of(mark, cloud)
    full = renderer.render(scene, camera(), W, H)
    assert not same_bytes(full, renderer.render(pointnpr.Scene(), camera(), W, H))
    assert same_bytes(full, renderer.render(scene, camera(), W, H, point_budget=cloud.num_points))
    small = renderer.render(scene, camera(), W, H, point_budget=4000)
    assert small.stats["point_budget_points"] <= 4000
    assert small.stats["point_budget_points"] > 3000  # filled, up to one point per chunk
    assert "point_budget_level" in small.stats
    assert not same_bytes(full, small)
    if mark in ("points", "brush_splats"):  # the others shade the surface their points span
        covered = lambda r: int((np.asarray(r.color)[..., 3] > 0).sum())
        assert 0 < covered(small) < covered(full)


def test_a_larger_budget_only_adds_marks(renderer, cloud):
    # Brush splats hand back the point of every splat drawn.
    scene = scene_of("brush_splats", cloud)
    drawn = []
    for budget in (2000, 5000, 12000, 30000):
        r = renderer.render(scene, camera(), W, H, point_budget=budget, capture_marks=True)
        ids = set(np.asarray(r.marks["point_id"]).tolist())
        assert len(ids) <= budget
        drawn.append(ids)
    for smaller, larger in zip(drawn, drawn[1:]):
        assert smaller < larger


def test_the_budget_is_shared_by_density_across_segments_and_chunks(renderer):
    # The same patch near and three times as far: a third the size on screen,
    # a ninth of the area, so about a ninth of the near one's points.
    patch = wavy(30000, 6)
    far = np.eye(4)
    far[2, 3] = -12.0
    scene = pointnpr.Scene()
    for name, m in (("near", np.eye(4)), ("far", far)):
        scene.add_segment(name, pointnpr.Style(mark=("brush_splats", {"blending": "none"})), [(patch, m)])
    r = renderer.render(scene, camera(), W, H, point_budget=6000, capture_marks=True)
    assert r.stats["point_budget_points"] <= 6000
    depth = -np.asarray(r.marks["center"])[:, 2]
    near, far_count = int((depth < 10).sum()), int((depth > 10).sum())
    assert near + far_count == len(depth) <= 6000
    assert 6.0 < near / far_count < 12.0
    assert "point_budget_level" not in renderer.render(scene, camera(), W, H).stats


def test_budgeted_frames_in_tiles_are_the_bytes_of_the_whole_frame(renderer, cloud):
    scene = scene_of("points", cloud)
    whole = renderer.render(scene, camera(), W, H, point_budget=5000)
    tiled = renderer.render(scene, camera(), W, H, point_budget=5000, tile_size=64)
    assert tiled.stats["tiles"] > 1
    assert same_bytes(whole, tiled)


def test_the_same_budget_renders_the_same_bytes_in_another_process(renderer, cloud, tmp_path):
    code = """
import sys, numpy as np, pointnpr
sys.path.insert(0, {here!r})
import test_point_budget as t
r = pointnpr.Renderer().render(t.scene_of("hatching", t.wavy(40000, 5)), t.camera(), t.W, t.H, point_budget=5000)
np.save({out!r}, np.asarray(r.color))
""".format(here=str(__import__("pathlib").Path(__file__).parent), out=str(tmp_path / "other.npy"))
    env = dict(os.environ, PYTHONPATH=os.path.abspath(os.environ.get("POINTNPR_BUILD_DIR", "build")))
    subprocess.run([sys.executable, "-c", code], check=True, timeout=300, env=env)
    here = renderer.render(scene_of("hatching", cloud), camera(), W, H, point_budget=5000)
    assert np.asarray(here.color).tobytes() == np.load(tmp_path / "other.npy").tobytes()


def test_a_negative_budget_is_refused(renderer, cloud):
    with pytest.raises(ValueError, match="point_budget"):
        renderer.render(scene_of("points", cloud), camera(), W, H, point_budget=-1)


@pytest.mark.parametrize("mark,params", [("points", {"rasterizer": "compute"}), ("points", {"rasterizer": "gl_points"}),
                                         ("points", {"rasterizer": "native"}), ("feature_strokes", {}),
                                         ("hatching", {})])
def test_a_segment_of_a_cut_and_an_uncut_cloud_draws_both(renderer, mark, params):
    # A dense cloud the budget cuts short and a sparse one it leaves whole,
    # in one segment: the mark draws every chunk by the queue order.
    dense, sparse = wavy(40000, 7), wavy(300, 8)
    scene = pointnpr.Scene()
    scene.add_segment("both", pointnpr.Style(mark=(mark, params)), [dense, sparse])
    r = renderer.render(scene, camera(), W, H, point_budget=5000)
    assert "point_budget_level" in r.stats
    assert 5000 - 300 < r.stats["point_budget_points"] <= 5000
