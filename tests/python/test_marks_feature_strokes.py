"""The feature_strokes mark (seed 001, Xu et al., sections 5 to 7) and the
continuous resolution queue (render/mark.h) it draws through.

Statistical checks state their tolerance: the dithering choice is a
Bernoulli draw per point (a hash of its id), so a count of n expected draws
has standard deviation about sqrt(n); tolerances are at least four of those.

The mark's tests run on both of its paths (`rasterizer` gl and native, the
`path` fixture); the native path's images are the GL path's within a
stated tolerance (test_the_native_path_draws_the_gl_paths_images).
"""
import os
import numpy as np
import pytest

import pointnpr
from conftest import one_thread_in_another_process

W, H = 320, 240
SPACING = 0.025


def camera(z=0.0, width=W, height=H):
    m = np.eye(4)
    m[2, 3] = z
    return pointnpr.Camera.perspective(m, lens=50.0, width=width, height=height)


PATHS = ["gl", "native"]
_path = {"rasterizer": "auto"}


@pytest.fixture(params=PATHS)
def path(request):
    """Runs a test on each of the mark's paths (render() below draws by it)."""
    _path["rasterizer"] = request.param
    yield request.param
    _path["rasterizer"] = "auto"


# The paper's range-aware dithering (the tone is tested in
# test_marks_feature_strokes_tone.py).
PAPER = {"tone": 0.0}


def render(renderer, params, clouds, cam=None, capture=True, background=(1, 1, 1, 1)):
    scene = pointnpr.Scene()
    params = {**PAPER, **_path, **params}
    scene.add_segment("s", pointnpr.Style(mark=("feature_strokes", params)), [(c, np.eye(4)) for c in clouds])
    return renderer.render(scene, cam or camera(), W, H, background=background, capture_marks=capture)


def rotation(ax, ay):
    cx, sx, cy, sy = np.cos(ax), np.sin(ax), np.cos(ay), np.sin(ay)
    return np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]]) @ np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])


def box(size=1.0, spacing=SPACING):
    """Surface points of an axis-aligned cube centred at the origin (a grid per face)."""
    h = size / 2
    g = np.arange(-h, h + 1e-9, spacing)
    A, B = np.meshgrid(g, g)
    faces = []
    for axis in range(3):
        others = [i for i in range(3) if i != axis]
        for s in (-h, h):
            p = np.zeros((A.size, 3))
            p[:, axis] = s
            p[:, others[0]], p[:, others[1]] = A.ravel(), B.ravel()
            faces.append(p)
    return np.unique(np.round(np.vstack(faces), 9), axis=0)


def wall(width, height, spacing, z, color=(200, 200, 200)):
    xs = np.arange(-width / 2, width / 2 + 1e-9, spacing)
    ys = np.arange(-height / 2, height / 2 + 1e-9, spacing)
    X, Y = np.meshgrid(xs, ys)
    pos = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, float(z))])
    return pos, np.tile(np.asarray(color, np.uint8), (X.size, 1))


# ---------------------------------------------------------------------------
# Feature points, directions, dithering

def test_directional_strokes_lie_along_the_box_edges_and_faces_carry_only_dithering(renderer, path):
    local = box()
    R = rotation(0.5, 0.6)
    pos = local @ R.T + np.array([0.0, 0.0, -4.0])
    r = render(renderer, {}, [pointnpr.PointCloud(pos)])
    m = r.marks
    kind, ids = np.asarray(m["kind"]), np.asarray(m["point_id"])
    assert (kind == 0).sum() > 300 and (kind == 2).sum() > 300
    # The edge through a point: the axis along which it is farthest from the faces.
    inside = 0.5 - np.abs(local[ids])
    edge_axis = np.argmax(inside, axis=1)
    second = np.sort(inside, axis=1)
    directional = kind == 0
    edge_dir_view = R[:, edge_axis[directional]].T  # the camera looks down -Z from the origin: view = world
    cosang = np.abs(np.sum(np.asarray(m["direction"])[directional] * edge_dir_view, axis=1))
    angles = np.degrees(np.arccos(np.clip(cosang, 0.0, 1.0)))
    assert angles.mean() < 5.0, angles.mean()
    # Directional points lie on edges (within 3 spacings of two faces).
    assert (second[directional, 1] <= 3.01 * SPACING).all()
    # Face points (4 spacings or more from every edge) are only ever dithering.
    on_face = second[:, 1] >= 4 * SPACING - 1e-9
    assert on_face.sum() > 500
    assert (kind[on_face] == 2).all()


