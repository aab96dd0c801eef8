"""The gaussians mark (cpp/marks/gaussians/): a splat capture drawn as the
3DGS reference rasterizer draws it, checked against an independent numpy
implementation of the paper's equations (tests/python/gaussian_reference.py)
on a real capture and on synthetic splats, against closed forms for one
Gaussian (its footprint's integral and second moments, its SH colour), at
the near plane and with degenerate scales; the same bytes in another
process with one thread; floaters dropped by their thresholds."""
import hashlib
import os

import numpy as np
import pytest

import pointnpr
from conftest import one_thread_in_another_process
from gaussian_reference import (perspective, premultiplied_srgb, psnr, quat_matrix, random_splats, render,
                                sh_color, view_matrix)

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PLAYBOT = os.path.join(ROOT, "tests", "data", "io", "gaussians", "playbot_lod3.spz")
W, H = 200, 150


def _cloud(means, quats, scales, opacity, sh, degree):
    n = len(means)
    return pointnpr.PointCloud(np.asarray(means, np.float64), opacity=np.asarray(opacity, np.float32),
                               scales=np.asarray(scales, np.float32), rotations=np.asarray(quats, np.float32),
                               sh=np.asarray(sh, np.float32).reshape(n, -1), sh_degree=degree)


def _render(renderer, cloud, view, proj, params=None, width=W, height=H):
    scene = pointnpr.Scene()
    scene.add_segment("splats", pointnpr.Style(mark=("gaussians", params or {})), [(cloud, np.eye(4))])
    return renderer.render(scene, pointnpr.Camera.from_matrices(view, proj), width, height, background=(0, 0, 0, 0))


@pytest.fixture(scope="module")
def playbot():
    return pointnpr.read(PLAYBOT)


def _playbot_camera(d, offset=(1.6, 0.5, -2.0)):
    c = d.positions.mean(0)
    return view_matrix(c + np.asarray(offset), c, up=(0, 1, 0)), perspective(1.6, 1.6 * W / H, 0.1, 100.0)


def test_a_real_capture_matches_the_reference_rasterizer(renderer, playbot):
    d = playbot
    assert d.metadata["sh_degree"] == 2 and d.num_points == 31000
    A = d.attributes
    for offset in ((1.6, 0.5, -2.0), (-2.2, -0.4, 1.0)):
        view, proj = _playbot_camera(d, offset)
        res = _render(renderer, d.to_cloud(), view, proj)
        mine, a = premultiplied_srgb(res.color)
        ref, ra = render(d.positions, A["rotations"].astype(float), A["scales"].astype(float),
                         A["opacity"].astype(float), A["sh"].reshape(d.num_points, -1, 3).astype(float), 2,
                         view, proj, W, H)
        assert (ra > 0.01).mean() > 0.2  # the capture fills the frame
        assert psnr(mine, ref) >= 40.0, psnr(mine, ref)
        assert psnr(a, ra) >= 40.0
        assert res.stats["gaussians_drawn"] > 25000


@pytest.mark.parametrize("degree", [0, 1, 2, 3])
def test_synthetic_splats_match_the_reference_rasterizer(renderer, degree):
    means, q, scales, opacity, sh = random_splats(400, degree, seed=degree + 10)
    sh[:, 1:] *= 0.5  # captures' view-dependent bands are small beside their DC
    view, proj = view_matrix((0.4, -3.2, 0.9), (0, 0, 0)), perspective(1.8, 1.8 * W / H, 0.1, 100.0)
    res = _render(renderer, _cloud(means, q, scales, opacity, sh, degree), view, proj)
    mine, a = premultiplied_srgb(res.color)
    ref, ra = render(means, q, scales, opacity, sh, degree, view, proj, W, H)
    assert (ra > 0.01).mean() > 0.3
    # Where a pixel's premultiplied colour exceeds its opacity (a colour
    # above 1 per unit of coverage), the mark's straight-alpha image clamps
    # it as every segment's colour is clamped; everywhere else, the paper.
    fits = ~(ref > ra[..., None] + 1e-6).any(-1)
    assert fits.mean() > 0.95
    assert psnr(mine[fits], ref[fits]) >= 40.0, psnr(mine[fits], ref[fits])
    assert psnr(a, ra) >= 40.0


def _one(renderer, quat, scale, opacity=0.9, mean=(0.0, 0.0, 0.0), sh=None, degree=0, params=None, eye=(0, -4, 0)):
    sh = np.zeros((1, (degree + 1) ** 2, 3)) if sh is None else sh
    view, proj = view_matrix(eye, (0, 0, 0)), perspective(1.5, 1.5 * W / H, 0.1, 100.0)
    res = _render(renderer, _cloud([mean], [quat], [scale], [opacity], sh, degree), view, proj, params)
    return res, view, proj


