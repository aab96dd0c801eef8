"""Brush splats leave no cracks (issue 39): a brush is the pixel's surface
only where it covers at least half of the pixel, so the faint rim of a
brush in front of another surface blends over that surface instead of
cutting it away (which left the rim alone: white cracks around every
depth step, most on Kinect frames and sparse scans)."""
import os
import sys

import numpy as np
import pytest

import pointnpr
from pointnpr import presets

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import look_audit  # noqa: E402
BRUSH_PRESETS = [n for n, s in presets.PRESETS.items() if s["mark"][0] == "brush_splats"]


def _grid(x0, x1, y0, y1, z, spacing):
    xs, ys = np.arange(x0, x1 + 1e-9, spacing), np.arange(y0, y1 + 1e-9, spacing)
    X, Y = np.meshgrid(xs, ys)
    return np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, float(z))])


def _alpha(renderer, mark, cloud, cam, w, h, filters=()):
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=mark, filters=list(filters)), [(cloud, np.eye(4))])
    return np.asarray(renderer.render(scene, cam, w, h, background=(0, 0, 0, 0)).color)[..., 3]


def _filled(mask, r=5):
    """The silhouette closed by a disk of r px: gaps between splats filled
    (the look audits' closing, bench/look_audit.py)."""
    return look_audit.erode(look_audit.dilate(mask, r), r)


@pytest.mark.parametrize("rasterizer", ["native", "gl"])
@pytest.mark.parametrize("blending", ["none", "blur"])
def test_a_brush_in_front_leaves_no_crack_around_it(renderer, rasterizer, blending):
    # A patch in front of a wall, far beyond the depth tolerance: every
    # pixel the wall alone covers stays covered with the patch in front.
    wall = _grid(-1.0, 1.0, -1.0, 1.0, -6.0, 0.05)
    patch = _grid(-0.3, 0.3, -0.3, 0.3, -5.0, 0.05)
    normals = np.tile(np.array([[0.0, 0.0, 1.0]], np.float32), (len(wall) + len(patch), 1))
    colors = np.vstack([np.tile([[0.2, 0.3, 0.8]], (len(wall), 1)), np.tile([[0.9, 0.6, 0.1]], (len(patch), 1))])
    both = pointnpr.PointCloud(np.vstack([wall, patch]), normals=normals, colors=colors.astype(np.float32))
    alone = pointnpr.PointCloud(wall, normals=normals[:len(wall)], colors=colors[:len(wall)].astype(np.float32))
    cam = pointnpr.Camera.orthographic(np.eye(4), ortho_scale=2.0, clip_start=0.1, clip_end=100.0, width=256,
                                       height=256)
    # Pointillist's single round brush has the widest faint rim.
    params = dict(presets.PRESETS["Pointillist"]["mark"][1], rasterizer=rasterizer, blending=blending,
                  shading="none")
    wall_alone = _alpha(renderer, ("brush_splats", params), alone, cam, 256, 256) >= 0.5
    with_patch = _alpha(renderer, ("brush_splats", params), both, cam, 256, 256)
    cracks = wall_alone & (with_patch < 0.5)
    assert wall_alone.sum() > 0.9 * 256 * 256
    assert cracks.sum() == 0, int(cracks.sum())


