"""The brush_splats mark's native path (cpp/marks/brush_splats/native*.cpp,
`rasterizer` native, and auto on software GL for blur and none) against
its GL passes (cpp/marks/brush_splats/brush_splats.cpp), on the lion at the golden
camera; its bytes in another process with one thread, and its tiles
(tests/python/test_marks_brush_splats.py runs the tiled frames on both
paths, and its other behaviour tests on whatever auto picks).

Tolerance: the golden images' (a channel within 2/255) on at least 99 % of
the pixels; the native brush is a fitted exp(-q^lambda / 2) and the
quad's edges are decided by uv in [0, 1] rather than the GL's fixed-point
edges, so a splat edge pixel now and then falls to the other splat."""
import hashlib
import os

import numpy as np
import pytest

import pointnpr
from conftest import one_thread_in_another_process
from pointnpr import presets

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
W, H = 320, 224


@pytest.fixture(scope="module")
def lion():
    return pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()


def _camera(width=W, height=H):
    return pointnpr.Camera.perspective(pointnpr.look_at((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)), lens=35.0,
                                       clip_start=0.1, clip_end=100.0, width=width, height=height)


def _render(renderer, params, cloud, capture=False, **kw):
    scene = pointnpr.Scene()
    scene.add_segment("scan", pointnpr.Style(mark=("brush_splats", params)), [(cloud, np.eye(4))])
    return renderer.render(scene, _camera(), W, H, background=(1, 1, 1, 0), capture_marks=capture, **kw)


CASES = {"blur": {}, "none": {"blending": "none"}, "two layers": {"layers": "two", "layer_tint": -0.3},
         "clusters": {"clusters": True, "small_cluster": 400},
         "covariance frame, user eps": {"tangent_frame": "covariance", "epsilon_mode": "user", "epsilon": 0.002},
         "queue": {"density_mode": "constant_on_screen", "queue_level": 2.0}}
CASES.update({name: p["mark"][1] for name, p in presets.PRESETS.items() if p["mark"][0] == "brush_splats"})


@pytest.mark.parametrize("case", list(CASES))
def test_the_native_path_draws_the_gl_paths_image(renderer, lion, case):
    gl, native = (_render(renderer, dict(CASES[case], rasterizer=r), lion, capture=True) for r in ("gl", "native"))
    assert gl.stats["splats_drawn"] == native.stats["splats_drawn"] > 0
    assert "brush_native_blend_ms" in native.stats and "brush_native_blend_ms" not in gl.stats
    # The same splats captured (the capture is the GL's on both paths).
    assert np.array_equal(np.asarray(gl.marks["point_id"]), np.asarray(native.marks["point_id"]))
    a, b = np.asarray(gl.color), np.asarray(native.color)
    covered = a[..., 3] > 0
    assert covered.mean() > 0.2
    assert ((b[..., 3] > 0) != covered).mean() <= 0.001
    assert (np.abs(a - b).max(axis=-1) > 2.0 / 255.0).mean() <= 0.01
    da, db = np.asarray(gl.depth), np.asarray(native.depth)
    same = (np.isinf(da) & np.isinf(db)) | np.isclose(da, db, rtol=1e-3, atol=0)
    assert (~same).mean() <= 0.005


def test_the_native_path_is_closer_still_to_the_gl_exact_path(renderer, lion):
    # Its rules are the tile-invariant passes' (brush_splats_tiled.*): per
    # frame pixel, the same moved-depth test.
    exact = _render(renderer, {"rasterizer": "gl", "tile_invariant": True}, lion)
    native = _render(renderer, {"rasterizer": "native"}, lion)
    a, b = np.asarray(exact.color), np.asarray(native.color)
    assert (np.abs(a - b).max(axis=-1) > 2.0 / 255.0).mean() <= 0.005


def test_auto_is_native_on_software_gl_for_blur_and_none_and_gl_for_the_a_buffer(renderer, lion):
    software = bool(pointnpr.gl_info()["software"])
    for blending, native in (("blur", software), ("none", software), ("a_buffer", False)):
        r = _render(renderer, {"blending": blending}, lion)
        assert ("brush_native_blend_ms" in r.stats) == native, blending
    # Asked for, the A-buffer is still GL's lists (and their stats).
    r = _render(renderer, {"blending": "a_buffer", "rasterizer": "native"}, lion)
    assert "brush_native_blend_ms" not in r.stats and r.stats["a_buffer_fragments"] > 0


def test_the_native_path_draws_the_same_bytes_frame_after_frame(renderer, lion):
    """Splats blend in point order per screen bin, whatever order the
    threads ran the bins in."""
    first = _render(renderer, {"rasterizer": "native"}, lion)
    again = _render(renderer, {"rasterizer": "native"}, lion)
    assert np.asarray(first.color).tobytes() == np.asarray(again.color).tobytes()
    assert np.asarray(first.depth).tobytes() == np.asarray(again.depth).tobytes()


