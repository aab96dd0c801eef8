"""The stipples mark (seed 003): hidden-point removal in image space,
diffuse shading by a light-view min-depth quadtree, specular highlights from
point counts, dots. No normals, no colours: positions and point ids only.

The sphere is the registry tests' (tests/python/test_marks.py): 12000
evenly spaced points (Fibonacci) of radius 1 at 5 units, 320 x 240 pixels,
about 2 px between neighbours on screen. Every decision is deterministic
(hashes of the point id), so the fractions below are exact for this input;
their tolerances are margins over the values measured on this machine.
Every test runs on both implementations of the passes (GL compute shaders
and the native CPU passes), which make the same decisions.
"""
import numpy as np
import pytest

import pointnpr
from test_marks import H, W, render, sphere

N = 12000


@pytest.fixture(scope="module")
def ball():
    pos, normals = sphere(N)
    to_eye = -pos / np.linalg.norm(pos, axis=1)[:, None]
    return pointnpr.PointCloud(pos), pos, normals, to_eye


IMPLEMENTATION = ["auto"]


@pytest.fixture(params=["gl", "native"], autouse=True)
def implementation(request):
    """Every test below on both implementations of the passes."""
    IMPLEMENTATION[0] = request.param
    yield request.param
    IMPLEMENTATION[0] = "auto"


# The paper's mechanism as it describes it: every visible point a dot, one
# LEVEL for the whole segment, a fixed spreading (the tone, the level from
# the spacing and each point's spread are tested on their own: below,
# test_marks_stipples_tone.py and test_marks_stipples_spread.py).
PAPER = dict(tone=0.0, level_scale="absolute", level=7.0, spread_from_spacing=False)


def stipples(**params):
    return pointnpr.Style(mark=("stipples", dict(PAPER, **params, rasterizer=IMPLEMENTATION[0])))


def kept_points(renderer, style, c):
    r = render(renderer, style, [c])
    kept = np.zeros(N, bool)
    kept[r.marks["point_id"]] = True
    assert r.stats["stipples_drawn"] == kept.sum() == len(r.marks["point_id"])  # each point at most once
    return kept, r


def light(elevation):
    """Camera-space light from the right, `elevation` degrees away from the view axis."""
    e = np.radians(elevation)
    return np.array([np.sin(e), 0.0, np.cos(e)])


CAMERA_LIGHT = dict(light_space="camera", light_azimuth=0.0, light_elevation=60.0)


def test_hidden_points_removed_on_a_closed_sphere(renderer, ball):
    c, pos, normals, to_eye = ball
    kept, r = kept_points(renderer, stipples(diffuse=False), c)  # default iterations, offset, resolution
    facing = np.sum(normals * to_eye, axis=1)
    back, front = facing < 0, facing > 0
    # Measured: 0.86 % of the back half kept (all within 6 degrees of the
    # silhouette), 0.50 % of the front lost (the same band).
    assert kept[back].mean() <= 0.01, kept[back].mean()
    assert 1.0 - kept[front].mean() <= 0.01, 1.0 - kept[front].mean()
    assert r.stats["stipples_visible"] == kept.sum()
    # Away from the silhouette the decision is exact.
    assert not kept[facing < -0.1].any() and kept[facing > 0.1].all()


def test_no_iterations_leave_back_points_in_the_holes(renderer, ball):
    # Without spreading, back points show through the gaps between front
    # points (the paper's Fig. 12a): the iterations are what removes them,
    # or each point's own spread (spread_from_spacing) without any.
    c, pos, normals, to_eye = ball
    back = np.sum(normals * to_eye, axis=1) < -0.1
    kept, _ = kept_points(renderer, stipples(diffuse=False, iterations=0, spread_from_spacing=False), c)
    assert kept[back].mean() > 0.3
    kept, _ = kept_points(renderer, stipples(diffuse=False, iterations=0, spread_from_spacing=True), c)
    assert kept[back].mean() < 0.01


def _kept_by_light_angle(kept, visible, normals, l, edges):
    ndl = normals @ l
    out = []
    for a, b in zip(edges[:-1], edges[1:]):
        m = visible & (ndl >= a) & (ndl < b)
        assert m.sum() >= 100, (a, b, m.sum())
        out.append(kept[m].mean())
    return np.array(out)


def test_dot_density_falls_from_the_shadowed_to_the_lit_side(renderer, ball):
    c, pos, normals, to_eye = ball
    visible, _ = kept_points(renderer, stipples(diffuse=False), c)
    kept, _ = kept_points(renderer, stipples(level=6.0, **CAMERA_LIGHT), c)
    edges = np.linspace(-0.8, 1.0, 10)
    fractions = _kept_by_light_angle(kept, visible, normals, light(60.0), edges)
    # Monotonic in n.l within 0.02 (measured: 1.00 1.00 1.00 0.99 0.92 0.83 0.70 0.59 0.46 at level 6).
    assert np.all(np.diff(fractions) <= 0.02), fractions
    assert fractions[:3].min() > 0.97   # turned away from the light: every dot stays (shadow)
    assert fractions[-1] < 0.6          # facing it: thinned
    assert fractions[0] - fractions[-1] > 0.4