def test_the_colour_weight_makes_a_colour_edge_a_feature_and_leaves_a_shape_alone(renderer, path):
    """Seed 001's feature degree is (1 - w) shape + w colour: a flat wall
    painted half red, half blue has feature points along its colour edge
    only with a colour weight, never fewer with more weight; a colourless
    box's feature points do not depend on it."""
    pos, col = wall(2.0, 1.5, 0.02, -5.0)
    col[pos[:, 0] > 0.0] = (30, 60, 220)
    col[pos[:, 0] <= 0.0] = (220, 40, 30)
    painted = pointnpr.PointCloud(pos, colors=col)
    features = []
    for w in (0.0, 0.5, 1.0):
        r = render(renderer, {"color_weight": w, "shading": "none"}, [painted])
        kind, ids = np.asarray(r.marks["kind"]), np.asarray(r.marks["point_id"])
        on_edge = np.abs(pos[ids[kind < 2], 0]) < 0.1  # within 5 spacings of the colour edge
        features.append(int((kind < 2).sum()))
        if w > 0.0:
            assert on_edge.all() and on_edge.size > 100, (w, on_edge.size)
    assert features[0] == 0 and features[1] <= features[2], features
    box_pos = box() @ rotation(0.5, 0.6).T + np.array([0.0, 0.0, -4.0])
    colourless = pointnpr.PointCloud(box_pos)
    counts = [render(renderer, {"color_weight": w}, [colourless], capture=False).stats["strokes_directional"]
              for w in (0.0, 1.0)]
    assert counts[0] == counts[1] > 300, counts


def test_dithering_share_follows_the_parameter(renderer, path):
    pos, col = wall(2.0, 1.5, 0.02, -5.0)
    c = pointnpr.PointCloud(pos)
    counts = []
    for d in (0.1, 0.3):
        r = render(renderer, {"dither": d, "shading": "none"}, [c], capture=False)  # unlit: the share alone
        counts.append(r.stats["strokes_dithering"])
        # A flat wall has no feature points.
        assert r.stats["strokes_directional"] + r.stats["strokes_non_directional"] == 0
        n = len(pos)
        assert abs(counts[-1] - d * n) < 4 * np.sqrt(d * (1 - d) * n) + 1, (counts[-1], d * n)


def test_light_sets_the_dithering_tone_of_a_colourless_scan(renderer, path):
    # Issue 39 ("light for every mark"): by default (shading auto) a sphere
    # without colours dithers densely where it turns from the light and
    # sparsely where it faces it; unlit, the density is the same all over.
    n = 20000
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    a = 2.399963229728653 * np.arange(n)
    normals = np.column_stack([np.sqrt(1 - z * z) * np.cos(a), np.sqrt(1 - z * z) * np.sin(a), z])
    c = pointnpr.PointCloud(normals + [0.0, 0.0, -5.0], normals=normals.astype(np.float32))
    az, el = np.radians(135.0), np.radians(45.0)  # the camera light's default direction (view = world here)
    lam = np.abs(normals @ [np.sin(el) * np.cos(az), np.sin(el) * np.sin(az), np.cos(el)])
    facing = normals[:, 2] > 0.3  # seen, away from the rim
    shares = {}
    for shading in ("auto", "none"):
        r = render(renderer, {"dither": 0.3, "shading": shading, "dithering": "point_sprite"}, [c])
        kept = np.zeros(n, bool)
        kept[np.asarray(r.marks["point_id"])[np.asarray(r.marks["kind"]) == 2]] = True
        shares[shading] = [kept[facing & (lam < 0.35)].mean(), kept[facing & (lam > 0.85)].mean()]
    dark, lit = shares["auto"]
    assert dark > 1.8 * lit, shares
    dark, lit = shares["none"]
    assert 0.8 < dark / lit < 1.25, shares


