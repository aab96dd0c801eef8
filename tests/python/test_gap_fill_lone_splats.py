"""The gap fill's second stage (issue 40, shaders/gap_fill_pyramid.comp):
gaps among lone splats that no line through the gap meets on both sides
close from cells of 2 to 16 px, while a hole in the scan, the background
beside a silhouette and a surface in front stay as they are; back points
seen through a front surface's gaps give way to it."""
import numpy as np

import pointnpr

W, H = 320, 240
SIZE = 2.0          # px: small fixed splats, far apart from one another
MEAN_GAP = 5.0      # px: one point per MEAN_GAP^2 px, scattered at random (no lattice for lines to follow)
PLANE = (-100.0, 100.0, -80.0, 80.0)  # x0, x1, y0, y1 (px: one unit per pixel)
HOLE = (20.0, 70.0, -25.0, 25.0)      # no points there: over twice the scan's spacing
FILL = [("kuwahara", {"radius": 2.0, "impasto": 0.0})]  # reads neighbourhoods: the gap fill runs before it


def _in(xy, box):
    return (xy[:, 0] >= box[0]) & (xy[:, 0] < box[1]) & (xy[:, 1] >= box[2]) & (xy[:, 1] < box[3])


def _scatter(box, seed, z, colour, hole=None):
    rng = np.random.default_rng(seed)
    n = int((box[1] - box[0]) * (box[3] - box[2]) / MEAN_GAP ** 2)
    xy = np.column_stack([rng.uniform(box[0], box[1], n), rng.uniform(box[2], box[3], n)])
    if hole is not None:
        xy = xy[~_in(xy, hole)]
    pos = np.column_stack([xy, np.full(len(xy), z)]).astype(np.float32)
    return pointnpr.PointCloud(pos, colors=np.tile(np.asarray(colour, np.uint8), (len(pos), 1)))


def _render(renderer, clouds, filters=FILL):
    scene = pointnpr.Scene()
    style = pointnpr.Style(mark=("points", {"point_size": SIZE}), filters=filters)
    scene.add_segment("s", style, [(c, np.eye(4)) for c in clouds])
    cam = pointnpr.Camera.orthographic(np.eye(4), float(W), clip_start=0.1, clip_end=200.0, width=W, height=H)
    return np.asarray(renderer.render(scene, cam, W, H, background=(0, 0, 0, 0)).color)


def _box(img, x0, x1, y0, y1):
    """The pixels over scene x in [x0, x1), y in [y0, y1)."""
    return img[int(H / 2 - y1):int(H / 2 - y0), int(W / 2 + x0):int(W / 2 + x1)]


def _open(img, box):
    return float((_box(img, *box)[..., 3] < 0.5).mean())


def test_scattered_small_splats_close_between_them_and_leave_the_hole_and_the_outside(renderer):
    cloud = _scatter(PLANE, 3, -4.0, (150, 150, 150), hole=HOLE)
    away = (PLANE[0] + 10, HOLE[0] - 10, PLANE[2] + 10, PLANE[3] - 10)  # inside, away from the hole and border
    bare = _render(renderer, [cloud], filters=[])
    assert _open(bare, away) > 0.5, "the splats leave most of the plane open"
    img = _render(renderer, [cloud])
    assert _open(img, away) < 0.01, "the gaps between the scattered splats close"
    # The hole (50 px) is over twice the scan's spacing (about 7 px): its
    # middle stays open, and the filled plane ends where its points do.
    assert _open(img, (HOLE[0] + 10, HOLE[1] - 10, HOLE[2] + 10, HOLE[3] - 10)) == 1.0, "the hole stays"
    outside = (PLANE[1] + 2, PLANE[1] + 20, PLANE[2], PLANE[3])
    assert _open(img, outside) == 1.0, "the silhouette does not grow"


def test_back_points_seen_through_scattered_splats_give_way_to_them(renderer):
    front = _scatter(PLANE, 5, -4.0, (220, 30, 30))
    back = _scatter((-150.0, 150.0, -110.0, 110.0), 6, -100.0, (30, 30, 220))  # far behind: no slope joins them
    inner = (PLANE[0] + 10, PLANE[1] - 10, PLANE[2] + 10, PLANE[3] - 10)
    # Random points leave a few voids wider than twice their spacing: holes
    # of the front surface, which its fill keeps (about 3 % here).
    own_holes = _open(_render(renderer, [front]), inner)
    assert own_holes < 0.05
    img = _render(renderer, [front, back])
    inside = _box(img, *inner)
    blue = (inside[..., 2] > inside[..., 0]) | (inside[..., 3] < 0.5)
    assert blue.mean() < own_holes + 0.005, "the back shows only through the front surface's own holes"
    # Beyond the front plane's border the back surface shows as it does alone.
    def back_shown(im):
        beside = _box(im, PLANE[1] + 12, 150.0, PLANE[2], PLANE[3])
        return float(((beside[..., 2] > beside[..., 0]) & (beside[..., 3] >= 0.5)).mean())

    alone = back_shown(_render(renderer, [back]))
    assert alone > 0.8 and back_shown(img) > alone - 0.01
