"""Other marks read a Gaussian splat's scales and opacity (issue 42): brush
splats and points sized by each splat's footprint (size_mode splat: 2 sqrt
of the product of its two largest scales), brush splats' alpha weighed by
the splat's opacity (opacity_weight), points, stipples and feature strokes
drawn with the splat's opacity as their chance and hatching's strokes with
it as their odds (opacity_draws); GL and native agree on each."""
import os

import numpy as np
import pytest

import pointnpr
from test_rasterizer import assert_agree

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PLAYBOT = os.path.join(ROOT, "tests", "data", "io", "gaussians", "playbot_lod3.spz")
SIZE = 128


def _splats(scale_of, opacity_of):
    """Flat splats on a grid on the plane z = -5, facing the camera (their
    third scale the thinnest), with scales and opacities per point."""
    g = np.arange(-1.0, 1.0001, 0.25)
    X, Y = np.meshgrid(g, g)
    n = X.size
    means = np.column_stack([X.ravel(), Y.ravel(), np.full(n, -5.0)])
    s = np.asarray([scale_of(i) for i in range(n)], np.float32)
    scales = np.column_stack([s, 0.5 * s, np.full(n, 1e-4, np.float32)])
    q = np.tile(np.asarray([1.0, 0.0, 0.0, 0.0], np.float32), (n, 1))
    opacity = np.asarray([opacity_of(i) for i in range(n)], np.float32)
    cloud = pointnpr.PointCloud(means, opacity=opacity, scales=scales, rotations=q,
                                sh=np.full((n, 3), 1.0, np.float32), sh_degree=0)
    return cloud, scales, opacity


def _ortho():
    return pointnpr.Camera.orthographic(np.eye(4), ortho_scale=3.0, clip_start=0.1, clip_end=100.0, width=SIZE,
                                        height=SIZE)


def _render(renderer, mark, params, cloud, cam=None, width=SIZE, height=SIZE, **kw):
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=(mark, params)), [(cloud, np.eye(4))])
    return renderer.render(scene, cam or _ortho(), width, height, background=(0, 0, 0, 0), **kw)


def _footprint(scales):
    s = np.sort(np.asarray(scales, np.float64), axis=1)
    return 2.0 * np.sqrt(s[:, 2] * s[:, 1])


@pytest.mark.parametrize("rasterizer", ["gl", "native"])
def test_brush_size_is_each_splat_s_footprint(renderer, rasterizer):
    cloud, scales, _ = _splats(lambda i: 0.02 + 0.004 * (i % 7), lambda i: 1.0)
    params = {"size_mode": "splat", "size_scale": 1.0, "max_radius": 64.0, "blending": "none",
              "rasterizer": rasterizer}
    r = _render(renderer, "brush_splats", params, cloud, capture_marks=True)
    ids = np.asarray(r.marks["point_id"])
    assert len(ids) == len(scales)
    # The captured length is the brush's side: 2 radius along its tangent.
    np.testing.assert_allclose(np.asarray(r.marks["length"]), 2.0 * _footprint(scales)[ids], rtol=1e-5)
    # And the pictures follow: the larger splats cover more pixels.
    alpha = np.asarray(r.color)[..., 3]
    assert (alpha > 0).sum() > 0
    world = _render(renderer, "brush_splats", dict(params, size_mode="world", world_radius=0.02), cloud)
    assert not np.array_equal(np.asarray(world.color), np.asarray(r.color))


@pytest.mark.parametrize("rasterizer", ["gl", "native"])
def test_brush_alpha_is_weighed_by_the_splat_s_opacity(renderer, rasterizer):
    # Every other splat at opacity 0.25; blending none, one splat per pixel:
    # the pixel's coverage is its brush's alpha.
    cloud, scales, opacity = _splats(lambda i: 0.03, lambda i: 1.0 if i % 2 == 0 else 0.25)
    params = {"size_mode": "splat", "size_scale": 1.0, "max_radius": 64.0, "blending": "none",
              "rasterizer": rasterizer}
    plain = _render(renderer, "brush_splats", params, cloud, capture_marks=True)
    weighed = _render(renderer, "brush_splats", dict(params, opacity_weight=True), cloud, capture_marks=True)
    ids = np.asarray(weighed.marks["point_id"])
    np.testing.assert_allclose(np.asarray(weighed.marks["color"])[:, 3], opacity[ids], rtol=1e-6)
    a, b = np.asarray(plain.color)[..., 3], np.asarray(weighed.color)[..., 3]
    # Each pixel's splat: the nearest on the grid (0.25 apart, brushes 0.085
    # wide; the grid's parity pattern is symmetric about 0, so the image's
    # row order does not matter).
    centre = (np.arange(SIZE) + 0.5) * 3.0 / SIZE - 1.5
    cell = np.clip(np.rint((centre + 1.0) / 0.25), 0, 8).astype(int)
    faint = ((cell[:, None] * 9 + cell[None, :]) % 2 == 1)
    drawn = a > 0
    assert (drawn & faint).sum() > 100 and (drawn & ~faint).sum() > 100
    np.testing.assert_array_equal(b[~faint], a[~faint])
    # A faint splat's coverage: a quarter of its brush's, or none under the cut.
    kept = faint & (0.25 * a >= 1.0 / 255.0)
    np.testing.assert_allclose(b[kept], 0.25 * a[kept], rtol=1e-5)
    assert (b[faint & ~kept] == 0).all() and (faint & ~kept & drawn).sum() > 0
    # Plain points are weighed by 1: the same image as without the weight.
    points = pointnpr.PointCloud(np.asarray([[0.0, 0.0, -5.0], [0.2, 0.1, -5.0], [-0.3, 0.2, -5.0]]))
    p1 = _render(renderer, "brush_splats", dict(params, size_mode="world"), points)
    p2 = _render(renderer, "brush_splats", dict(params, size_mode="world", opacity_weight=True), points)
    assert np.array_equal(np.asarray(p1.color), np.asarray(p2.color))


