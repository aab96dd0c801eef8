"""The points mark's native rasterizer (issue 14): the compute rasterizer's
images from the CPU's threads, picked by rasterizer = auto on software GL.

Agreement with compute uses the tolerance between compute and gl_points
(tests/cpp/test_render.cpp, ComputeAndGlPointsRasterizersAgree): 0.5 % of
the covered pixels may differ (float rounding of a different processor
on splat borders and on depth ties)."""
import hashlib
import os
import subprocess
import sys

import numpy as np
import pytest

import pointnpr

W, H = 240, 180
BACKGROUND = 1e10  # the frame's depth where nothing is drawn


def terrain(n=60000, seed=5, z0=-6.0, normals=False):
    """Random points on a wavy surface with random colours, intensities and
    classes: every attribute differs from point to point."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(-2.5, 2.5, n)
    y = rng.uniform(-1.8, 1.8, n)
    z = z0 + 0.5 * np.sin(3 * x) * np.cos(2 * y) + rng.normal(0, 0.01, n)
    extra = {}
    if normals:
        nrm = np.column_stack([-1.5 * np.cos(3 * x) * np.cos(2 * y), np.sin(3 * x) * np.sin(2 * y), np.ones(n)])
        extra["normals"] = (nrm / np.linalg.norm(nrm, axis=1, keepdims=True)).astype(np.float32)
    return pointnpr.PointCloud(np.column_stack([x, y, z]), colors=rng.integers(0, 255, (n, 3)).astype(np.uint8),
                               intensity=rng.gamma(2.0, 40.0, n).astype(np.float32),
                               classification=rng.integers(0, 24, n).astype(np.uint8), **extra)


@pytest.fixture(scope="module")
def cloud():
    return terrain()


def camera(width=W, height=H):
    return pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=width, height=height)


def render(renderer, cloud, params, cam=None, width=W, height=H, **kw):
    scene = pointnpr.Scene()
    scene.add_segment("scan", pointnpr.Style(rasterize=params), [cloud])
    r = renderer.render(scene, cam or camera(width, height), width, height, **kw)
    return np.asarray(r.color).reshape(-1, 4), np.asarray(r.depth).ravel(), r


def assert_agree(a, b, min_covered=1000):
    """Coverage, colour and depth of two renders within the tolerance."""
    (ca, da, _), (cb, db, _) = a, b
    cov_a, cov_b = ca[:, 3] > 0, cb[:, 3] > 0
    either = int(np.count_nonzero(cov_a | cov_b))
    assert either >= min_covered
    # The frame's depth is the background's (1e10) exactly where nothing is covered.
    for c, d in ((cov_a, da), (cov_b, db)):
        assert np.array_equal(d < BACKGROUND, c)
    both = cov_a & cov_b
    differ = (cov_a != cov_b) | (both & ((np.abs(ca - cb).max(axis=1) > 1e-5) | (da != db)))
    assert np.count_nonzero(differ) * 200 <= either, f"{np.count_nonzero(differ)} of {either} pixels differ"


CASES = {
    "0.7 px": {"point_size": 0.7},
    "1 px": {"point_size": 1},
    "1.5 px": {"point_size": 1.5},
    "2 px": {"point_size": 2},
    "3.5 px": {"point_size": 3.5},
    "world size": {"size_mode": "world", "world_size": 0.03},
    "spacing size": {"size_mode": "spacing", "point_size": 1.5},
    "rgb": {"color_source": "rgb"},
    "intensity": {"color_source": "intensity"},
    "classification": {"color_source": "classification"},
    "constant": {"color_source": "constant", "color": (0.2, 0.5, 0.9, 1.0)},
    "diffuse, camera light": {"shading": "diffuse", "shading_strength": 1.0},
    "diffuse, world light": {"shading": "diffuse", "light_space": "world", "light_azimuth": 30.0,
                             "light_elevation": 20.0, "normal_neighbors": 8},
    "queue": {"density_mode": "constant_on_screen", "queue_level": 0.25},
}


@pytest.mark.parametrize("case", list(CASES))
def test_native_draws_the_images_of_compute(renderer, cloud, case):
    params = dict({"point_size": 2}, **CASES[case])
    native = render(renderer, cloud, dict(params, rasterizer="native"))
    compute = render(renderer, cloud, dict(params, rasterizer="compute"))
    assert_agree(native, compute)


def test_shading_uses_the_clouds_own_normals(renderer):
    lit = terrain(normals=True)
    params = {"point_size": 2, "shading": "diffuse", "shading_strength": 1.0, "color_source": "constant",
              "color": (1, 1, 1, 1)}
    native = render(renderer, lit, dict(params, rasterizer="native"))
    assert_agree(native, render(renderer, lit, dict(params, rasterizer="compute")))
    flat = render(renderer, lit, dict(params, shading="none", rasterizer="native"))
    covered = native[0][:, 3] > 0
    # The slopes are darker than unlit, and by different amounts.
    assert np.mean(native[0][covered, 0]) < np.mean(flat[0][covered, 0]) - 0.05
    assert np.std(native[0][covered, 0]) > 0.05


def test_orthographic_camera(renderer, cloud):
    cam = pointnpr.Camera.orthographic(np.eye(4), ortho_scale=5.0, width=W, height=H)
    for params in ({"point_size": 2}, {"size_mode": "world", "world_size": 0.04}):
        native = render(renderer, cloud, dict(params, rasterizer="native"), cam)
        assert_agree(native, render(renderer, cloud, dict(params, rasterizer="compute"), cam))


def test_auto_is_native_on_software_gl(renderer, cloud):
    auto = render(renderer, cloud, {"point_size": 2})
    native = render(renderer, cloud, {"point_size": 2, "rasterizer": "native"})
    compute = render(renderer, cloud, {"point_size": 2, "rasterizer": "compute"})
    software = pointnpr.gl_info()["software"]
    assert ("native_scatter_ms" in auto[2].stats) == software
    assert "native_scatter_ms" not in compute[2].stats
    expected = native if software else compute
    assert auto[0].tobytes() == expected[0].tobytes() and auto[1].tobytes() == expected[1].tobytes()


def test_queue_adds_points_only_at_its_end(renderer, cloud):
    """More queue level: the points drawn before stay drawn (each pixel's
    winner only changes to a point added, never to one dropped)."""
    def points_drawn(level):
        c, d, _ = render(renderer, cloud, {"point_size": 1, "rasterizer": "native", "color_source": "rgb",
                                           "density_mode": "constant_on_screen", "queue_level": level})
        return c[:, 3] > 0, d
    low_cov, low_d = points_drawn(0.05)
    high_cov, high_d = points_drawn(0.15)
    assert 500 < low_cov.sum() < high_cov.sum()
    assert np.all(high_cov[low_cov])  # covered stays covered
    assert np.all(high_d[low_cov] <= low_d[low_cov])  # only nearer points win


def test_tiles_are_the_bytes_of_the_whole_frame(renderer, cloud):
    for params in ({"point_size": 3}, {"point_size": 1.5}, {"size_mode": "world", "world_size": 0.05},
                   {"size_mode": "spacing", "point_size": 2}):
        whole = render(renderer, cloud, dict(params, rasterizer="native"), width=257, height=199)
        tiled = render(renderer, cloud, dict(params, rasterizer="native"), width=257, height=199, tile_size=64)
        assert tiled[2].stats["tiles"] > 1
        assert whole[0].tobytes() == tiled[0].tobytes() and whole[1].tobytes() == tiled[1].tobytes()


def test_empty_behind_and_degenerate_clouds_draw_nothing_and_do_not_fail(renderer):
    cam = camera()
    # Every point behind the camera, at the camera plane (w = 0), beyond far,
    # or far off to the side: nothing covered, nothing raised.
    rng = np.random.default_rng(2)
    odd = np.concatenate([
        np.column_stack([rng.uniform(-1, 1, 500), rng.uniform(-1, 1, 500), np.full(500, 3.0)]),
        np.column_stack([rng.uniform(-1, 1, 500), rng.uniform(-1, 1, 500), np.zeros(500)]),
        np.column_stack([rng.uniform(-1, 1, 500), rng.uniform(-1, 1, 500), np.full(500, -5000.0)]),
        np.column_stack([np.full(500, 1e7), rng.uniform(-1, 1, 500), np.full(500, -5.0)]),
    ])
    for positions in (odd, odd[:1]):
        for params in ({"point_size": 2}, {"size_mode": "world", "world_size": 1.0}):
            c, d, _ = render(renderer, pointnpr.PointCloud(positions), dict(params, rasterizer="native"), cam)
            assert not np.any(c[:, 3] > 0) and np.all(d >= BACKGROUND)
    # A point just in front of the camera plane, to the side: its splat lands
    # far outside the frame (huge window coordinates), skipped like compute.
    near = np.array([[0.5, 0.2, -0.1000001], [0.0, 0.0, -5.0]])
    for params in ({"point_size": 32}, {"size_mode": "world", "world_size": 100.0}):
        native = render(renderer, pointnpr.PointCloud(near), dict(params, rasterizer="native"), cam)
        compute = render(renderer, pointnpr.PointCloud(near), dict(params, rasterizer="compute"), cam)
        assert native[0].tobytes() == compute[0].tobytes()
    # An empty cloud.
    c, d, _ = render(renderer, pointnpr.PointCloud(np.zeros((0, 3))), {"rasterizer": "native"}, cam)
    assert not np.any(c[:, 3] > 0)


_CHILD = r"""
import hashlib, sys
sys.path.insert(0, sys.argv[1])
sys.path.insert(0, sys.argv[2])
import numpy as np, pointnpr
from test_rasterizer import terrain, render
c, d, _ = render(pointnpr.Renderer(), terrain(80000, 9), {"point_size": 2.5, "rasterizer": "native",
                 "shading": "diffuse", "density_mode": "constant_on_screen", "queue_level": 0.5})
print(hashlib.sha256(c.tobytes() + d.tobytes()).hexdigest(), int((c[:, 3] > 0).sum()))
"""


def test_deterministic_bytes_across_processes():
    build = os.path.abspath(os.environ.get("POINTNPR_BUILD_DIR", os.path.join(os.path.dirname(__file__), "..", "..",
                                                                            "build")))
    here = os.path.dirname(os.path.abspath(__file__))
    runs = [subprocess.run([sys.executable, "-c", _CHILD, build, here], capture_output=True, text=True, check=True,
                           timeout=300).stdout.split() for _ in range(2)]
    assert runs[0] == runs[1]
    assert int(runs[0][1]) > 5000