@pytest.mark.parametrize("preset", BRUSH_PRESETS)
def test_every_brush_preset_covers_a_kinect_frame(renderer, preset):
    # Issue 39's acceptance: at most 1 % of the filled silhouette (the
    # points' coverage closed by 5 px) below alpha 0.5 on a Kinect frame
    # (before the surface cut and the noise floor: 1.07 % for Pointillist
    # here, 6.6 % on the whole frame in bench/marks_audit.py).
    scan = pointnpr.read(os.path.join(ROOT, "tests", "data", "io", "mug_crop.pcd"))
    pos = np.asarray(scan.positions, np.float64)
    ok = np.isfinite(pos).all(1)
    cloud = pointnpr.PointCloud(pos[ok], colors=np.asarray(scan.attributes["colors"])[ok])
    # From the sensor, at the sampling of a whole 640x480 frame drawn at
    # 1280x720 (the look audit's): 2 px between neighbouring samples.
    w, h = 240, 180
    pts = pos[ok]
    _idx, dist = pointnpr.knn(pts, 2)
    spacing = float(np.median(np.asarray(dist)[:, 1]))
    centre = (pts.min(0) + pts.max(0)) / 2
    lens = 2.0 * 36.0 * centre[2] / (w * spacing)
    cam = pointnpr.Camera.perspective(pointnpr.look_at((0.0, 0.0, 0.0), tuple(centre), up=(0, -1, 0)),
                                      lens=lens, clip_start=0.05, clip_end=50.0, width=w, height=h)
    filled = _filled(_alpha(renderer, ("points", {"point_size": 3.0}), cloud, cam, w, h) >= 0.5)
    spec = presets.PRESETS[preset]
    alpha = _alpha(renderer, spec["mark"], cloud, cam, w, h, spec["filters"])
    holes = (filled & (alpha < 0.5)).sum() / filled.sum()
    assert filled.sum() > 0.3 * w * h
    assert holes <= 0.01, holes


@pytest.mark.parametrize("rasterizer", ["native", "gl", "gl, a_buffer"])
@pytest.mark.parametrize("preset", BRUSH_PRESETS)
def test_a_rim_over_a_surface_behind_is_whole_and_one_against_nothing_stays_soft(renderer, rasterizer, preset):
    # Where a brush's rim covers half a pixel or more it is the pixel's
    # surface and the wall's splats under it are cut: the rim alone left the
    # pixel part covered, a pale ring around the patch (Impressionist: 35 %
    # of the ring's pixels, down to alpha 0.54). The wall under the rim now
    # shows (shaders/brush_rims.glsl): the ring (the patch's own soft edge,
    # within 3 px of its outside, where the wall alone is whole) is whole
    # with the wall behind; the wall's border, against nothing, keeps its
    # soft edge.
    wall = _grid(-1.0, 1.0, -1.0, 1.0, -2.5, 0.05)
    patch = _grid(-0.3, 0.3, -0.3, 0.3, -2.0, 0.05)
    normals = np.tile(np.array([[0.0, 0.0, 1.0]], np.float32), (len(wall) + len(patch), 1))
    colors = np.vstack([np.tile([[0.2, 0.3, 0.8]], (len(wall), 1)), np.tile([[0.9, 0.6, 0.1]], (len(patch), 1))])
    colors = colors.astype(np.float32)
    cam = pointnpr.Camera.perspective(np.eye(4), lens=35.0, clip_start=0.1, clip_end=100.0, width=256, height=256)
    params = dict(presets.PRESETS[preset]["mark"][1], rasterizer=rasterizer.split(",")[0], shading="none")
    if rasterizer.endswith("a_buffer"):
        params["blending"] = "a_buffer"

    def alpha(points, n, c):
        cloud = pointnpr.PointCloud(points, normals=n, colors=c)
        return _alpha(renderer, ("brush_splats", params), cloud, cam, 256, 256)

    wall_alone = alpha(wall, normals[:len(wall)], colors[:len(wall)])
    patch_alone = alpha(patch, normals[len(wall):], colors[len(wall):])
    both = alpha(np.vstack([wall, patch]), normals, colors)
    whole = 1.0 - 0.5 / 255.0
    ring = ((patch_alone > 0.0) & (patch_alone < whole) & look_audit.dilate(patch_alone == 0.0, 3) &
            (wall_alone >= whole))
    assert ring.sum() > 500
    assert (both[ring] < whole).mean() <= 0.02 and both[ring].min() > 0.95, (
        (both[ring] < whole).mean(), both[ring].min())
    soft = (wall_alone > 0.0) & (wall_alone < whole) & ~look_audit.dilate(patch_alone > 0.0, 20)
    assert soft.sum() > 100 and np.array_equal(both[soft], wall_alone[soft])
