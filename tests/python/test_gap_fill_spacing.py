"""The gap fill reads each point's own spacing (issue 40): where a scan is
sparser than nine in ten of its points (an aerial tile's water, a far
bank), the gaps between its own samples close too, a hole wider than twice
that spacing stays open, and every rasterizer writes the same spacing."""
import numpy as np
import pytest

import pointnpr

W, H = 320, 240
# The view: orthographic, one unit per pixel, looking down -z at the plane.
# Points 2 px apart over most of the plane; over a sparser part (a single
# flight line's strip, a far bank) scan lines 11 px apart, a point every
# 3 px along them. 3 px splats: the lines' 8 px gaps are wider than twice
# the splats (the fill's rule for splats as wide as their gaps does not
# close them) and than twice the segment's spacing.
DENSE, SPARSE, ALONG = 2.0, 11.0, 3.0  # px
SIZE = 3.0
SPARSE_X, SPARSE_Y = (40.0, 120.0), (-60.0, 60.0)
HOLE = (60.0, 100.0, -20.0, 20.0)  # x0, x1, y0, y1: no points there


def _in(x, y, box):
    return (x >= box[0]) & (x < box[1]) & (y >= box[2]) & (y < box[3])


def _plane():
    X, Y = np.meshgrid(np.arange(-150.0, 150.0, DENSE), np.arange(-100.0, 100.0, DENSE))
    sparse_box = SPARSE_X + SPARSE_Y
    dense = np.column_stack([X.ravel(), Y.ravel()])
    dense = dense[~_in(dense[:, 0], dense[:, 1], sparse_box)]
    X, Y = np.meshgrid(np.arange(SPARSE_X[0], SPARSE_X[1], ALONG), np.arange(SPARSE_Y[0], SPARSE_Y[1], SPARSE))
    sparse = np.column_stack([X.ravel(), Y.ravel()])
    xy = np.vstack([dense, sparse])
    xy = xy[~_in(xy[:, 0], xy[:, 1], HOLE)] + 0.25  # off the pixel centres: coverage has no ties
    pos = np.column_stack([xy, np.full(len(xy), -4.0)]).astype(np.float32)
    sparse_share = float(_in(xy[:, 0], xy[:, 1], sparse_box).mean())
    return pointnpr.PointCloud(pos, colors=np.full((len(pos), 3), 150, np.uint8)), sparse_share


FILL = [("kuwahara", {"radius": 2.0, "impasto": 0.0})]  # reads neighbourhoods: the gap fill runs before it


def _render(renderer, cloud, filters=FILL, **backend):
    scene = pointnpr.Scene()
    mark = ("points", {"point_size": SIZE, **backend})
    style = pointnpr.Style(mark=mark, filters=filters)
    scene.add_segment("s", style, [(cloud, np.eye(4))])
    cam = pointnpr.Camera.orthographic(np.eye(4), float(W), width=W, height=H)
    return np.asarray(renderer.render(scene, cam, W, H).color)


def _open(img, x0, x1, y0, y1):
    """Background pixels (alpha < 0.5) over scene x in [x0, x1), y in [y0, y1)."""
    rows = slice(int(H / 2 - y1), int(H / 2 - y0))  # image rows run downwards
    cols = slice(int(W / 2 + x0), int(W / 2 + x1))
    return int((img[rows, cols, 3] < 0.5).sum())


GL_METHODS = [{"rasterizer": "gl", "gl_method": "compute"}, {"rasterizer": "gl", "gl_method": "gl_points"}]