@pytest.fixture(scope="module")
def playbot():
    return pointnpr.read(PLAYBOT).to_cloud()


def _playbot_camera(width=200, height=150):
    d = pointnpr.read(PLAYBOT)
    c = d.positions.mean(0)
    return pointnpr.Camera.perspective(pointnpr.look_at(tuple(c + np.asarray([1.6, 0.5, -2.0])), tuple(c)),
                                       lens=30.0, clip_start=0.1, clip_end=100.0, width=width, height=height)


@pytest.mark.parametrize("params", [{"size_mode": "splat"}, {"size_mode": "splat", "opacity_weight": True},
                                    {"opacity_weight": True, "layers": "two", "blending": "none"}])
def test_brush_splats_on_a_capture_native_draws_the_gl_image(renderer, playbot, params):
    cam = _playbot_camera()
    gl, native = (_render(renderer, "brush_splats", dict(params, rasterizer=r, tile_invariant=True), playbot, cam,
                          200, 150) for r in ("gl", "native"))
    a, b = np.asarray(gl.color), np.asarray(native.color)
    covered = a[..., 3] > 0
    assert covered.mean() > 0.1
    assert ((b[..., 3] > 0) != covered).mean() <= 0.002
    assert (np.abs(a - b).max(axis=-1) > 2.0 / 255.0).mean() <= 0.01
    base = _render(renderer, "brush_splats", {"rasterizer": "native", "tile_invariant": True}, playbot, cam, 200, 150)
    assert not np.array_equal(np.asarray(base.color), b)  # the splats' data changed the picture


def test_points_are_sized_by_each_splat_s_footprint(renderer):
    cloud, scales, _ = _splats(lambda i: 0.01 + 0.003 * (i % 5), lambda i: 1.0)
    # One point per grid cell; a splat's disc is 2 x 2 sqrt(s1 s2) across.
    px_per_unit = SIZE / 3.0
    d = 2.0 * _footprint(scales) * px_per_unit
    for rasterizer in ("compute", "native", "gl_points"):
        r = _render(renderer, "points", {"size_mode": "splat", "rasterizer": rasterizer}, cloud)
        covered = int((np.asarray(r.color)[..., 3] > 0).sum())
        expected = float(np.sum(np.pi * (d / 2) ** 2))
        assert abs(covered - expected) < 0.15 * expected, (rasterizer, covered, expected)
    world = _render(renderer, "points", {"size_mode": "world", "world_size": 0.05}, cloud)
    assert (np.asarray(world.color)[..., 3] > 0).sum() != covered


