"""Every parameter of every mark acts (issue 39, "every parameter alive"):
the sweep of param_sweep.py (its measure and the values it tries are stated
there) with each mark's own style, on real scans at 320x180: the lion
(photogrammetry, every 4th point) as a Gaussian-splat capture (its points
small splats of its own spacing with their colours and a per-point
opacity, so the gaussians mark draws it and the settings that weigh
opacity act) and the LiDAR HD tile seen low and oblique without its colours
(aerial, intensity and classes only, so `auto` colour and shading resolve
the other way; sparse, with depth jumps of every size), then its positions
alone (where the constant colour and the light of a colourless scan act).

Colour parameters start tinted (a grey has no hue to turn or to match to
pencils), as path parameters start set to an image; light or dark, they
stay so (ink on paper stays visible).

A picture here is a segment's colour and depth (its depth decides what it
hides when segments and meshes composite). Parameters of how a mark is
drawn rather than what (SAME_PICTURE) are asserted to change no more than
MIN_SHARE. The meshes' surface (mesh_surface) is swept on three spheres:
textured, vertex-coloured and bare."""
import functools
import os

import numpy as np
import pytest

import pointnpr
from param_sweep import MIN_SHARE, changed_share, dead_parameters, grey_ramp_image, other_values, base_settings

W, H = 320, 180
DATA = os.path.join(os.path.dirname(__file__), "..", "..", "data")
MARKS = [s for s in pointnpr.schemas() if s["kind"] == "mark"]
SURFACE = "mesh_surface"  # the segment's meshes, drawn beside its point mark: a style's surface
# How a mark is drawn, not what: the backend (the parity tests compare its
# bytes), the points' GL method (compute or GL points) and the brush's exact
# path for tiles, so tiled frames match whole ones. Each is asserted to keep
# the picture instead.
SAME_PICTURE = ("rasterizer", "gl_method", "tile_invariant")
# Values the host gives their meaning: scene_sun is the world light whose
# direction Blender sets from its sun lamp (tests/blender/test_marks.py
# turns the sun and sees the render change).
HOST_VALUES = {("light_space", "scene_sun")}
# Settings the sweep's values or these scans cannot show, each shown by a
# test of its own: the thresholds of a capture's floaters, whose ranges
# start at 0 (off) and reach far, so the quarter points (2,500 units, 250x
# the spacing) drop no splat of any real capture (test_marks_gaussians.py
# drops floaters at 0.05 and 4x); and the pencils, which keep a colour's
# value and saturation (seed 002, 3.3), so they move only saturated
# colours, which these scans have few of (test_marks.py's pencil test, on
# random colours); and the hatching strokes' growth where the points lie too
# sparse on screen for their coverage, which these scans at 320x180 never
# do (test_marks_hatching_sparse.py).
ACTS_ON_OTHER_DATA = {"gaussians": ("max_scale", "isolation"),
                      "hatching": ("pencil_quantize", "pencil_set", "grow_sparse_strokes")}


