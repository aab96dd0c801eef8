"""The flow-based oil paint (flow_oil, issue 40): its bristle streaks run
along the image's flow, its paint texture stays on the surface when the
camera moves, it keeps the silhouette, and it draws the same bytes every
run. Scenes: a plane of points facing the camera, seen square."""
import numpy as np
import pytest

import pointnpr

SIZE = 160
DEPTH = 6.0
LENS = 70.0
SENSOR = 36.0  # mm, Blender's default sensor width (the camera's horizontal fit)
HALF = 1.5  # the plane spans [-HALF, HALF]^2: it covers nearly the whole frame
SPACING = 0.015
MARGIN = 24  # px kept off the frame's and the plane's borders in the measures
FLAT = {"impasto": 0.0}
RELIEF = {"impasto": 0.6, "gloss": 0.0}


def _plane_xy():
    xs = np.arange(-HALF, HALF + 1e-9, SPACING)
    X, Y = np.meshgrid(xs, xs)
    return X.ravel(), Y.ravel()


def striped_plane(period=0.25):
    """Stripes of two colours along the direction (2, 1) of the plane."""
    x, y = _plane_xy()
    across = (-x + 2.0 * y) / np.sqrt(5.0)
    stripe = (np.floor(across / (0.5 * period)) % 2).astype(bool)
    colors = np.where(stripe[:, None], (200, 150, 70), (70, 90, 160)).astype(np.uint8)
    return pointnpr.PointCloud(np.column_stack([x, y, np.zeros_like(x)]), colors=colors)


def flat_plane(color=(150, 40, 30)):
    x, y = _plane_xy()
    return pointnpr.PointCloud(np.column_stack([x, y, np.zeros_like(x)]),
                               colors=np.tile(np.asarray(color, np.uint8), (x.size, 1)))


def render(renderer, cloud, filters, camera_x=0.0, background=(1, 1, 1, 1)):
    scene = pointnpr.Scene()
    scene.add_segment("plane", pointnpr.Style(rasterize={"point_size": 3.0}, filters=filters), [(cloud, np.eye(4))])
    m = np.eye(4)
    m[:3, 3] = (camera_x, 0.0, DEPTH)
    cam = pointnpr.Camera.perspective(m, lens=LENS, width=SIZE, height=SIZE)
    return np.asarray(renderer.render(scene, cam, SIZE, SIZE, background=background).color)


def interior(a):
    return a[MARGIN:-MARGIN, MARGIN:-MARGIN]


def energy(image, step):
    """Mean squared difference between pixels `step` = (dx, dy) apart."""
    dx, dy = step
    a = image[MARGIN:-MARGIN, MARGIN:-MARGIN]
    b = image[MARGIN + dy:SIZE - MARGIN + dy, MARGIN + dx:SIZE - MARGIN + dx]
    return float(((a - b) ** 2).mean())


def test_streaks_run_along_the_flow(renderer):
    cloud = striped_plane()
    plain = render(renderer, cloud, [])[..., :3].mean(axis=-1)
    # The stripes' direction on screen, from the plain render: of the two
    # diagonals (2, +-1), the one along which the colour changes least.
    along = min([(2, 1), (2, -1)], key=lambda s: energy(plain, s))
    across = (-along[1], along[0])
    assert energy(plain, across) > 3 * energy(plain, along)
    # The relief's shading alone: the paint lit minus the flat paint.
    shade = (render(renderer, cloud, [("flow_oil", RELIEF)]) -
             render(renderer, cloud, [("flow_oil", FLAT)]))[..., :3].mean(axis=-1)
    assert np.abs(interior(shade)).mean() > 0.01, "the relief shows"
    ratio = energy(shade, across) / energy(shade, along)
    assert ratio > 5.0, f"streaks along the stripes: across / along {ratio:.2f}"


def test_paint_texture_moves_with_the_surface(renderer):
    """After a camera pan of 4 px the paint texture is found 4 px over, not
    where it was on screen (noise fixed to the surface, not to pixels)."""
    cloud = flat_plane()
    shift = 4
    pixel = DEPTH * SENSOR / (LENS * SIZE)  # world units one pixel spans on the plane
    a = render(renderer, cloud, [("flow_oil", RELIEF)])[..., :3]
    b = render(renderer, cloud, [("flow_oil", RELIEF)], camera_x=shift * pixel)[..., :3]
    assert np.abs(interior(a) - interior(a).mean(axis=(0, 1))).mean() > 0.01, "a texture to follow"
    rows = slice(MARGIN, SIZE - MARGIN)
    cols = slice(MARGIN, SIZE - MARGIN)
    moved = np.abs(a[rows, MARGIN + shift:SIZE - MARGIN + shift] - b[rows, cols]).mean()
    kept = np.abs(a[rows, cols] - b[rows, cols]).mean()
    assert moved < 0.25 * kept, (moved, kept)


def test_keeps_the_silhouette_and_lets_no_background_in(renderer):
    cloud = flat_plane()
    clear = (0, 0, 0, 0)
    out = render(renderer, cloud, [("flow_oil", {"levels": 0, "impasto": 0.0})], background=clear)
    reference = render(renderer, cloud, [("kuwahara", {"impasto": 0.0})], background=clear)
    assert np.array_equal(out[..., 3], reference[..., 3]), "the outline stays where it was"
    covered = out[..., 3] > 0
    assert 0.5 < covered.mean() < 1.0
    assert np.all(out[~covered] == 0.0), "the background untouched"
    # A uniform colour stays that colour up to the border: no white bleeds in.
    want = np.asarray(reference[covered][:, :3]).mean(axis=0)
    assert np.abs(out[covered][:, :3] - want).max() < 2.0 / 255.0


@pytest.mark.parametrize("settings", [{}, {"tensor_sigma": 1.0, "brush_size": 4.0, "stroke_length": 40.0}])
def test_same_bytes_every_run(renderer, settings):
    cloud = striped_plane()
    first = render(renderer, cloud, [("flow_oil", settings)])
    again = render(pointnpr.Renderer(), cloud, [("flow_oil", settings)])
    assert first.tobytes() == again.tobytes()