def test_points_are_drawn_with_the_splat_s_opacity_as_their_chance(renderer):
    n = 4000
    means, opacity, cloud = _plane_of_two_opacities(n, seed=3, scale=0.001)
    images = {}
    for rasterizer in ("compute", "native", "gl_points"):
        r = _render(renderer, "points", {"point_size": 1, "opacity_draws": True, "rasterizer": rasterizer}, cloud)
        images[rasterizer] = r
    full = _render(renderer, "points", {"point_size": 1}, cloud)
    cov = lambda r: np.asarray(r.color)[..., 3] > 0  # noqa: E731
    left, right = slice(0, SIZE // 2 - 1), slice(SIZE // 2 + 1, SIZE)
    f = cov(full)
    for name, r in images.items():
        c = cov(r)
        share_left, share_right = c[:, left].sum() / f[:, left].sum(), c[:, right].sum() / f[:, right].sum()
        assert abs(share_left - 0.2) < 0.05 and abs(share_right - 0.9) < 0.05, (name, share_left, share_right)
    # The same points drawn: compute and native agree as they do without it.
    as_rows = lambda r: (np.asarray(r.color).reshape(-1, 4), np.asarray(r.depth).ravel(), r)  # noqa: E731
    assert_agree(as_rows(images["native"]), as_rows(images["compute"]), min_covered=500)
    # Plain points are all drawn.
    plain = pointnpr.PointCloud(means)
    a = _render(renderer, "points", {"point_size": 1, "opacity_draws": True}, plain)
    b = _render(renderer, "points", {"point_size": 1}, plain)
    assert np.array_equal(np.asarray(a.color), np.asarray(b.color))


def test_hatching_strokes_are_drawn_with_the_splat_s_opacity_as_their_odds(renderer, playbot):
    # The odds of a splat's strokes times its opacity: the strokes drawn
    # are those of before whose id's draw lies under the scaled odds, the
    # same on both backends.
    cam = _playbot_camera()
    opacity = np.asarray(pointnpr.read(PLAYBOT).attributes["opacity"], np.float64)
    base = {"density": 1.0, "stroke_coverage": 0.0}
    runs = {}
    for rasterizer in ("gl", "native"):
        for weighed in (False, True):
            r = _render(renderer, "hatching", dict(base, rasterizer=rasterizer, opacity_draws=weighed), playbot, cam,
                        200, 150, capture_marks=True)
            runs[rasterizer, weighed] = r
    for rasterizer in ("gl", "native"):
        full = np.asarray(runs[rasterizer, False].marks["point_id"])
        kept = np.asarray(runs[rasterizer, True].marks["point_id"])
        assert set(kept) < set(full)
        # The share kept is the mean opacity of the splats that drew (the
        # capture's splats are indexed by their file order: point_id).
        expected = opacity[full].mean()
        assert abs(len(kept) / len(full) - expected) < 0.03, (rasterizer, len(kept) / len(full), expected)
        assert opacity[kept].mean() > opacity[np.setdiff1d(full, kept)].mean() + 0.2
    assert np.array_equal(np.asarray(runs["gl", True].marks["point_id"]), np.asarray(runs["native", True].marks["point_id"]))
    assert runs["gl", True].stats["strokes_drawn"] == runs["native", True].stats["strokes_drawn"]


def _plane_of_two_opacities(n=8000, seed=5, scale=0.01):
    """Splats scattered over the plane z = -5 facing the camera: opacity 0.2
    left of x = 0, 0.9 right of it."""
    rng = np.random.default_rng(seed)
    means = np.column_stack([rng.uniform(-1.4, 1.4, n), rng.uniform(-1.4, 1.4, n), np.full(n, -5.0)])
    opacity = np.where(means[:, 0] < 0, 0.2, 0.9).astype(np.float32)
    cloud = pointnpr.PointCloud(means, opacity=opacity, scales=np.full((n, 3), scale, np.float32),
                                rotations=np.tile(np.float32([1, 0, 0, 0]), (n, 1)),
                                sh=np.full((n, 3), 1.0, np.float32), sh_degree=0)
    return means, opacity, cloud


@pytest.mark.parametrize("mark, params", [("stipples", {"diffuse": False}), ("feature_strokes", {"tone": 0.0, "dither": 1.0})])
def test_stipples_and_feature_strokes_are_drawn_with_the_splat_s_opacity_as_their_chance(renderer, mark, params):
    # The opacities are computed only for a style that draws by them.
    assert "splat_opacity" in pointnpr.Style(mark=(mark, dict(params, opacity_draws=True))).attributes
    assert "splat_opacity" not in pointnpr.Style(mark=(mark, params)).attributes
    means, opacity, cloud = _plane_of_two_opacities()
    ids = {}
    for rasterizer in ("gl", "native"):
        for draws in (False, True):
            r = _render(renderer, mark, dict(params, rasterizer=rasterizer, opacity_draws=draws), cloud,
                        capture_marks=True)
            ids[rasterizer, draws] = np.sort(np.asarray(r.marks["point_id"]))
    for rasterizer in ("gl", "native"):
        full, kept = ids[rasterizer, False], ids[rasterizer, True]
        assert set(kept) < set(full)
        for level in (0.2, 0.9):
            of_level = full[opacity[full] == np.float32(level)]
            assert len(of_level) > 1000, (rasterizer, len(of_level))
            share = np.isin(of_level, kept).mean()
            assert abs(share - level) < 0.05, (rasterizer, level, share)
    # GL and native draw the same splats.
    assert np.array_equal(ids["gl", True], ids["native", True])
    # Plain points are all drawn.
    plain = pointnpr.PointCloud(means)
    a, b = (_render(renderer, mark, dict(params, opacity_draws=draws), plain, capture_marks=True) for draws in (True, False))
    assert np.array_equal(np.sort(np.asarray(a.marks["point_id"])), np.sort(np.asarray(b.marks["point_id"])))