def test_dithering_is_uniform_in_3d_on_unevenly_sampled_surfaces(renderer, path):
    # Two walls side by side, sampled 2x apart: as many dithering points per
    # square metre on each.
    a, _ = wall(1.0, 1.0, 0.02, -5.0)
    b, _ = wall(1.0, 1.0, 0.04, -5.0)
    a[:, 0] -= 0.6
    b[:, 0] += 0.6
    r = render(renderer, {"dither": 0.1}, [pointnpr.PointCloud(np.vstack([a, b]))])
    x = np.asarray(r.marks["center"])[:, 0]
    left, right = (x < 0).sum(), (x > 0).sum()
    assert left > 100 and right > 100
    assert abs(left / right - 1.0) < 0.25, (left, right)


# ---------------------------------------------------------------------------
# Visibility splatting

def test_strokes_are_hidden_behind_nearer_surfaces(renderer, path):
    far, far_col = wall(2.4, 1.8, 0.02, -6.0, (230, 30, 30))
    near, near_col = wall(0.8, 0.6, 0.02, -4.0, (30, 30, 230))
    c = pointnpr.PointCloud(np.vstack([far, near]), colors=np.vstack([far_col, near_col]))
    params = {"coloring": "point", "dither": 0.3, "dithering": "point_sprite", "sprite_size": 3.0}
    img = np.asarray(render(renderer, params, [c], capture=False).color)
    # The near wall's screen rectangle, shrunk by the largest sprite radius.
    f = 50.0 / 36.0 * W  # focal length in pixels (36 mm sensor across the width)
    half_w, half_h = 0.4 / 4.0 * f, 0.3 / 4.0 * f
    cx, cy = W / 2, H / 2
    rows = slice(int(cy - half_h) + 3, int(cy + half_h) - 3)
    cols = slice(int(cx - half_w) + 3, int(cx + half_w) - 3)
    patch = img[rows, cols]
    red = (patch[..., 0] > 0.5) & (patch[..., 2] < 0.4)
    blue = (patch[..., 2] > 0.5) & (patch[..., 0] < 0.4)
    assert red.sum() == 0
    assert blue.sum() > 100  # the near wall's own strokes pass the offset depth test
    # ... and without the near wall, the far wall's strokes are there.
    img_far = np.asarray(render(renderer, params, [pointnpr.PointCloud(far, colors=far_col)], capture=False).color)
    patch = img_far[rows, cols]
    assert ((patch[..., 0] > 0.5) & (patch[..., 2] < 0.4)).sum() > 100


# ---------------------------------------------------------------------------
# The continuous resolution queue

QUEUE = {"density_mode": "constant_on_screen", "queue_level": 0.15, "dither": 0.5, "dithering": "point_sprite"}


def _density(renderer, params, c, z):
    r = render(renderer, params, [c], cam=camera(z), capture=False, background=(1, 1, 1, 0))
    covered = (np.asarray(r.color)[..., 3] > 0).sum()
    return r.stats["strokes_drawn"] / covered, r.stats["strokes_drawn"]


def test_stroke_density_on_screen_stays_constant_with_the_queue_and_quadruples_without(path):
    renderer = pointnpr.Renderer()
    pos, _ = wall(1.2, 0.9, 0.005, -4.0)  # 43k points, 3 chunks
    c = pointnpr.PointCloud(pos)
    # Camera at distance 4 and 8 (the wall 1.2 m wide is in view at both).
    near_q, n_near = _density(renderer, QUEUE, c, 0.0)
    far_q, n_far = _density(renderer, QUEUE, c, 4.0)
    # The queue is not saturated (229 strokes at 8 m: M is the wall's own
    # area now, not its three chunks' overlapping boxes).
    assert n_far > 200 and n_near < 0.5 * len(pos)
    assert abs(far_q / near_q - 1.0) < 0.15, (near_q, far_q)
    off = dict(QUEUE, density_mode="all_points")
    near_a, _ = _density(renderer, off, c, 0.0)
    far_a, _ = _density(renderer, off, c, 4.0)
    assert 3.2 < far_a / near_a < 4.8, far_a / near_a