def test_one_anisotropic_rotated_gaussian_has_the_footprint_of_its_projected_covariance(renderer):
    angle = np.radians(35.0)
    quat = np.array([np.cos(angle / 2), 0.0, np.sin(angle / 2), 0.0])  # about the view axis (y)
    quat = quat / np.linalg.norm(quat)
    scale = np.array([0.35, 0.05, 0.12])
    opacity = 0.6  # below the 0.99 clamp everywhere
    res, view, proj = _one(renderer, quat, scale, opacity)
    alpha = np.asarray(res.color)[..., 3].astype(np.float64)
    # The analytic projection (orthographic limit is not exact: use the paper's Jacobian at the centre).
    fx, fy = 0.5 * W * proj[0, 0], 0.5 * H * proj[1, 1]
    rs = quat_matrix(quat) @ np.diag(scale)
    cov3 = view[:3, :3] @ rs @ rs.T @ view[:3, :3].T
    depth = 4.0
    jac = np.array([[fx / depth, 0, 0], [0, fy / depth, 0]])
    cov2 = jac @ cov3 @ jac.T + 0.3 * np.eye(2)
    integral = opacity * 2.0 * np.pi * np.sqrt(np.linalg.det(cov2))  # of o * exp(-d^T S^-1 d / 2)
    assert abs(alpha.sum() / integral - 1.0) < 0.02, (alpha.sum(), integral)
    ys, xs = np.mgrid[0:H, 0:W] + 0.5
    m = alpha.sum()
    cx, cy = (alpha * xs).sum() / m, (alpha * ys).sum() / m
    assert abs(cx - W / 2) < 0.05 and abs(cy - H / 2) < 0.05
    moments = np.array([[(alpha * (xs - cx) ** 2).sum(), (alpha * (xs - cx) * (ys - cy)).sum()],
                        [(alpha * (xs - cx) * (ys - cy)).sum(), (alpha * (ys - cy) ** 2).sum()]]) / m
    # The 3-sigma square and the 1/255 cut trim the tails a little.
    assert np.allclose(moments, cov2, rtol=0.06, atol=0.3), (moments, cov2)
    assert abs(moments[0, 1]) > 5.0  # rotated: the axes are not the screen's
    # The peak: opacity, in the centre pixel's neighbourhood.
    assert abs(alpha.max() - opacity) < 0.01