def _capture(pos, colors, seed=3):
    """The points as a Gaussian-splat capture of their own spacing: splats
    elongated and turned at random, a per-point opacity, view-dependent
    colour to the third band, and a few large faint floaters (so the
    largest radius and the depth's opacity act)."""
    rng = np.random.default_rng(seed)
    n = len(pos)
    lo, hi = pos.min(axis=0), pos.max(axis=0)
    spacing = float(np.sqrt(np.prod(np.sort(hi - lo)[1:]) / n))
    scales = spacing * np.exp(rng.normal(-0.4, 0.4, (n, 3)))
    opacity = rng.uniform(0.2, 1.0, n)
    floaters = rng.choice(n, n // 200, replace=False)
    scales[floaters] *= 40.0
    opacity[floaters] = 0.15
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    sh = np.zeros((n, 16, 3))
    sh[:, 0] = (np.asarray(colors, float) / 255.0 - 0.5) / 0.28209479177387814
    sh[:, 1:] = rng.normal(0.0, 0.3, (n, 15, 3))
    return dict(opacity=opacity, scales=scales, rotations=q, sh=sh, sh_degree=3)


@functools.lru_cache(maxsize=None)
def _read(path):
    return pointnpr.read(path)  # the tile is drawn twice: read once


def _scan(path, step, attributes):
    """Every `step`th point of a scan file: "capture" a Gaussian-splat
    capture with its colours, "scalars" its intensity and classes alone,
    "none" its positions alone."""
    data = _read(path)
    pos = np.asarray(data.positions)[::step]
    attrs = {k: np.asarray(v)[::step] for k, v in data.attributes.items()}
    if attributes == "capture":
        return pointnpr.PointCloud(pos, colors=attrs["colors"], **_capture(pos, attrs["colors"]))
    if attributes == "scalars":
        return pointnpr.PointCloud(pos, **{k: attrs[k] for k in ("intensity", "classification") if k in attrs})
    return pointnpr.PointCloud(pos)


@pytest.fixture(scope="module")
def scans():
    lion = _scan(os.path.join(DATA, "lion_takanawa.ply"), 4, "capture")
    lion_cam = pointnpr.Camera.perspective(pointnpr.look_at((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)), lens=35.0,
                                           clip_start=0.1, clip_end=100.0, width=W, height=H)
    tile_path = os.path.join(DATA, "lidarhd_myria3d_870000_6618000_subset.las")
    tile = _scan(tile_path, 1, "scalars")
    lo, hi = np.asarray(tile.bounds[0]), np.asarray(tile.bounds[1])
    centre = (lo + hi) / 2
    tile_cam = pointnpr.Camera.perspective(pointnpr.look_at(centre + (0.0, -80.0, 35.0), centre), lens=35.0,
                                           clip_start=0.5, clip_end=1000.0, width=W, height=H)
    return [(lion, lion_cam), (tile, tile_cam), (_scan(tile_path, 1, "none"), tile_cam)]


def _sphere_mesh(with_texture, with_colors, rows=24, cols=48):
    """A UV sphere of radius 1 at (0, 0, -4); with vertex colours, a checker
    texture and a base colour, with vertex colours and a base colour, or
    bare."""
    theta = np.linspace(0.0, np.pi, rows + 1)
    phi = np.linspace(0.0, 2.0 * np.pi, cols + 1)
    T, P = np.meshgrid(theta, phi, indexing="ij")
    v = np.column_stack([(np.sin(T) * np.cos(P)).ravel(), (np.sin(T) * np.sin(P)).ravel(),
                         np.cos(T).ravel() - 4.0])
    idx = np.arange((rows + 1) * (cols + 1)).reshape(rows + 1, cols + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])]).astype(np.int64)
    kwargs = dict(base_color=(0.3, 0.5, 0.8)) if with_colors else {}
    if with_colors:
        kwargs["colors"] = np.column_stack([0.5 + 0.5 * np.sin(3 * P.ravel()), 0.5 + 0.5 * np.cos(2 * T.ravel()),
                                            np.full(v.shape[0], 0.3)])
    if with_texture:
        check = (np.indices((64, 64)).sum(axis=0) // 8) % 2
        tex = np.full((64, 64, 4), 255, np.uint8)
        tex[..., 0], tex[..., 1] = 230 * check, 50 + 150 * (1 - check)
        kwargs.update(uvs=np.column_stack([P.ravel() / (2 * np.pi), T.ravel() / np.pi]), texture=tex)
    return pointnpr.TriangleMesh(v, tri, **kwargs)


@pytest.fixture(scope="module")
def meshes():
    """A textured and a vertex-coloured sphere, and a bare one, each alone."""
    # Seen from the side and above, so that world and camera lights differ.
    camera = pointnpr.Camera.perspective(pointnpr.look_at((2.5, -2.5, -2.0), (0.0, 0.0, -4.0)), lens=35.0,
                                         clip_start=0.1, clip_end=100.0, width=W, height=H)
    return [(_sphere_mesh(True, True), camera), (_sphere_mesh(False, True), camera),
            (_sphere_mesh(False, False), camera)]


@pytest.fixture(scope="module")
def image(tmp_path_factory):
    return grey_ramp_image(str(tmp_path_factory.mktemp("mark_sweep") / "ramp.png"))


TINT = np.array([0.75, 0.3, 0.15])


def _tinted(schema):
    """The schema with its colour parameters' defaults halfway to orange."""
    params = [dict(p, default=tuple(0.5 * (np.asarray(p["default"][:3]) + TINT)) + (p["default"][3],))
              if p["type"] == "color" else p for p in schema["params"]]
    return dict(schema, params=params)


def _render(renderer, scan, style):
    drawn, camera = scan
    scene = pointnpr.Scene()
    scene.add_segment("scan", style, [drawn] if isinstance(drawn, pointnpr.TriangleMesh) else [(drawn, np.eye(4))])
    result = renderer.render(scene, camera, W, H, background=(1, 1, 1, 1))
    return np.asarray(result.color)[..., :3], np.asarray(result.depth)


@pytest.mark.parametrize("schema", MARKS, ids=[s["id"] for s in MARKS])
def test_every_parameter_changes_the_picture(renderer, scans, meshes, image, schema):
    if schema["id"] == SURFACE:
        own, style = meshes, lambda settings: pointnpr.Style(surface=settings)
    else:
        own, style = scans, lambda settings: pointnpr.Style(mark=(schema["id"], settings))
    dead = dead_parameters(_tinted(schema), lambda settings, i: _render(renderer, own[i], style(settings)),
                           len(own), image, skip=SAME_PICTURE + ACTS_ON_OTHER_DATA.get(schema["id"], ()),
                           skip_values=HOST_VALUES)
    assert not dead, "%s: parameters that change no picture:\n  %s" % (schema["id"], "\n  ".join(dead))


CHOICES = [(s, p) for s in MARKS for p in s["params"] if p["name"] in SAME_PICTURE]


@pytest.mark.parametrize("schema,param", CHOICES, ids=["%s.%s" % (s["id"], p["name"]) for s, p in CHOICES])
def test_how_a_mark_is_drawn_keeps_the_picture(renderer, scans, image, schema, param):
    base = base_settings(schema, image)
    if param["when"] and param["when"]["param"] == "rasterizer":
        base["rasterizer"] = "gl"  # a GL method acts on the GL backend (auto picks native on llvmpipe)
    for value in other_values(param, base[param["name"]], image):
        for scan in scans:
            share = changed_share(_render(renderer, scan, pointnpr.Style(mark=(schema["id"], base))),
                                  _render(renderer, scan, pointnpr.Style(mark=(schema["id"],
                                                                                dict(base, **{param["name"]: value})))))
            assert share < MIN_SHARE, (value, share)


def test_the_sweep_finds_a_setting_that_does_not_apply(renderer, scans, image):
    """The sweep itself: the brush's second-layer tint, its condition (two
    layers, or clusters) taken away, is found to change nothing with one
    layer; with the condition it is swept where it applies and acts."""
    schema = pointnpr.schema("brush_splats", "mark")
    tint = [p for p in schema["params"] if p["name"] in ("layers", "layer_tint")]
    bare = dict(schema, params=[dict(p, when=None) for p in tint])
    declared = dict(schema, params=tint)

    def draw(settings, i):
        return _render(renderer, scans[i], pointnpr.Style(mark=("brush_splats", settings)))
    found = dead_parameters(bare, draw, len(scans), image, skip=("layers",))
    assert len(found) == 1 and found[0].startswith("layer_tint"), found
    assert dead_parameters(declared, draw, len(scans), image, skip=("layers",)) == []