def _digest(result):
    """The bytes of a frame's colour and depth, as a digest."""
    return hashlib.sha256(np.asarray(result.color).tobytes() + np.asarray(result.depth).tobytes()).hexdigest()


def _native_digest(renderer):
    cloud = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()
    r = _render(renderer, {"rasterizer": "native", "layers": "two", "clusters": True}, cloud)
    return _digest(r)


def test_the_kept_point_frames_follow_every_parameter_they_are_made_from(renderer, lion):
    # The camera-independent part of each splat (axes, radius, stretch,
    # layers, column angles) is kept per cloud between frames; a frame after
    # a change of any parameter it follows draws a fresh renderer's bytes.
    def image(r, params):
        return _digest(_render(r, dict(params, rasterizer="native"), lion))

    before = image(renderer, {})
    for params in ({"seed": 3}, {"brush_angle": 30.0}, {"angle_jitter": 40.0}, {"tangent_frame": "eberly"},
                   {"layers": "two"}, {"size_scale": 2.0}, {"epsilon_mode": "user", "epsilon": 0.004},
                   {"size_mode": "world", "world_radius": 0.01}, {"normals": "radius_3r"}, {"normal_neighbors": 8},
                   {"resolution_neighbors": 12}, {"clusters": True, "small_cluster": 400},
                   {"clusters": True, "max_stretch": 1.5}):
        changed = image(renderer, params)
        assert changed != before, params
        assert changed == image(pointnpr.Renderer(), params), params
        assert image(renderer, {}) == before, params


def test_the_native_path_draws_the_same_bytes_with_one_thread_in_another_process(renderer):
    assert one_thread_in_another_process("test_marks_brush_splats_native", "_native_digest") == \
        _native_digest(renderer)


def test_the_scalar_lanes_draw_the_vector_lanes_bytes(renderer):
    """The brush, the rows and their fragments run on Highway's widest
    target the CPU has, one source for every target: the same float
    operations in the same order, so the same bytes as the scalar target
    (forced here by native_limits, in the same renderer; tests/cpp runs
    every target the CPU has)."""
    cloud = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()
    params = {"rasterizer": "native", "layers": "two", "clusters": True}
    scalar = _render(renderer, params, cloud, native_limits={"scalar_lanes": True})
    assert scalar.stats["brush_native_lanes"] == 1
    lanes = _render(renderer, params, pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud())
    with open("/proc/cpuinfo") as f:
        assert lanes.stats["brush_native_lanes"] == (8 if " avx2" in f.read() else 4)
    assert _digest(scalar) == _digest(lanes)


def test_native_limits_are_checked():
    with pytest.raises(pointnpr.ParameterError, match="unknown limit 'batch'"):
        _render(pointnpr.Renderer(), {"rasterizer": "native"}, _tiny_cloud(), native_limits={"batch": 3})
    with pytest.raises(pointnpr.ParameterError, match="max_bins must be 0"):
        _render(pointnpr.Renderer(), {"rasterizer": "native"}, _tiny_cloud(), native_limits={"max_bins": -1})


def _tiny_cloud():
    return pointnpr.PointCloud(np.random.default_rng(0).uniform(-0.5, 0.5, (100, 3)))


