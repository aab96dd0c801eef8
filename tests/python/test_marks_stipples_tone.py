"""The stipples mark's tone and its level from the spacing (issue 39): seed
003 draws a dot per visible point and hides one point per light cell of one
LEVEL, so its ink follows how densely the scan's points lie on screen and
in space, not the light. With `tone` the dots' density is the tone's at any
density and output size; with `level_scale` spacing each point's cells are
as wide as its own spacing, so the lit share follows N.L on dense and
sparse parts alike. Both backends."""
import numpy as np
import pytest

import pointnpr
from test_marks import camera, render, sphere
from test_marks_stipples import CAMERA_LIGHT, _kept_by_light_angle, light


@pytest.fixture(params=["gl", "native"])
def implementation(request):
    return request.param


def kept_ids(renderer, params, cloud, n):
    r = render(renderer, pointnpr.Style(mark=("stipples", params)), [cloud])
    kept = np.zeros(n, bool)
    kept[r.marks["point_id"]] = True
    return kept


def lit_share_by_angle(renderer, n, params):
    """Kept share of the visible points of an n-point sphere in bins of N.L."""
    pos, normals = sphere(n)
    c = pointnpr.PointCloud(pos)
    visible = kept_ids(renderer, dict(params, diffuse=False), c, n)
    kept = kept_ids(renderer, dict(params, **CAMERA_LIGHT), c, n)
    return _kept_by_light_angle(kept, visible, normals, light(60.0), np.linspace(-0.2, 1.0, 7))


def test_the_level_from_the_spacing_lights_dense_and_sparse_scans_alike(renderer, implementation):
    # Spheres of 4,000 and 32,000 points (8x the density). Measured with the
    # level from the spacing: 0.91 0.57 0.32 0.12 0.02 0.01 and 0.95 0.67
    # 0.31 0.09 0.05 0.03 (within 0.10); with one LEVEL for both, 0.22 0.01
    # 0 ... and 0.55 0.27 0.01 0 ...: the sparse one all but white.
    base = dict(tone=0.0, rasterizer=implementation)
    spacing = {n: lit_share_by_angle(renderer, n, dict(base, level_scale="spacing")) for n in (4000, 32000)}
    absolute = {n: lit_share_by_angle(renderer, n, dict(base, level_scale="absolute")) for n in (4000, 32000)}
    assert np.abs(spacing[4000] - spacing[32000]).max() < 0.15, spacing
    assert np.abs(absolute[4000] - absolute[32000]).max() > 0.25, absolute
    for curve in spacing.values():  # still shading: dense where turned away, thin where lit
        assert np.all(np.diff(curve) <= 0.02) and curve[0] > 0.85 and curve[-1] < 0.1, curve


def flat_wall(n, seed=1):
    rng = np.random.default_rng(seed)
    return pointnpr.PointCloud(np.column_stack([rng.uniform(-1.5, 1.5, n), rng.uniform(-1.2, 1.2, n),
                                                np.full(n, -5.0)]))


def wall_ink(renderer, cloud, params, width, height):
    """Mean ink (1 - luminance over white paper) of the middle of the wall."""
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("stipples", dict(params, diffuse=False))), [(cloud, np.eye(4))])
    img = np.asarray(renderer.render(scene, camera(width=width, height=height), width, height).color)
    return float(1.0 - img[height // 4:3 * height // 4, width // 4:3 * width // 4, :3].mean())


def test_the_tone_keeps_the_ink_at_any_density_and_output_size(renderer, implementation):
    # A wall of 20,000 and of 80,000 points at 320x240 and 640x480. The
    # paper's dots: ink 0.77, 0.34, 0.99, 0.77 (it follows the points per
    # pixel). With tone 0.5: 0.62 in the three where the dots need not grow
    # past 3x, 0.41 where they would (20,000 points at 640x480).
    walls = {n: flat_wall(n) for n in (20000, 80000)}
    sizes = ((320, 240), (640, 480))

    def inks(tone):
        return {(n, w): wall_ink(renderer, walls[n], dict(tone=tone, rasterizer=implementation), w, h)
                for n in walls for w, h in sizes}
    paper, toned, darker = inks(0.0), inks(0.5), inks(0.8)
    assert max(paper.values()) - min(paper.values()) > 0.5, paper
    within = [toned[k] for k in toned if k != (20000, 640)]
    assert max(within) - min(within) < 0.03, toned
    assert 0.45 < min(within) and max(within) < 0.7, toned
    assert toned[(20000, 640)] < min(within)  # the growth's cap: dots of 3 sizes at most
    assert all(darker[k] > toned[k] + 0.15 for k in toned), (toned, darker)


def test_the_tone_draws_a_fixed_subset_of_the_dots_by_the_point_id(renderer, implementation):
    # Where the points crowd, the tone keeps a share of them chosen by their
    # ids: a lower tone keeps a subset of a higher one's dots (the dots stay
    # put as the camera moves and the share changes).
    pos, _ = sphere(32000)
    c = pointnpr.PointCloud(pos)
    kept = {t: kept_ids(renderer, dict(tone=t, diffuse=False, rasterizer=implementation), c, 32000)
            for t in (0.3, 0.6)}
    assert 0 < kept[0.3].sum() < kept[0.6].sum()
    assert np.all(kept[0.6][kept[0.3]])


def test_the_highlight_follows_the_surface_not_the_scan_s_density(renderer, implementation):
    # Two spheres side by side in one segment, of 4,000 and 32,000 points.
    # The specular measure (area per point seen from eye and light) is 8x
    # larger on the sparse one everywhere: taken as it is, its whole lit
    # side reads as the highlight and the dense one opens none (of the
    # dense sphere's dots the light keeps, 1.0 stay where N.H >= 0.8 and
    # 0.85 below). Taken per unit of each point's own surface (level_scale
    # spacing), both open it where N.H is high: measured 0.20 and 0.47 of
    # the dots stay there, 0.88 and 0.86 below (LEVEL 8, so the diffuse
    # share leaves dots where the light is high).
    spheres = [sphere(4000, centre=(-1.2, 0.0, -6.0)), sphere(32000, centre=(1.2, 0.0, -6.0))]
    pos = np.vstack([p for p, _ in spheres])
    normals = np.vstack([n for _, n in spheres])
    sparse = np.arange(len(pos)) < 4000
    c = pointnpr.PointCloud(pos)
    base = dict(tone=0.0, tau=0.5, level_scale="spacing", level=8.0, rasterizer=implementation, **CAMERA_LIGHT)
    lit = kept_ids(renderer, dict(base, specular=False), c, len(pos))
    kept = kept_ids(renderer, dict(base, specular=True), c, len(pos))
    to_eye = -pos / np.linalg.norm(pos, axis=1)[:, None]
    half = light(60.0) + to_eye
    high = np.sum(normals * half / np.linalg.norm(half, axis=1)[:, None], axis=1) >= 0.8
    for one in (sparse, ~sparse):
        assert (lit & one & high).sum() >= 10
        assert kept[lit & one & high].mean() < 0.6 and kept[lit & one & ~high].mean() > 0.8, (
            kept[lit & one & high].mean(), kept[lit & one & ~high].mean())
