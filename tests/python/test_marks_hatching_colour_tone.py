"""The hatching mark's colour tone (`color_tone`, coloring `point`): a
colour darker than the scan's median gets more strokes under the same
light, a lighter one fewer; without colours nothing changes."""
import numpy as np
import pytest

import pointnpr

W, H = 320, 240


def _wall(colors=True):
    xs = np.arange(-1.0, 1.0, 0.01)
    X, Y = np.meshgrid(xs, np.arange(-0.75, 0.75, 0.01))
    pos = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, -4.0)])
    # Dark, mid-grey (the median) and light bands, left to right.
    grey = np.select([pos[:, 0] < -0.4, pos[:, 0] < 0.4], [60, 128], 220).astype(np.uint8)
    cloud = pointnpr.PointCloud(pos, colors=np.repeat(grey[:, None], 3, axis=1)) if colors else \
        pointnpr.PointCloud(pos)
    return cloud, pos


def _strokes(renderer, cloud, pos, path, **params):
    scene = pointnpr.Scene()
    style = {"coloring": "point", "xtoon": "two_colored", "light_space": "camera", "light_elevation": 30.0,
             "stroke_coverage": 0.0, "rasterizer": path, **params}
    scene.add_segment("s", pointnpr.Style(mark=("hatching", style)), [(cloud, np.eye(4))])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=W, height=H)
    r = renderer.render(scene, cam, W, H, capture_marks=True)
    x = pos[np.asarray(r.marks["point_id"]), 0]
    return int((x < -0.4).sum()), int((x >= 0.4).sum()), np.asarray(r.color)


@pytest.mark.parametrize("path", ["gl", "native"])
def test_a_dark_colour_gets_more_strokes_than_a_light_one_under_the_same_light(renderer, path):
    cloud, pos = _wall()
    dark0, light0 = _strokes(renderer, cloud, pos, path, color_tone=0.0)[:2]
    dark1, light1 = _strokes(renderer, cloud, pos, path, color_tone=1.0)[:2]
    assert light0 > 200 and abs(dark0 / light0 - 1.0) < 0.1, (dark0, light0)  # the light alone: alike bands
    assert dark1 > 1.3 * dark0 and light1 < 0.8 * light0, (dark0, light0, dark1, light1)


def test_a_scan_without_colours_keeps_its_strokes(renderer):
    cloud, pos = _wall(colors=False)
    a = _strokes(renderer, cloud, pos, "auto", color_tone=0.0)
    b = _strokes(renderer, cloud, pos, "auto", color_tone=1.0)
    assert a[0] > 100 and a[:2] == b[:2] and np.array_equal(a[2], b[2])
