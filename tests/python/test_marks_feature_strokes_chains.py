"""Feature strokes' chains (chain_lines; geometry/feature_chains.h): the
feature points along one line draw it as one line through them, where a
stroke per point (the paper's) leaves it dashed. On both of the mark's
paths."""
import numpy as np
import pytest

import pointnpr

W, H = 320, 240
LENS = 50.0


def roof(spacing):
    """A gabled roof on a grid (its ridge a row of points along x), tilted
    toward a camera at the origin looking down -z; and its ridge, projected
    to frame pixels (x right, y up)."""
    xs = np.arange(-0.6, 0.6 + 1e-9, spacing)
    ys = np.arange(-0.5, 0.5 + 1e-9, spacing)
    X, Y = np.meshgrid(xs, ys)
    local = np.column_stack([X.ravel(), Y.ravel(), -np.abs(Y.ravel()) * np.tan(np.radians(35.0))])
    a = np.radians(-50.0)
    R = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    place = np.array([0.0, 0.0, -2.5])
    ridge = np.column_stack([np.linspace(-0.5, 0.5, 400), np.zeros(400), np.zeros(400)]) @ R.T + place
    f = (W / 2) / (18.0 / LENS)  # a 36 mm sensor across the width
    px = np.column_stack([W / 2 + f * ridge[:, 0] / -ridge[:, 2], H / 2 + f * ridge[:, 1] / -ridge[:, 2]])
    return local @ R.T + place, px


def draw(renderer, pos, chain_lines, path, **more):
    scene = pointnpr.Scene()
    params = {"tone": 0.0, "dithering": "none", "non_directional": "none", "directional": "line_segment",
              "line_width": 1.5, "directional_length": 3.0, "chain_lines": chain_lines, "rasterizer": path, **more}
    scene.add_segment("roof", pointnpr.Style(mark=("feature_strokes", params)), [(pointnpr.PointCloud(pos), np.eye(4))])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=LENS, width=W, height=H)
    return renderer.render(scene, cam, W, H, background=(1, 1, 1, 1), capture_marks=True)


def ridge_covered(result, ridge_px):
    """The share of the ridge's samples with ink within a pixel across it."""
    ink = np.asarray(result.color)[..., :3].mean(-1) < 0.6
    return np.mean([ink[int(round(y)) - 1:int(round(y)) + 2, int(x)].any() for x, y in ridge_px])


@pytest.mark.parametrize("path", ["gl", "native"])
def test_a_chain_draws_the_ridge_as_one_line_where_a_stroke_each_leaves_it_dashed(renderer, path):
    # 5 px between the ridge's points on screen, strokes 3 px long: a
    # stroke per point leaves a gap between every two; the chain's links
    # (at most twice the stroke's length) join them.
    pos, ridge_px = roof(0.03)
    chained, each = draw(renderer, pos, True, path), draw(renderer, pos, False, path)
    # The same points are directional either way; only how they draw differs.
    assert chained.stats["strokes_directional"] == each.stats["strokes_directional"] > 100
    assert ridge_covered(each, ridge_px) < 0.85
    assert ridge_covered(chained, ridge_px) > 0.98
    # The links run along the ridge (x), as the points' own fits do.
    direction = np.asarray(chained.marks["direction"])
    assert np.median(np.abs(direction[:, 0])) > 0.95



@pytest.mark.parametrize("path", ["gl", "native"])
def test_a_chain_stays_one_line_where_the_resolution_queue_draws_few_of_its_points(renderer, path):
    # The queue keeps a tenth of the points: a stroke each would dot the
    # ridge; every link of the chain still draws (its ink is its length on
    # screen, which the queue need not thin).
    pos, ridge_px = roof(0.03)
    thin = {"density_mode": "constant_on_screen", "queue_level": 0.004}
    chained, each = draw(renderer, pos, True, path, **thin), draw(renderer, pos, False, path, **thin)
    assert chained.stats["queue_points"] < 0.15 * len(pos)
    assert ridge_covered(each, ridge_px) < 0.5
    assert ridge_covered(chained, ridge_px) > 0.98