def test_the_queue_follows_the_points_area_not_the_empty_space_in_a_chunks_box(path):
    # A few stray points 2 m in front of a wall stretch the box of the chunk
    # they fall in toward the camera: its hull on screen grows about 4x while
    # the surface its points sample does not, so the chunk's density must not.
    renderer = pointnpr.Renderer()
    pos, _ = wall(1.2, 0.9, 0.005, -4.0)  # 43k points, 3 chunks
    strays = np.array([[0.1 * i, 0.0, -2.0] for i in range(-2, 3)])
    _, alone = _density(renderer, QUEUE, pointnpr.PointCloud(pos), 0.0)
    _, with_strays = _density(renderer, QUEUE, pointnpr.PointCloud(np.vstack([pos, strays])), 0.0)
    assert alone > 300 and with_strays < 1.05 * alone + len(strays), (alone, with_strays)


def test_a_moving_camera_adds_and_removes_points_only_at_the_end_of_the_queue(renderer, path):
    pos, _ = wall(1.2, 0.9, 0.01, -4.0)
    c = pointnpr.PointCloud(pos)
    previous, counts = None, []
    for step in range(8):  # approaching in steps of 1 % of the distance
        r = render(renderer, QUEUE, [c], cam=camera(-0.04 * step))
        ids = set(np.asarray(r.marks["point_id"]).tolist())
        counts.append(len(ids))
        if previous is not None:
            assert previous <= ids  # nothing drawn before disappears as more are added
            assert 0 < len(ids - previous) < 0.05 * len(previous)
        previous = ids
    assert counts == sorted(counts)
    # ... and moving back removes exactly those added last.
    back = set(np.asarray(render(renderer, QUEUE, [c], cam=camera(0.0)).marks["point_id"]).tolist())
    first = set(np.asarray(render(renderer, QUEUE, [c], cam=camera(0.0)).marks["point_id"]).tolist())
    assert back == first


def test_queue_order_follows_point_ids_not_storage_order(renderer, path):
    pos, _ = wall(1.2, 0.9, 0.01, -4.0)
    perm = np.random.default_rng(3).permutation(len(pos))
    a = render(renderer, QUEUE, [pointnpr.PointCloud(pos)])
    b = render(renderer, QUEUE, [pointnpr.PointCloud(pos[perm], point_index=perm.astype(np.uint32))])
    assert set(np.asarray(a.marks["point_id"]).tolist()) == set(np.asarray(b.marks["point_id"]).tolist())


def test_level_and_threshold_animate_smoothly(renderer, path):
    local = box()
    pos = local @ rotation(0.5, 0.6).T + np.array([0.0, 0.0, -4.0])
    c = pointnpr.PointCloud(pos)

    def ids(**p):
        r = render(renderer, dict(QUEUE, **p), [c])
        return set(np.asarray(r.marks["point_id"]).tolist())

    a, b = ids(queue_level=0.15), ids(queue_level=0.153)  # +2 %
    assert a <= b and len(b - a) < 0.05 * len(a)
    t0, t1 = ids(feature_threshold=0.35), ids(feature_threshold=0.36)
    assert len(t0 ^ t1) < 0.05 * len(t0)


# ---------------------------------------------------------------------------
# Primitives and textures

def test_primitive_none_draws_nothing_of_that_class(renderer, path):
    pos = box() @ rotation(0.5, 0.6).T + np.array([0.0, 0.0, -4.0])
    c = pointnpr.PointCloud(pos)
    r = render(renderer, {"dithering": "none"}, [c])
    kinds = set(np.asarray(r.marks["kind"]).tolist())
    assert 2 not in kinds and 0 in kinds
    r = render(renderer, {"directional": "none", "non_directional": "none", "dither": 0.2}, [c])
    assert set(np.asarray(r.marks["kind"]).tolist()) == {2}