def test_raising_level_thins_more_and_fractions_blend(renderer, ball):
    c, pos, normals, to_eye = ball
    drawn = {}
    for level in (4.0, 5.0, 5.25, 5.5, 5.75, 6.0, 7.0):
        kept, _ = kept_points(renderer, stipples(level=level, **CAMERA_LIGHT), c)
        drawn[level] = kept
    counts = [drawn[level].sum() for level in sorted(drawn)]
    assert all(a > b for a, b in zip(counts, counts[1:])), counts
    # A fractional level takes each point's decision from one of the two
    # levels around it: between them, and the finer one's share grows.
    for level in (5.25, 5.5, 5.75):
        kept = drawn[level]
        assert np.all(kept >= drawn[6.0] & drawn[5.0])
        assert np.all(kept <= drawn[6.0] | drawn[5.0])
    only_coarse = drawn[5.0] & ~drawn[6.0]  # dots level 6 hides and level 5 keeps
    shares = [1.0 - drawn[level][only_coarse].mean() for level in (5.25, 5.5, 5.75)]
    n = only_coarse.sum()
    for share, expected in zip(shares, (0.25, 0.5, 0.75)):
        assert abs(share - expected) < 4.0 * np.sqrt(expected * (1 - expected) / n) + 0.01, (shares, n)


def test_a_highlight_opens_where_eye_and_light_meet(renderer, ball):
    c, pos, normals, to_eye = ball
    visible, _ = kept_points(renderer, stipples(diffuse=False), c)
    kept, _ = kept_points(renderer, stipples(diffuse=False, specular=True, tau=0.2, **CAMERA_LIGHT), c)
    half = to_eye + light(60.0)
    half /= np.linalg.norm(half, axis=1)[:, None]
    ndh = np.sum(normals * half, axis=1)
    at_highlight = visible & (ndh > 0.95)
    elsewhere = visible & (ndh < 0.7)
    assert at_highlight.sum() > 100 and elsewhere.sum() > 1000
    # Measured: 39 % kept at the highlight, 98.1 % elsewhere; the few
    # opened elsewhere lie at the lit silhouette (n.v < 0.1), where eye
    # cells cut by the silhouette overestimate the area per point.
    assert kept[at_highlight].mean() < 0.5, kept[at_highlight].mean()
    assert kept[elsewhere].mean() > 0.975, kept[elsewhere].mean()
    facing_eye = np.sum(normals * to_eye, axis=1) > 0.15
    assert kept[elsewhere & facing_eye].mean() > 0.995, kept[elsewhere & facing_eye].mean()
    # The opened dots (off the silhouette) gather around the half-way
    # direction, between the eye's (0, 0, 1) and the light's, 60 degrees apart.
    opened = visible & ~kept & facing_eye
    mean = normals[opened].mean(axis=0)
    mean /= np.linalg.norm(mean)
    centre_half = half[opened].mean(axis=0)
    centre_half /= np.linalg.norm(centre_half)

    def angle(a, b):
        return np.degrees(np.arccos(np.clip(a @ b, -1, 1)))

    assert angle(mean, centre_half) < 10.0, angle(mean, centre_half)
    assert angle(mean, light(60.0)) < 45.0 and angle(mean, np.array([0.0, 0.0, 1.0])) < 45.0
    # No highlight without tau.
    none, _ = kept_points(renderer, stipples(diffuse=False, specular=True, tau=0.0, **CAMERA_LIGHT), c)
    assert np.array_equal(none, visible)


