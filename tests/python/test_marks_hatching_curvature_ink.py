"""Curvature-controlled length (seed 002) changes the hatching's strokes,
not its tone (issue 39): strokes shortened where the surface curves used to
take their ink with them, so a rough surface (foliage on an aerial tile,
a noisy depth frame) read lighter than a smooth one under the same light.
The ink is made up by keeping more strokes where the coverage limit thins
them, then by crossing more of them. Both backends."""
import numpy as np
import pytest

import pointnpr
from test_marks import H, W, render


@pytest.fixture(params=["gl", "native"])
def implementation(request):
    return request.param


def rough_wall(n, seed=3):
    """n points over a wall facing the camera, jittered in depth by 0.6 of
    their spacing: a surface variation of about 0.05-0.15 everywhere."""
    rng = np.random.default_rng(seed)
    side = np.sqrt(2.4 * 1.8 / n)
    return pointnpr.PointCloud(np.column_stack([rng.uniform(-1.2, 1.2, n), rng.uniform(-0.9, 0.9, n),
                                                -5.0 + rng.normal(scale=0.6 * side, size=n)]))


def strokes(cloud, implementation, curvature_length, cross_hatch, renderer):
    params = dict(stroke_coverage=1.5, cross_hatch=cross_hatch, curvature_length=curvature_length,
                  length_jitter=0.0, light_space="camera", light_elevation=60.0, depth_pass=False,
                  paper_color=(1.0, 1.0, 1.0, 1.0), rasterizer=implementation)
    return render(renderer, pointnpr.Style(mark=("hatching", params)), [cloud])


def middle_ink(result):
    img = np.asarray(result.color)
    return float(1.0 - img[H // 2 - 50:H // 2 + 50, W // 2 - 80:W // 2 + 80, :3].mean())


@pytest.mark.parametrize("points,cross_hatch,least", [
    (60000, 0.0, 0.9),  # the coverage limit thins the strokes: more of them are kept
    (60000, 0.5, 0.9),
    (4000, 0.5, 0.75),  # every stroke already drawn: more of them cross
])
def test_shortened_strokes_keep_the_surface_s_ink(renderer, implementation, points, cross_hatch, least):
    # Ink of the wall's middle with curvature_length 0.6 over its ink with 0
    # (strokes about half as long). Measured before: 0.53 in every case;
    # now 0.97, 0.96 and 0.80.
    wall = rough_wall(points)
    plain, curved = (middle_ink(strokes(wall, implementation, c, cross_hatch, renderer)) for c in (0.0, 0.6))
    assert curved > least * plain, (plain, curved)


def test_parallel_hatching_stays_parallel(renderer, implementation):
    # With cross_hatch 0 a sparse surface's shortened strokes cannot be made
    # up (each point draws one stroke): none crosses, and it reads lighter
    # (measured 0.57 of the ink).
    wall = rough_wall(4000)
    plain, curved = (strokes(wall, implementation, c, 0.0, renderer) for c in (0.0, 0.6))
    assert not np.any(curved.marks["crossed"])
    assert middle_ink(curved) < 0.7 * middle_ink(plain)