def test_an_image_stroke_texture_sets_the_stroke_alpha(renderer, path, tmp_path):
    pos = box() @ rotation(0.5, 0.6).T + np.array([0.0, 0.0, -4.0])
    c = pointnpr.PointCloud(pos)
    clear = np.zeros((8, 32, 4), np.float32)
    ink = np.zeros((8, 32, 4), np.float32)
    ink[..., 3] = 1.0  # black, opaque
    paths = []
    for name, img in (("clear", clear), ("ink", ink)):
        paths.append(str(tmp_path / f"{name}.png"))
        pointnpr.save_image(paths[-1], img)
    base = {"stroke_texture": "image", "non_directional": "textured_stroke", "dithering": "textured_stroke",
            "paper_color": [1, 1, 1, 0]}
    a = np.asarray(render(renderer, dict(base, texture_image=paths[0]), [c], capture=False, background=(1, 1, 1, 0)).color)
    b = np.asarray(render(renderer, dict(base, texture_image=paths[1]), [c], capture=False, background=(1, 1, 1, 0)).color)
    assert (a[..., 3] > 0).sum() == 0
    assert (b[..., 3] > 0.5).sum() > 2000
    with pytest.raises(pointnpr.ParameterError):
        render(renderer, {"stroke_texture": "image"}, [c], capture=False)


# ---------------------------------------------------------------------------
# The native path (`auto` on software GL) against the GL passes

def _on_both_paths(renderer, params, clouds, cam):
    out = []
    for rasterizer in PATHS:
        scene = pointnpr.Scene()
        scene.add_segment("s", pointnpr.Style(mark=("feature_strokes", dict(PAPER, **params, rasterizer=rasterizer))),
                          [(c, np.eye(4)) for c in clouds])
        out.append(renderer.render(scene, cam, W, H, background=(1, 1, 1, 0), capture_marks=True))
    return out


def _two_walls():
    far, far_col = wall(2.4, 1.8, 0.02, -6.0, (230, 30, 30))
    near, near_col = wall(0.8, 0.6, 0.02, -4.0, (30, 30, 230))
    return pointnpr.PointCloud(np.vstack([far, near]), colors=np.vstack([far_col, near_col]))


NATIVE_CASES = {
    "defaults": {},
    "lines": {"directional": "line_segment", "non_directional": "line_segment", "dithering": "line_segment",
              "dither": 0.4, "line_width": 1.0},
    "sprites": {"dithering": "point_sprite", "dither": 0.5},
    "brush": {"stroke_texture": "brush", "dithering": "textured_stroke"},
    "dry": {"stroke_texture": "dry", "dithering": "textured_stroke", "opacity": 0.6},
    "image": {"stroke_texture": "image", "non_directional": "textured_stroke", "dithering": "textured_stroke"},
    "queue": {"density_mode": "constant_on_screen", "queue_level": 0.15, "screen_angle": 20.0},
    "orthographic": {"directional": "line_segment"},
    "hidden walls": {"coloring": "point", "dither": 0.3, "dithering": "point_sprite", "paper_color": [1, 1, 1, 0.5]},
}


@pytest.mark.parametrize("case", list(NATIVE_CASES))
# The native path (cpp/marks/feature_strokes/native.cpp) against the GL passes (feature_strokes.cpp).
def test_the_native_path_draws_the_gl_paths_images(renderer, case, tmp_path):
    """The same strokes (ids, classes, counts) and the same images within
    the tolerance of the kernels' last bits (exp, pow, noise and texture
    filtering evaluated by the CPU's maths instead of llvmpipe's): colour
    within 1e-3 and depth within 1e-6 relative, but for at most 0.05 % of
    the pixels (coverage ties on disc and quad edges)."""
    params = dict(NATIVE_CASES[case])
    if case == "image":
        ramp = np.zeros((8, 32, 4), np.float32)
        ramp[..., 3] = np.linspace(0.0, 1.0, 32)[None, :]  # black, opaque towards the stroke's end
        params["texture_image"] = str(tmp_path / "ramp.png")
        pointnpr.save_image(params["texture_image"], ramp)
    if case == "hidden walls":
        clouds, cam = [_two_walls()], camera()
    else:
        clouds = [pointnpr.PointCloud(box() @ rotation(0.5, 0.6).T + np.array([0.0, 0.0, -4.0]))]
        cam = pointnpr.Camera.orthographic(np.eye(4), 3.0, width=W, height=H) if case == "orthographic" else camera()
    gl, native = _on_both_paths(renderer, params, clouds, cam)
    for key in ("strokes_drawn", "strokes_directional", "strokes_non_directional", "strokes_dithering", "queue_points"):
        assert gl.stats[key] == native.stats[key], key
    assert gl.stats["strokes_drawn"] > 1000
    for key in ("point_id", "kind"):
        assert np.array_equal(np.asarray(gl.marks[key]), np.asarray(native.marks[key])), key
    assert np.allclose(np.asarray(gl.marks["center"]), np.asarray(native.marks["center"]), rtol=0, atol=1e-6)
    a, b = np.asarray(gl.color), np.asarray(native.color)
    covered = (a[..., 3] > 0).sum()
    assert covered > 3000
    allowed = 0.0005 * a[..., 0].size
    assert (np.abs(a - b).max(axis=-1) > 1e-3).sum() <= allowed
    da, db = np.asarray(gl.depth), np.asarray(native.depth)
    same = (np.isinf(da) & np.isinf(db)) | np.isclose(da, db, rtol=1e-6, atol=0)
    assert (~same).sum() <= allowed


