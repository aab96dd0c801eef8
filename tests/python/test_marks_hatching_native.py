"""The hatching mark's native backend (cpp/marks/hatching/native.cpp)
against its GL passes: the same kernels (shaders/hatching_kernels.glsl,
hatching_quad.glsl) compiled for both, so the same strokes and the same
images but for the last bits of pow, exp, sin and cos (llvmpipe's maths
against the CPU's) and the depth pass's disc rims: the native backend tests
against the points mark's native discs, the GL one against GL_POINTS, and
a pixel where those two draw another disc (the points mark's own
gl_points/native difference, 0.2 % of the lion's pixels with 4 px discs)
may show another surface. Tolerances: colour within 1e-3 and depth within
1e-5 relative everywhere but on those pixels and at most 0.1 % of the
others (measured: at most 0.035 % of all pixels on the lion and the LiDAR
tile, every hatching preset)."""
import hashlib
import os

import numpy as np
import pytest

import pointnpr
from conftest import one_thread_in_another_process

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
W, H = 320, 224


@pytest.fixture(scope="module")
def lion():
    return pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()


def _camera(ortho=False):
    view = pointnpr.look_at((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2))
    if ortho:
        return pointnpr.Camera.orthographic(view, 4.0, width=W, height=H, clip_start=0.1, clip_end=100.0)
    return pointnpr.Camera.perspective(view, lens=35.0, clip_start=0.1, clip_end=100.0, width=W, height=H)


def _render(renderer, cloud, params, rasterizer, cam=None):
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("hatching", dict(params, rasterizer=rasterizer))), [(cloud, np.eye(4))])
    return renderer.render(scene, cam or _camera(), W, H, background=(1, 1, 1, 0), capture_marks=True)


CASES = {
    "defaults": {},
    "world units": {"units": "world", "world_length": 0.06, "world_width": 0.006, "depth_disc": "world",
                    "depth_world_size": 0.02},
    "pixel discs": {"depth_disc": "pixels", "depth_size": 5.0},
    "crayon, point colours, pencils": {"stroke_texture": "crayon", "coloring": "point", "pencil_quantize": True,
                                       "hue_shift": 30.0, "xtoon": "wax_crayon"},
    "irregular, specular": {"placement": "irregular", "angle_jitter": 40.0, "specular": 0.6, "shininess": 8.0,
                            "two_sided": True, "stroke_texture": "soft"},
    "no depth pass, ink": {"depth_pass": False, "stroke_texture": "ink", "xtoon": "ink", "coloring": "xtoon"},
    "queue": {"density_mode": "constant_on_screen", "queue_level": 0.3, "stroke_coverage": 0.0,
              "curvature_length": 0.0},
    "orthographic": {"xtoon": "two_colored", "coloring": "xtoon"},
}


def _disc_diameter(cloud, params):
    """The depth discs' diameter in scene units: depth_world_size, or by
    default depth_spacing (2) median spacings (the upper median of the mean
    distance to 8 neighbours, as the mark takes it)."""
    if params.get("depth_disc") == "world":
        return params["depth_world_size"]
    r = np.asarray(pointnpr.local_resolution(cloud, 8)[0])
    return float(params.get("depth_spacing", 2.0)) * float(np.partition(r, len(r) // 2)[len(r) // 2])


def _disc_rims(renderer, cloud, params, cam):
    """Pixels where the depth pass's discs differ between GL_POINTS and the
    native rasterizer (the points mark with the same discs)."""
    if params.get("depth_pass") is False:
        return np.zeros((H, W), bool)
    size = {"size_mode": "world", "world_size": _disc_diameter(cloud, params)}
    if params.get("depth_disc") == "pixels":
        size = {"point_size": params.get("depth_size", 4.0)}
    depth = []
    for rz in ("gl_points", "native"):
        scene = pointnpr.Scene()
        scene.add_segment("s", pointnpr.Style(mark=("points", dict(size, rasterizer=rz))), [(cloud, np.eye(4))])
        depth.append(np.asarray(renderer.render(scene, cam, W, H).depth))
    a, b = depth
    return ~((np.isinf(a) & np.isinf(b)) | (a == b))


@pytest.mark.parametrize("case", list(CASES))
def test_the_native_backend_draws_the_gl_passes_strokes_and_images(renderer, lion, case):
    cam = _camera(ortho=case == "orthographic")
    gl = _render(renderer, lion, CASES[case], "gl", cam)
    native = _render(renderer, lion, CASES[case], "native", cam)
    assert "native_select_ms" in native.stats and "native_select_ms" not in gl.stats
    for key in ("strokes_drawn", "strokes_crossed"):
        assert gl.stats[key] == native.stats[key], key
    assert gl.stats["strokes_drawn"] > 500
    for key in ("point_id", "crossed"):
        assert np.array_equal(np.asarray(gl.marks[key]), np.asarray(native.marks[key])), key
    assert np.allclose(np.asarray(gl.marks["center"]), np.asarray(native.marks["center"]), rtol=0, atol=1e-5)
    rims = _disc_rims(renderer, lion, CASES[case], cam)
    assert rims.mean() < 0.005
    a, b = np.asarray(gl.color), np.asarray(native.color)
    assert (a[..., 3] > 0).sum() > 5000
    allowed = 0.001 * a[..., 0].size
    assert ((np.abs(a - b).max(axis=-1) > 1e-3) & ~rims).sum() <= allowed
    da, db = np.asarray(gl.depth), np.asarray(native.depth)
    same = (np.isinf(da) & np.isinf(db)) | np.isclose(da, db, rtol=1e-5, atol=0)
    assert (~same & ~rims).sum() <= allowed


def test_auto_takes_the_native_backend_on_a_software_device(renderer, lion):
    r = _render(renderer, lion, {}, "auto")
    assert ("native_select_ms" in r.stats) == pointnpr.gl_info()["software"]


def test_an_xtoon_image_is_sampled_alike(renderer, lion, tmp_path):
    ramp = np.zeros((4, 64, 4), np.float32)
    ramp[..., :3] = 0.1
    ramp[..., 3] = np.linspace(1.0, 0.0, 64)[None, :]  # dark: every stroke; lit: none
    path = str(tmp_path / "xtoon.png")
    pointnpr.save_image(path, ramp)
    params = {"xtoon": "image", "xtoon_image": path, "coloring": "xtoon"}
    gl, native = (_render(renderer, lion, params, rz) for rz in ("gl", "native"))
    assert gl.stats["strokes_drawn"] == native.stats["strokes_drawn"] > 500
    a, b = np.asarray(gl.color), np.asarray(native.color)
    assert (np.abs(a - b).max(axis=-1) > 1e-3).sum() <= 0.001 * a[..., 0].size


def _digest(renderer):
    cloud = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()
    r = _render(renderer, cloud, {"coloring": "point", "stroke_texture": "crayon", "placement": "irregular"}, "native")
    return hashlib.sha256(np.asarray(r.color).tobytes() + np.asarray(r.depth).tobytes()).hexdigest()


def test_the_native_backend_draws_the_same_bytes_with_one_thread_in_another_process(renderer):
    assert one_thread_in_another_process("test_marks_hatching_native", "_digest") == _digest(renderer)