def test_dots_paper_and_colours(renderer, ball):
    c, pos, normals, to_eye = ball
    ink, paper = (0.6, 0.1, 0.2, 1.0), (0.9, 0.85, 0.7, 1.0)
    r = render(renderer, stipples(dot_color=ink, paper_color=paper, **CAMERA_LIGHT), [c], capture=False,
               background=(0, 0, 0, 0), composite={"mode": "depth_test"})
    color, depth = np.asarray(r.color), np.asarray(r.depth)
    covered = color[..., 3] > 0
    # Inside the silhouette every pixel is paper, dot, or an antialiased mix of the two.
    inside = covered[H // 2 - 40:H // 2 + 40, W // 2 - 40:W // 2 + 40]
    assert inside.all()
    lin = color[covered][:, :3]  # the result is scene-linear; the mark mixes in display sRGB
    rgb = np.where(lin <= 0.0031308, lin * 12.92, 1.055 * np.power(np.maximum(lin, 0), 1 / 2.4) - 0.055)
    t = (rgb - paper[:3]) @ (np.subtract(ink[:3], paper[:3])) / np.sum(np.subtract(ink[:3], paper[:3]) ** 2)
    assert np.abs(rgb - (np.asarray(paper[:3]) + t[:, None] * np.subtract(ink[:3], paper[:3]))).max() < 2e-3
    assert (t > 0.99).sum() > 1000 and (t < 0.01).sum() > 2000  # solid dot centres, bare paper
    # The sphere's front at 4: dots at their depth, paper at the spread surface (at most
    # iterations x the step, 4 x 0.026 x the depth range of about 2.2, deeper).
    centre = depth[H // 2 - 5:H // 2 + 5, W // 2 - 5:W // 2 + 5]
    assert np.all(centre > 4.0 - 0.01) and np.all(centre < 4.0 + 0.25) and abs(np.median(centre) - 4.0) < 0.06
    # Without paper, only dots cover; size jitter changes dot sizes, not which points draw.
    bare = render(renderer, stipples(paper_color=(1, 1, 1, 0), level=5.0), [c], background=(0, 0, 0, 0))
    jitter = render(renderer, stipples(paper_color=(1, 1, 1, 0), level=5.0, size_jitter=0.8), [c],
                    background=(0, 0, 0, 0))
    assert np.array_equal(np.sort(bare.marks["point_id"]), np.sort(jitter.marks["point_id"]))
    bare_inside = np.asarray(bare.color)[H // 2 - 40:H // 2 + 40, W // 2 - 40:W // 2 + 40, 3]
    assert 0.2 < bare_inside.mean() < 0.9 and (bare_inside == 0).sum() > 1000, bare_inside.mean()
    assert not np.array_equal(np.asarray(bare.color), np.asarray(jitter.color))


def test_needs_no_normals_and_reads_only_point_ids(ball):
    renderer = pointnpr.Renderer()
    pos, _ = sphere(3000)
    c = pointnpr.PointCloud(pos)
    for params in ({}, {"specular": True}, {"shadow_casters": "visible"}):
        style = stipples(**params)
        assert style.attributes == ["point_index"]
        render(renderer, style, [c], capture=False)
    assert pointnpr.computed_attributes(c) == []
    assert renderer.uploaded_attributes(c) == ["point_index"]


def test_seed_varies_the_fractional_choices_only(renderer, ball):
    c, pos, normals, to_eye = ball
    a, _ = kept_points(renderer, stipples(level=5.5, **CAMERA_LIGHT), c)
    b, _ = kept_points(renderer, stipples(level=5.5, seed=9, **CAMERA_LIGHT), c)
    assert not np.array_equal(a, b)
    whole_a, _ = kept_points(renderer, stipples(level=6.0, **CAMERA_LIGHT), c)
    whole_b, _ = kept_points(renderer, stipples(level=6.0, seed=9, **CAMERA_LIGHT), c)
    assert np.array_equal(whole_a, whole_b)  # whole levels have no random choice


def test_point_count_level_scale_shifts_by_log4_of_the_points(renderer):
    # point_count: LEVEL as for 16384 points; 4096 points get one level less.
    for n, shift in ((16384, 0.0), (4096, -1.0)):
        pos, _ = sphere(n)
        c = pointnpr.PointCloud(pos)
        relative = render(renderer, stipples(level=6.0, level_scale="point_count", **CAMERA_LIGHT), [c])
        absolute = render(renderer, stipples(level=6.0 + shift, **CAMERA_LIGHT), [c])
        assert np.array_equal(np.sort(relative.marks["point_id"]), np.sort(absolute.marks["point_id"])), n
        assert np.array_equal(np.asarray(relative.color), np.asarray(absolute.color))


def test_the_resolution_queue_keeps_the_dot_density_on_screen():
    # A sphere at 5 and at 10 units covers 4x fewer pixels from twice as far:
    # with the queue, the dots per covered pixel stay within 25 %; without
    # it, all points are drawn into a quarter of the area (about 4x denser).
    renderer = pointnpr.Renderer()
    pos, _ = sphere(40000)
    per_pixel = {}
    for queued in (True, False):
        params = {"diffuse": False, "density_mode": "constant_on_screen" if queued else "all_points",
                  "queue_level": 0.05}
        for distance in (5.0, 10.0):
            c = pointnpr.PointCloud(pos + [0.0, 0.0, 5.0 - distance])
            r = render(renderer, stipples(**params), [c], capture=False, background=(0, 0, 0, 0))
            # The sphere's disc on screen (50 mm lens, 36 mm sensor over W pixels).
            f = 50.0 / 36.0 * W
            area = np.pi * (f * np.tan(np.arcsin(1.0 / distance))) ** 2
            per_pixel[(queued, distance)] = r.stats["stipples_drawn"] / area
    assert 0.75 < per_pixel[(True, 10.0)] / per_pixel[(True, 5.0)] < 1.25, per_pixel
    assert 3.0 < per_pixel[(False, 10.0)] / per_pixel[(False, 5.0)] < 5.0, per_pixel