def _native_digest(renderer):
    import hashlib
    pos = box() @ rotation(0.5, 0.6).T + np.array([0.0, 0.0, -4.0])
    clouds = [pointnpr.PointCloud(pos), _two_walls()]
    scene = pointnpr.Scene()
    style = pointnpr.Style(mark=("feature_strokes", {**PAPER, "rasterizer": "native", "dither": 0.5, "coloring": "point",
                                                     "stroke_texture": "brush", "dithering": "point_sprite"}))
    scene.add_segment("s", style, [(c, np.eye(4)) for c in clouds])
    r = renderer.render(scene, camera(), W, H)
    return hashlib.sha256(np.asarray(r.color).tobytes() + np.asarray(r.depth).tobytes()).hexdigest()


def test_the_native_path_draws_the_same_bytes_with_one_thread_in_another_process(renderer):
    assert one_thread_in_another_process("test_marks_feature_strokes", "_native_digest") == _native_digest(renderer)


# ---------------------------------------------------------------------------
# The queue on the points mark (the project's level of detail)

def _points(renderer, params, c, z):
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("points", params)), [(c, np.eye(4))])
    r = renderer.render(scene, camera(z), W, H, background=(1, 1, 1, 0))
    return np.asarray(r.color)[..., 3] > 0


@pytest.mark.parametrize("rasterizer", ["compute", "gl_points", "native"])
def test_points_mark_keeps_its_density_on_screen_with_the_queue(renderer, rasterizer):
    pos, _ = wall(1.2, 0.9, 0.005, -4.0)
    c = pointnpr.PointCloud(pos)
    f = 50.0 / 36.0 * W
    params = {"rasterizer": rasterizer, "point_size": 1.5, "color_source": "constant",
              "density_mode": "constant_on_screen", "queue_level": 0.1}
    fractions = []
    for z, distance in ((0.0, 4.0), (4.0, 8.0)):
        covered = _points(renderer, params, c, z).sum()
        area = (1.2 * f / distance) * (0.9 * f / distance)
        fractions.append(covered / area)
    assert 0.05 < fractions[0] < 0.5
    assert abs(fractions[1] / fractions[0] - 1.0) < 0.15, fractions
    # Off: every point, the far wall fully covered.
    off = _points(renderer, dict(params, density_mode="all_points"), c, 4.0).sum()
    assert off / ((1.2 * f / 8.0) * (0.9 * f / 8.0)) > 0.9


def test_points_mark_rasterizers_draw_the_same_queue_points(renderer):
    pos, _ = wall(1.2, 0.9, 0.005, -4.0)
    c = pointnpr.PointCloud(pos)
    # 3 px discs: the rasterizers' coverage rules agree exactly there.
    params = {"point_size": 3.0, "color_source": "constant", "density_mode": "constant_on_screen", "queue_level": 0.02}
    a = _points(renderer, dict(params, rasterizer="compute"), c, 0.0)
    b = _points(renderer, dict(params, rasterizer="gl_points"), c, 0.0)
    n = _points(renderer, dict(params, rasterizer="native"), c, 0.0)
    full = _points(renderer, dict(params, density_mode="all_points"), c, 0.0)
    assert 1000 < a.sum() < 0.5 * full.sum()
    assert np.array_equal(a, b) and np.array_equal(a, n)


