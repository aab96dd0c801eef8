"""Intensity-only scans are exposed from their own histogram (issue 40):
the median intensity lands on middle grey (display 118/255, where an RGB
scan's median sits), whatever the units and the spread; white at the 99th
percentile, as before, put a skewed tile's median near black."""
import os

import numpy as np
import pytest

import pointnpr

W, H = 160, 120
MIDDLE_GREY = 0.4614  # sRGB encoding of 18 % linear


def _display(linear):
    c = np.clip(linear, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)


def _median_display_grey(renderer, cloud, camera):
    scene = pointnpr.Scene()
    scene.add_segment("scan", pointnpr.Style(rasterize={"point_size": 3.0}), [(cloud, np.eye(4))])
    color = renderer.render(scene, camera, W, H).color
    covered = color[..., 3] > 0
    assert covered.mean() > 0.2
    rgb = color[..., :3][covered] / color[..., 3:][covered]
    return float(np.median(_display(rgb).mean(axis=1)))


def _plane(intensity):
    n = int(np.sqrt(len(intensity)))
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n))
    pos = np.column_stack([x.ravel(), y.ravel(), np.full(n * n, -4.0)])
    return pointnpr.PointCloud(pos, intensity=np.asarray(intensity[:n * n], np.float32))


@pytest.mark.parametrize("spread", ["lognormal", "tight", "lognormal_in_thousands"])
def test_the_median_intensity_is_middle_grey(renderer, spread):
    rng = np.random.default_rng(7)
    values = {"lognormal": rng.lognormal(3.0, 1.0, 200 * 200),            # skewed, glints far above
              "tight": rng.uniform(2000.0, 2456.0, 200 * 200),             # one material
              "lognormal_in_thousands": 1000.0 * rng.lognormal(3.0, 1.0, 200 * 200)}[spread]
    # Shuffled over the plane: the median pixel sees the median intensity.
    camera = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=W, height=H)
    grey = _median_display_grey(renderer, _plane(values), camera)
    assert abs(grey - MIDDLE_GREY) < 3.0 / 255.0, grey * 255
    if spread == "lognormal":
        # What white at the 99th percentile gave: the median near black (< 30/255).
        assert np.median(values) / np.percentile(values, 99) < 30.0 / 255.0


def test_an_aerial_tile_by_intensity_alone_is_mid_grey(renderer):
    """The LiDAR HD tile without its colours, from above: the median pixel
    within 16/255 of middle grey (pixels are not points: trees, darker in
    intensity, cover more of the view than their share of the points)."""
    data = pointnpr.read(os.path.join(os.path.dirname(__file__), "..", "..", "data",
                                      "lidarhd_myria3d_870000_6618000_subset.las"))
    pos = np.asarray(data.positions)
    centre = (pos.min(0) + pos.max(0)) / 2
    cloud = pointnpr.PointCloud(pos - centre, intensity=np.asarray(data.attributes["intensity"]))
    camera = pointnpr.Camera.perspective(pointnpr.look_at((0.0, -1.0, 120.0), (0.0, 0.0, 0.0)), lens=35.0,
                                         clip_start=0.5, clip_end=1000.0, width=W, height=H)
    grey = _median_display_grey(renderer, cloud, camera)
    assert abs(grey - MIDDLE_GREY) < 16.0 / 255.0, grey * 255