def _setup_digests(renderer, limits=None):
    """Digests of frames whose splats set up every branch: points without a
    normal (half of them), perspective and orthographic, the queue's order;
    and a wide blur of a view the scan fills past the image's edges."""
    data = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply"))
    normals = np.random.default_rng(3).normal(size=(data.num_points, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    normals[::2] = 0.0
    cloud = pointnpr.PointCloud(np.asarray(data.positions, float), colors=np.asarray(data.attributes["colors"]),
                                normals=normals.astype(np.float32))
    view = pointnpr.look_at((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2))
    out = []
    for camera, params in (("perspective", {}), ("orthographic", {}),
                           ("perspective", {"density_mode": "constant_on_screen", "queue_level": 2.0}),
                           ("close", {"blur_radius": 6})):
        scene = pointnpr.Scene()
        scene.add_segment("scan", pointnpr.Style(mark=("brush_splats", dict(params, rasterizer="native"))),
                          [(cloud, np.eye(4))])
        common = dict(clip_start=0.1, clip_end=100.0, width=W, height=H)
        cam = (pointnpr.Camera.orthographic(view, ortho_scale=6.0, **common) if camera == "orthographic" else
               pointnpr.Camera.perspective(view, lens=120.0 if camera == "close" else 35.0, **common))
        r = renderer.render(scene, cam, W, H, background=(1, 1, 1, 0), native_limits=limits or {})
        covered = np.asarray(r.color)[..., 3] > 0
        assert covered.mean() > 0.2
        if camera == "close":  # (the blur's taps reach past the image's edges)
            assert covered[:, 0].any() and covered[:, -1].any()
        out.append(_digest(r))
    return out


def test_the_scalar_setup_and_blur_make_the_vector_bytes(renderer):
    """Splats are set up, and the blur runs, a vector at a time (eight on
    AVX2) or one by one on the scalar target: the same bytes, also for
    points without a normal, orthographic views, the queue's order and a
    blur at the image's edges."""
    assert _setup_digests(renderer, {"scalar_lanes": True}) == _setup_digests(renderer)


def _passes(renderer, limits=None):
    """Digests and pass statistics of frames whose bins fit their candidates,
    and of one (big splats on a small frame) where some bins hold more."""
    cloud = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()
    out = []
    for params in ({"layers": "two", "clusters": True}, {"size_scale": 8.0}, {"size_scale": 8.0, "camera": "ortho"}):
        params = dict(params, rasterizer="native")
        if params.pop("camera", None) == "ortho":
            scene = pointnpr.Scene()
            scene.add_segment("scan", pointnpr.Style(mark=("brush_splats", params)), [(cloud, np.eye(4))])
            cam = pointnpr.Camera.orthographic(pointnpr.look_at((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)), ortho_scale=4.0,
                                               clip_start=0.1, clip_end=100.0, width=W, height=H)
            r = renderer.render(scene, cam, W, H, background=(1, 1, 1, 0), native_limits=limits or {})
        else:
            r = _render(renderer, params, cloud, native_limits=limits or {})
        out.append({"digest": _digest(r),
                    "batches": r.stats["brush_native_batches"],
                    "kept frames": r.stats["brush_native_clouds_with_kept_frames"],
                    "apart": r.stats["brush_native_bins_blended_apart"]})
    return out


def test_one_pass_with_candidates_draws_the_two_passes_bytes(renderer):
    """With one batch of splats, each bin's depth pass keeps the fragments
    near its surface, with their brush, and blends those that stay near the
    final surface; a bin with more than its bound of them, and frames of
    several batches (forced here by native_limits' batch_splats), run the
    blend pass apart: the same bytes either way."""
    apart = _passes(renderer, {"batch_splats": 50000})
    merged = _passes(renderer)
    assert [f["batches"] for f in merged] == [1, 1, 1] and all(f["batches"] > 1 for f in apart)
    assert merged[0]["apart"] == 0 and merged[1]["apart"] > 0 and merged[2]["apart"] > 0
    assert [f["digest"] for f in merged] == [f["digest"] for f in apart]


def test_clouds_too_large_to_keep_their_point_frames_make_them_per_splat_to_the_same_bytes(renderer):
    """Point frames are kept for clouds of up to 4M points (60 bytes each);
    a larger cloud makes them per splat in every frame: forced here for the
    lion by native_limits' kept_frames_max = 1."""
    made = _passes(renderer, {"kept_frames_max": 1})
    kept = _passes(renderer)
    assert [f["kept frames"] for f in kept] == [1, 1, 1] and [f["kept frames"] for f in made] == [0, 0, 0]
    assert [f["digest"] for f in made] == [f["digest"] for f in kept]


def test_bins_wider_than_their_side_are_cut_to_the_same_bytes(renderer):
    """Past 16384 bins (frames over 67M pixels) the screen bins grow wider
    than the 64 pixels the passes' arrays hold, and each is cut into 64-pixel
    parts with the splats that reach them: forced here at 320 x 224 by
    native_limits' max_bins = 2 (two bins, 256 and 64 pixels wide, 224
    high), the bytes of 64-pixel bins."""
    cut = _passes(renderer, {"max_bins": 2})
    assert [f["digest"] for f in cut] == [f["digest"] for f in _passes(renderer)]


def test_the_frames_memory_budget_sizes_the_batches_to_the_same_bytes(renderer, lion):
    """A batch's splat records (a Splat and its key, 172 bytes) take at most
    half the frame's memory budget: at the default 2 GiB the lion (341k
    splats) and clouds of up to about 6M drawn splats are set up once; at
    32 MiB (16 MiB of records, about 98k splats) the lion runs in batches,
    each set up for the depth pass and again for the blend, to the same
    bytes, and the renderer keeps no more than the budget between frames."""
    whole = _render(renderer, {"rasterizer": "native"}, lion)
    small = _render(renderer, {"rasterizer": "native"}, lion, memory_budget_gb=1.0 / 32)
    assert whole.stats["brush_native_batches"] == 1
    assert small.stats["brush_native_batches"] >= 3
    assert small.stats["host_kept_mb"] <= 32.0
    assert _digest(small) == _digest(whole)