def test_hatching_mark_keeps_its_stroke_density_on_screen_with_the_queue():
    renderer = pointnpr.Renderer()
    pos, _ = wall(1.2, 0.9, 0.005, -4.0)
    c = pointnpr.PointCloud(pos, normals=np.tile(np.float32([0, 0, 1]), (len(pos), 1)))
    params = {"density_mode": "constant_on_screen", "queue_level": 0.05, "stroke_coverage": 0.0,
              "xtoon": "ink", "light_space": "camera", "light_elevation": 80.0, "paper_color": [1, 1, 1, 1]}
    dens = []
    for z in (0.0, 4.0):
        scene = pointnpr.Scene()
        scene.add_segment("s", pointnpr.Style(mark=("hatching", params)), [(c, np.eye(4))])
        r = renderer.render(scene, camera(z), W, H, background=(1, 1, 1, 0))
        dens.append(r.stats["strokes_drawn"] / (np.asarray(r.color)[..., 3] > 0).sum())
    assert dens[1] > 0.01
    assert abs(dens[1] / dens[0] - 1.0) < 0.15, dens


# ---------------------------------------------------------------------------
# Visibility discs in the tangent plane

def test_a_surface_seen_edge_on_hides_no_more_than_its_own_strip(renderer, path):
    # A sparse plane tilted 84 degrees from the view: it projects to a thin
    # strip, and its discs (in its tangent plane, feature_strokes_disc.glsl)
    # to slivers inside that strip. Round discs of its 3D spacing (about
    # 15 px across here) would paint paper 7 px beyond it.
    g = np.arange(-0.6, 0.6 + 1e-9, 0.06)
    A, B = np.meshgrid(g, g)
    flat = np.column_stack([A.ravel(), B.ravel(), np.zeros(A.size)])
    pos = flat @ rotation(np.radians(84.0), 0.0).T + np.array([0.0, 0.0, -3.0])
    normals = np.tile((rotation(np.radians(84.0), 0.0) @ [0.0, 0.0, 1.0]).astype(np.float32), (len(pos), 1))
    plane = pointnpr.PointCloud(pos, normals=normals)
    params = {"directional": "none", "non_directional": "none", "dithering": "point_sprite", "dither": 1.0}
    drawn = np.asarray(render(renderer, params, [plane], background=(0, 0, 0, 0)).color)[..., 3] > 0
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("points", {"point_size": 1.0})), [(plane, np.eye(4))])
    dots = np.asarray(renderer.render(scene, camera(), W, H, background=(0, 0, 0, 0)).color)[..., 3] > 0
    rows = np.nonzero(dots.any(axis=1))[0]
    assert drawn.sum() > 0 and len(rows) < 0.2 * H
    # Within 2 px of the rows the points cover (round discs: about 7).
    assert not drawn[:max(rows.min() - 2, 0)].any() and not drawn[rows.max() + 3:].any()


def test_a_point_alone_beside_the_scan_gets_no_disc_larger_than_the_scan_s_sparse_spacing(renderer, path):
    # A wall and, beside it, nine points 0.2 apart (10x the wall's spacing,
    # each other's nearest neighbours: a stray cluster, as the lion's sky
    # has). Their discs, sized by their own spacing, were 40 px wide patches
    # of paper in the sky; capped at twice the scan's sparse spacing they
    # stay within a few pixels of their points.
    pos, _ = wall(1.0, 1.0, 0.02, -4.0)
    g = np.arange(3) * 0.2
    stray = np.column_stack([0.45 + np.repeat(g, 3), 0.2 + np.tile(g, 3), np.full(9, -4.0)])
    c = pointnpr.PointCloud(np.vstack([pos - [0.5, 0.0, 0.0], stray]))
    params = {"directional": "none", "non_directional": "none", "dithering": "point_sprite", "dither": 0.5}
    drawn = np.asarray(render(renderer, params, [c], background=(0, 0, 0, 0)).color)[..., 3] > 0
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("points", {"point_size": 1.0})), [(c, np.eye(4))])
    dots = np.asarray(renderer.render(scene, camera(), W, H, background=(0, 0, 0, 0)).color)[..., 3] > 0
    ys, xs = np.nonzero(dots)
    near = np.zeros_like(dots)
    for y, x in zip(ys, xs):
        near[max(y - 8, 0):y + 9, max(x - 8, 0):x + 9] = True
    assert drawn.sum() > 1000 and (drawn & ~near).sum() == 0, (drawn & ~near).sum()