@pytest.mark.parametrize("degree", [1, 2, 3])
def test_the_view_dependent_colour_is_the_sh_evaluated_from_the_camera(renderer, degree):
    rng = np.random.default_rng(degree)
    sh = rng.normal(0.0, 0.25, (1, (degree + 1) ** 2, 3))
    sh[0, 0] = (0.1, -0.2, 0.3)
    for eye in ((0, -4, 0), (2.5, -3, 1.5), (-3, 1, -2)):
        for used in range(degree + 1):
            res, view, proj = _one(renderer, (1, 0, 0, 0), (0.3, 0.3, 0.3), 0.99, sh=sh, degree=degree,
                                   params={"sh_degree": used}, eye=eye)
            c = np.asarray(res.color, np.float64)
            centre = c[H // 2, W // 2]
            straight = centre[:3] / centre[3]
            expected = np.clip(sh_color(sh[0], used, -np.asarray(eye, float) / np.linalg.norm(eye)), 0, 1)
            lin = np.where(expected <= 0.04045, expected / 12.92, ((expected + 0.055) / 1.055) ** 2.4)
            assert np.allclose(straight, lin, atol=2e-5), (eye, used, straight, lin)


def test_near_plane_and_degenerate_scales_draw_nothing_wrong(renderer):
    # Behind the clip start: not drawn; zero and huge scales: finite images.
    view, proj = view_matrix((0, -4, 0), (0, 0, 0)), perspective(1.5, 1.5 * W / H, 0.1, 100.0)
    q, s = np.array([[1.0, 0, 0, 0]] * 2), np.full((2, 3), 0.1)
    both = _render(renderer, _cloud([(0, 0, 0), (0.0, -3.95, 0.0)], q, s, [0.9, 0.9], np.zeros((2, 1, 3)), 0), view, proj)
    alone = _render(renderer, _cloud([(0, 0, 0)], q[:1], s[:1], [0.9], np.zeros((1, 1, 3)), 0), view, proj)
    assert both.stats["gaussians_culled"] == 1 and both.stats["gaussians_drawn"] == 1
    assert np.array_equal(np.asarray(both.color), np.asarray(alone.color))
    flat, _, _ = _one(renderer, (1, 0, 0, 0), (0.2, 0.0, 0.2))  # a disc seen face on
    assert np.asarray(flat.color)[..., 3].max() > 0.5
    edge, _, _ = _one(renderer, (1, 0, 0, 0), (0.0, 0.2, 0.0))  # a needle seen end on: the 0.3 px dilation alone
    a = np.asarray(edge.color)[..., 3]
    # sigma^2 = 0.3 px^2: 0.9 exp(-r^2 / 0.6) >= 1/255 within r = 1.81 px of
    # the centre (a pixel corner here): 4 pixel centres at 0.71 px, 8 at 1.58.
    assert np.isfinite(np.asarray(edge.color)).all() and (a > 0).sum() == 12
    point, _, _ = _one(renderer, (0, 0, 0, 0), (0.0, 0.0, 0.0))  # no size, zero quaternion
    assert np.isfinite(np.asarray(point.color)).all()
    huge, _, _ = _one(renderer, (1, 0, 0, 0), (50.0, 50.0, 50.0), params={"max_radius": 64})
    assert np.isfinite(np.asarray(huge.color)).all() and np.asarray(huge.color)[..., 3].max() > 0


def test_depth_is_where_the_opacity_reaches_one_half(renderer):
    # Two splats on the view axis: a faint one in front, an opaque one behind.
    means = np.array([[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]])
    q = np.array([[1.0, 0, 0, 0]] * 2)
    s = np.full((2, 3), 0.3)
    view, proj = view_matrix((0, -4, 0), (0, 0, 0)), perspective(1.5, 1.5 * W / H, 0.1, 100.0)
    cloud = _cloud(means, q, s, [0.3, 0.95], np.zeros((2, 1, 3)), 0)
    depth = np.asarray(_render(renderer, cloud, view, proj).depth)
    assert abs(depth[H // 2, W // 2] - 5.0) < 1e-4  # the faint one alone gives 0.3
    front = np.asarray(_render(renderer, cloud, view, proj, {"depth_alpha": 0.25}).depth)
    assert abs(front[H // 2, W // 2] - 3.0) < 1e-4


def test_floaters_are_dropped_by_opacity_scale_and_isolation(renderer, playbot):
    view, proj = _playbot_camera(playbot)
    cloud = playbot.to_cloud()
    base = _render(renderer, cloud, view, proj)
    A = playbot.attributes
    for params, expected in (({"min_opacity": 0.1}, int((A["opacity"] < 0.1).sum())),
                             ({"max_scale": 0.05}, int((A["scales"].max(1) > 0.05).sum()))):
        r = _render(renderer, cloud, view, proj, params)
        assert r.stats["gaussians_floaters"] == expected > 0, params
        assert not np.array_equal(np.asarray(r.color), np.asarray(base.color))
    lone = _render(renderer, cloud, view, proj, {"isolation": 4.0})
    assert 0 < lone.stats["gaussians_floaters"] < 0.05 * playbot.num_points
    assert base.stats["gaussians_floaters"] == 0


def test_a_frame_drawn_in_tiles_is_the_bytes_of_the_whole_frame(renderer, playbot):
    view, proj = _playbot_camera(playbot)
    cam = pointnpr.Camera.from_matrices(view, proj)
    scene = pointnpr.Scene()
    scene.add_segment("splats", pointnpr.Style(mark=("gaussians", {"max_radius": 24})), [(playbot.to_cloud(), np.eye(4))])
    whole = renderer.render(scene, cam, W, H, background=(0, 0, 0, 0))
    tiled = renderer.render(scene, cam, W, H, background=(0, 0, 0, 0), tile_size=64)
    assert whole.stats["tiles"] == 1 and tiled.stats["tiles"] > 1
    assert np.asarray(whole.color)[..., 3].mean() > 0.2
    for name in ("color", "depth"):
        assert np.asarray(getattr(whole, name)).tobytes() == np.asarray(getattr(tiled, name)).tobytes(), name


def test_filters_take_the_faithful_render_as_their_input(renderer, playbot):
    view, proj = _playbot_camera(playbot)
    cam = pointnpr.Camera.from_matrices(view, proj)
    plain, painted = pointnpr.Scene(), pointnpr.Scene()
    plain.add_segment("s", pointnpr.Style(mark=("gaussians", {})), [(playbot.to_cloud(), np.eye(4))])
    painted.add_segment("s", pointnpr.Style(mark=("gaussians", {}), filters=[("watercolor", {})]),
                        [(playbot.to_cloud(), np.eye(4))])
    a = np.asarray(renderer.render(plain, cam, W, H, background=(1, 1, 1, 1)).color)
    b = np.asarray(renderer.render(painted, cam, W, H, background=(1, 1, 1, 1)).color)
    assert np.isfinite(b).all()
    changed = np.abs(a - b).max(axis=-1) > 0.02
    assert 0.2 < changed.mean()  # the capture, painted over
    assert np.abs(a[..., :3].mean() - b[..., :3].mean()) < 0.2  # its colours, not another picture


def render_bytes(renderer):
    """The playbot capture's frame as a hash of its bytes (another process)."""
    d = pointnpr.read(PLAYBOT)
    view, proj = _playbot_camera(d)
    r = _render(renderer, d.to_cloud(), view, proj, {"isolation": 6.0})
    return hashlib.sha256(np.ascontiguousarray(r.color).tobytes() + np.ascontiguousarray(r.depth).tobytes()).hexdigest()


def test_the_same_bytes_in_another_process_with_one_thread(renderer):
    assert render_bytes(renderer) == one_thread_in_another_process("test_marks_gaussians", "render_bytes")


def test_plain_points_are_not_drawn_and_said_so(renderer):
    cloud = pointnpr.PointCloud(np.zeros((3, 3)))
    view, proj = view_matrix((0, -4, 0), (0, 0, 0)), perspective(1.5, 1.5 * W / H, 0.1, 100.0)
    r = _render(renderer, cloud, view, proj)
    assert np.asarray(r.color)[..., 3].max() == 0.0
    assert any("no Gaussian splat parameters" in w for w in r.warnings)


def test_a_splat_capture_s_normals_are_its_splats_shortest_axes_oriented(renderer):
    # Flat splats on two parallel planes, turned at random about their
    # normal (+-z): the normals every mark reads are +-z, consistently
    # oriented, where a neighbourhood fit of the centres would see two planes
    # 2 cm apart as one noisy surface.
    rng = np.random.default_rng(5)
    n = 4000
    means = np.column_stack([rng.uniform(-1, 1, n), rng.uniform(-1, 1, n), rng.choice([0.0, 0.02], n)])
    angle = rng.uniform(0, 2 * np.pi, n)
    q = np.column_stack([np.cos(angle / 2), np.zeros(n), np.zeros(n), np.sin(angle / 2)])
    flip = rng.random(n) < 0.5  # half of them upside down: q and a half turn about x
    q[flip] = np.column_stack([np.zeros(flip.sum()), np.cos(angle[flip] / 2), np.sin(angle[flip] / 2), np.zeros(flip.sum())])
    scales = np.column_stack([rng.uniform(0.02, 0.05, n), rng.uniform(0.02, 0.05, n), np.full(n, 1e-4)])
    cloud = _cloud(means, q, scales, np.full(n, 0.9), np.zeros((n, 1, 3)), 0)
    normals = np.asarray(pointnpr.estimate_normals(cloud, k=16))
    assert np.abs(np.abs(normals[:, 2]) - 1.0).max() < 1e-5
    assert (normals[:, 2] > 0).all()  # one orientation: the consistent propagation's (+z at the top)


def test_the_gl_compute_pass_composites_what_the_native_path_does(renderer, playbot):
    # Same records in the same order; GL's exp may differ from the C++
    # library's in the last bits, so a tolerance rather than bytes.
    view, proj = _playbot_camera(playbot)
    cloud = playbot.to_cloud()
    native = _render(renderer, cloud, view, proj, {"rasterizer": "native"})
    gl = _render(renderer, cloud, view, proj, {"rasterizer": "compute"})
    a, b = np.asarray(native.color, np.float64), np.asarray(gl.color, np.float64)
    assert (a[..., 3] > 0.01).mean() > 0.2
    assert np.abs(a - b).max() < 1e-3
    da, db = np.asarray(native.depth), np.asarray(gl.depth)
    assert np.array_equal(da == 1e10, db == 1e10) and np.allclose(da, db, rtol=1e-5)
    mine, alpha = premultiplied_srgb(gl.color)
    A = playbot.attributes
    ref, ra = render(playbot.positions, A["rotations"].astype(float), A["scales"].astype(float),
                     A["opacity"].astype(float), A["sh"].reshape(playbot.num_points, -1, 3).astype(float), 2,
                     view, proj, W, H)
    assert psnr(mine, ref) >= 40.0 and psnr(alpha, ra) >= 40.0
    # auto: native where GL is software, the compute pass on a GPU.
    auto = _render(renderer, cloud, view, proj)
    software = bool(pointnpr.gl_info()["software"])
    assert np.array_equal(np.asarray(auto.color), np.asarray(native.color if software else gl.color))


def test_brush_splats_lie_in_each_splat_s_own_frame(renderer):
    # Flat splats on the plane z = -5 facing an orthographic camera, each
    # turned by its own angle: seed 004's covariance frame takes the
    # splat's longest axis as the brush direction, its shortest as normal.
    rng = np.random.default_rng(8)
    g = np.arange(-1.0, 1.0001, 0.05)
    X, Y = np.meshgrid(g, g)
    n = X.size
    means = np.column_stack([X.ravel(), Y.ravel(), np.full(n, -5.0)])
    angle = rng.uniform(0, np.pi, n)
    q = np.column_stack([np.cos(angle / 2), np.zeros(n), np.zeros(n), np.sin(angle / 2)])
    scales = np.column_stack([np.full(n, 0.03), np.full(n, 0.01), np.full(n, 1e-4)])
    cloud = _cloud(means, q, scales, np.full(n, 0.9), np.zeros((n, 1, 3)), 0)
    cam = pointnpr.Camera.orthographic(np.eye(4), ortho_scale=3.0, clip_start=0.1, clip_end=100.0, width=96, height=96)
    for rasterizer in ("gl", "native"):
        scene = pointnpr.Scene()
        scene.add_segment("s", pointnpr.Style(mark=("brush_splats", {"tangent_frame": "covariance",
                                                                      "rasterizer": rasterizer})), [(cloud, np.eye(4))])
        m = renderer.render(scene, cam, 96, 96, capture_marks=True).marks
        ids = np.asarray(m["point_id"])
        assert len(ids) > 0.9 * n
        axis = np.column_stack([np.cos(angle), np.sin(angle), np.zeros(n)])[ids]
        along = np.abs((np.asarray(m["direction"], np.float64) * axis).sum(1))
        assert along.min() > 0.99, rasterizer
        assert np.abs(np.asarray(m["normal"], np.float64)[:, 2]).min() > 0.999


def test_min_coverage_leaves_the_faint_haze_empty_and_the_rest_unchanged(renderer, playbot):
    view, proj = _playbot_camera(playbot)
    cloud = playbot.to_cloud()
    for rasterizer in ("native", "compute"):
        full = _render(renderer, cloud, view, proj, {"rasterizer": rasterizer})
        cut = _render(renderer, cloud, view, proj, {"rasterizer": rasterizer, "min_coverage": 0.3})
        a, b = np.asarray(full.color), np.asarray(cut.color)
        faint = (a[..., 3] > 0) & (a[..., 3] < 0.3)
        assert faint.mean() > 0.01  # a capture's haze
        assert (b[faint] == 0).all() and (np.asarray(cut.depth)[faint] == 1e10).all()
        assert np.array_equal(a[~faint], b[~faint])


def test_an_antialiased_capture_scales_opacity_by_the_filter_compensation(renderer, tmp_path):
    # SPZ's flag 0x1 (Mip-Splatting): opacity x sqrt(det S / det(S + 0.3 I)).
    from gaussian_reference import write_spz
    quat, scale, opacity = np.array([1.0, 0, 0, 0]), np.array([0.004, 0.004, 0.004]), 0.8
    for flags in (0, 1):
        path = str(tmp_path / f"one_{flags}.spz")
        write_spz(path, np.zeros((1, 3)), quat[None], scale[None], np.array([opacity]), np.zeros((1, 1, 3)), 0,
                  flags=flags)
        d = pointnpr.read(path)
        assert d.metadata["antialiased"] == flags
        view, proj = view_matrix((0, -4, 0), (0, 0, 0)), perspective(1.5, 1.5 * W / H, 0.1, 100.0)
        alpha = np.asarray(_render(renderer, d.to_cloud(), view, proj).color)[..., 3]
        o = float(d.attributes["opacity"][0])
        s = float(d.attributes["scales"][0, 0])
        sigma2 = (0.5 * W * proj[0, 0] * s / 4.0) ** 2  # the splat's variance on screen, px^2
        factor = np.sqrt(sigma2 * sigma2 / (sigma2 + 0.3) ** 2) if flags else 1.0
        # The centre pixel sits half a pixel off the splat's centre on each axis.
        expected = o * factor * np.exp(-0.5 * 0.5 / (sigma2 + 0.3))
        assert abs(alpha.max() - expected) < 1e-3, (flags, alpha.max(), expected)