def test_a_sparser_part_of_the_scan_closes_by_its_own_spacing_and_keeps_its_hole(renderer):
    cloud, sparse_share = _plane()
    # The sparse part is sparser than nine in ten points: the segment's
    # spacing (their 90th percentile) is the dense part's.
    r = np.asarray(pointnpr.local_resolution(cloud, 8))
    assert sparse_share < 0.1 and np.percentile(r, 90) < 1.5 * DENSE, (sparse_share, np.percentile(r, 90))
    # Away from the hole and the sparse part's border; deep in the hole.
    away = (SPARSE_X[0] + 6, SPARSE_X[1] - 6, SPARSE_Y[0] + 6, SPARSE_Y[1] - 6)
    ring = (HOLE[0] - 12, HOLE[1] + 12, HOLE[2] - 12, HOLE[3] + 12)
    deep = (HOLE[0] + 8, HOLE[1] - 8, HOLE[2] + 8, HOLE[3] - 8)
    unfilled = _render(renderer, cloud, filters=[])
    before = _open(unfilled, *away) - _open(unfilled, *ring)
    assert before > 2000, "the splats leave the lines' gaps"
    img = _render(renderer, cloud, rasterizer="native")
    # Neither the segment's spacing nor the splats' width closes them: what
    # closes is by the points' own spacing (a pixel-exact rule on this
    # lattice leaves a few pixels where its diagonals are just too long).
    assert _open(img, *away) - _open(img, *ring) < 0.05 * before, "the sparse part's gaps close"
    assert _open(img, *deep) == 24 * 24, "the hole (40 px, over twice the sparse spacing) stays open"


@pytest.mark.parametrize("backend", GL_METHODS, ids=["compute", "gl_points"])
def test_every_rasterizer_hands_the_fill_the_same_spacing(renderer, backend):
    cloud, _ = _plane()
    assert np.array_equal(_render(renderer, cloud, **backend), _render(renderer, cloud, rasterizer="native"))


def _canopy():
    """A canopy of lone returns (1.5 % of the points, 0.16 apart, jittered)
    beside a dense part (0.01 apart) that sets the segment's spacing: a
    search reach of 8 px. Seen orthographically, 256 px over 2.2 units."""
    rng = np.random.default_rng(7)
    dense = np.stack(np.meshgrid(np.arange(-1.0, 0.0, 0.01), np.arange(-0.5, 0.5, 0.01)), -1).reshape(-1, 2)
    lattice = np.stack(np.meshgrid(np.arange(0.05, 1.0, 0.16), np.arange(-0.45, 0.5, 0.16)), -1).reshape(-1, 2)
    xy = np.vstack([dense, lattice + rng.uniform(-0.05, 0.05, lattice.shape)])
    pos = np.column_stack([xy, np.full(len(xy), -5.0)]).astype(np.float32)
    cloud = pointnpr.PointCloud(pos, colors=np.full((len(pos), 3), 0.5, np.float32))
    scene = pointnpr.Scene()
    mark = ("points", {"size_mode": "spacing", "point_size": 3.0})
    scene.add_segment("s", pointnpr.Style(mark=mark, filters=FILL), [(cloud, np.eye(4))])
    bare = pointnpr.Scene()
    bare.add_segment("s", pointnpr.Style(mark=mark), [(cloud, np.eye(4))])
    cam = pointnpr.Camera.orthographic(np.eye(4), ortho_scale=2.2, clip_start=0.1, clip_end=100.0, width=256,
                                       height=256)
    return scene, bare, cam


def test_lone_returns_wider_apart_than_the_segments_reach_close_between_their_splats(renderer):
    # The returns' splats are as wide as their own spacing (the looks'
    # splats), so the gaps between them are slivers, but a sliver's ends
    # lie up to 16 px apart along its lines: the search reaches as far as
    # the sparsest points' own spacing asks, not only the segment's (0.8 %
    # of the canopy stayed open then).
    scene, bare, cam = _canopy()

    def alpha(s):
        return np.asarray(renderer.render(s, cam, 256, 256, background=(0, 0, 0, 0)).color)[..., 3]

    def px(v):
        return int((v + 1.1) / 2.2 * 256)

    canopy = (slice(px(-0.35), px(0.35)), slice(px(0.15), px(0.85)))  # away from its border
    assert (alpha(bare)[canopy] < 0.5).mean() > 0.05, "the splats leave slivers"
    assert (alpha(scene)[canopy] < 0.5).mean() < 0.003, "the slivers close"


def test_the_canopys_fill_drawn_in_tiles_is_the_bytes_of_the_whole_frame(renderer):
    # Each pixel's reach comes from the points its own lines meet, not from
    # the dispatch's 16 px tiles, whose grid moves with a tile's region.
    scene, _, cam = _canopy()
    whole = renderer.render(scene, cam, 256, 256)
    tiled = renderer.render(scene, cam, 256, 256, tile_size=48)
    assert tiled.stats["tiles"] > 1
    assert np.asarray(whole.color).tobytes() == np.asarray(tiled.color).tobytes()
