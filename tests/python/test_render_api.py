"""The Python API of the core, used without Blender."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import pointnpr
from conftest import BUILD_DIR, plane


def test_schemas_describe_every_mark_filter_and_stage():
    kinds = {(s["id"], s["kind"]) for s in pointnpr.schemas()}
    assert {("points", "mark"), ("hatching", "mark"), ("pencil_hatching", "filter"), ("cartoon", "filter"),
            ("warp", "filter"), ("inpaint", "stage"), ("composite", "stage")} <= kinds
    assert "rasterize" not in {i for i, _ in kinds}
    assert pointnpr.schema("pencil_hatching", kind="filter")["label"] == "Pencil Hatching"
    assert pointnpr.schema("hatching", kind="mark")["label"] == "Hatching"
    with pytest.raises(KeyError):
        pointnpr.schema("cartoon", kind="mark")
    points = pointnpr.schema("points")["params"]
    world = next(p for p in points if p["name"] == "world_size")
    assert world["when"] == {"param": "size_mode", "values": ["world"]}
    assert next(p for p in points if p["name"] == "color_source")["when"] is None
    warp = pointnpr.schema("warp")
    amp = next(p for p in warp["params"] if p["name"] == "amplitude")
    assert amp["type"] == "float" and amp["unit"] == "px" and amp["min"] == 0.0 and amp["doc"]
    mode = next(p for p in pointnpr.schema("composite")["params"] if p["name"] == "mode")
    assert mode["items"] == ["layering", "depth_test", "inpaint"] and mode["default"] == "inpaint"


def test_style_validates_against_the_schema():
    style = pointnpr.Style(rasterize={"point_size": 4, "color_source": "constant", "color": (1, 0, 0)},
                           filters=[("cartoon", {"levels": 3}), "warp"], inpaint={"radius": 6})
    assert style.rasterize["point_size"] == 4.0
    assert style.rasterize["color"] == (1.0, 0.0, 0.0, 1.0)
    assert [f[0] for f in style.filters] == ["cartoon", "warp"]
    assert style.filters[0][1]["levels"] == 3
    with pytest.raises(ValueError, match="radius"):
        pointnpr.Style(inpaint={"radius": 0})
    with pytest.raises(ValueError, match="finite"):
        pointnpr.Style(rasterize={"point_size": float("nan")})
    with pytest.raises(ValueError, match="not one of"):
        pointnpr.Style(rasterize={"color_source": "rainbow"})
    with pytest.raises(ValueError, match="unknown filter"):
        pointnpr.Style(filters=["sepia_deluxe"])
    # rasterize= is the points mark under its older name.
    assert style.mark[0] == "points" and style.mark[1]["point_size"] == 4.0
    hatch = pointnpr.Style(mark=("hatching", {"cross_hatch": 0.0}))
    assert hatch.mark[0] == "hatching" and hatch.mark[1]["cross_hatch"] == 0.0 and hatch.rasterize is None
    with pytest.raises(pointnpr.ParameterError):
        pointnpr.Style(filters=[("warp", {"amplitud": 3})])


def test_a_renamed_parameter_is_still_read_under_its_former_name():
    """Every mark with two backends names the choice `rasterizer`; the
    stipples mark called it `implementation`, which scripts (and saved
    Blender files, tests/blender/test_versioning.py) still use."""
    schema = {p["name"]: p for p in pointnpr.schema("stipples", kind="mark")["params"]}
    assert "implementation" not in schema and schema["rasterizer"]["former_names"] == ["implementation"]
    for mark in ("points", "brush_splats", "feature_strokes", "stipples"):
        items = {p["name"]: p for p in pointnpr.schema(mark, kind="mark")["params"]}["rasterizer"]["items"]
        assert "native" in items and "auto" in items, mark
    style = pointnpr.Style(mark=("stipples", {"implementation": "native"}))
    assert style.mark[1]["rasterizer"] == "native" and "implementation" not in style.mark[1]
    with pytest.raises(pointnpr.ParameterError, match="given twice"):
        pointnpr.Style(mark=("stipples", {"implementation": "native", "rasterizer": "gl"}))


def test_point_cloud_from_numpy(renderer):
    pos = np.random.default_rng(1).random((1000, 3)) * 10 + np.array([6.5e5, 5.1e6, 100.0])
    cloud = pointnpr.PointCloud(pos, colors=np.zeros((1000, 3), np.uint8),
                                intensity=np.arange(1000, dtype=np.float32))
    assert cloud.num_points == 1000
    assert cloud.has("colors") and cloud.has("intensity") and not cloud.has("classification")
    lo, hi = cloud.bounds
    assert np.allclose(lo, pos.min(axis=0)) and np.allclose(hi, pos.max(axis=0))
    assert sorted(cloud.point_index.tolist()) == list(range(1000))
    with pytest.raises(RuntimeError, match="N,3"):
        pointnpr.PointCloud(np.zeros((10, 2)))
    float_colors = pointnpr.PointCloud(pos, colors=np.full((1000, 3), 0.5, np.float32))
    assert float_colors.has("colors")


def test_point_cloud_takes_float32_positions_without_a_float64_copy(renderer, camera):
    import tracemalloc

    rng = np.random.default_rng(7)
    n = 400_000
    pos32 = (rng.random((n, 3)) * [4.0, 3.0, 0.5] - [2.0, 1.5, 10.25]).astype(np.float32)
    colors = rng.integers(0, 256, (n, 3), dtype=np.uint8)

    def traced_peak(positions):
        tracemalloc.start()   # numpy's arrays are traced; the core's own memory is not
        try:
            cloud = pointnpr.PointCloud(positions, colors=colors)
            return cloud, tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    cloud32, peak32 = traced_peak(pos32)
    assert peak32 < n   # no copy: a float64 one would be 24 bytes a point
    _, peak_int = traced_peak(pos32.astype(np.int32))   # converted: the measure sees the copy
    assert peak_int >= 24 * n
    cloud64 = pointnpr.PointCloud(pos32.astype(np.float64), colors=colors)
    assert np.array_equal(cloud32.point_index, cloud64.point_index)
    assert cloud32.bounds == cloud64.bounds and cloud32.num_chunks == cloud64.num_chunks
    frames = []
    for cloud in (cloud32, cloud64):
        scene = pointnpr.Scene()
        scene.add_segment("s", pointnpr.Style(rasterize={"point_size": 2}), [cloud])
        frames.append(renderer.render(scene, camera, 320, 240).color.tobytes())
    assert frames[0] == frames[1]
    # Non-contiguous float32 input is accepted too (made contiguous, still float32).
    strided = np.asfortranarray(pos32)
    assert np.array_equal(pointnpr.PointCloud(strided).point_index, pointnpr.PointCloud(pos32).point_index)


def test_render_result_arrays(renderer, two_planes, camera):
    r = renderer.render(two_planes, camera, 320, 240, background=(0.0, 0.0, 0.0, 0.0))
    assert r.color.shape == (240, 320, 4) and r.color.dtype == np.float32
    assert r.depth.shape == (240, 320) and r.segment_index.shape == (240, 320)
    assert r.segment_index[120, 100] == 0 and r.depth[120, 100] == pytest.approx(5.0, abs=0.05)
    assert r.segment_index[120, 260] == 1 and r.depth[120, 260] == pytest.approx(10.0, abs=0.05)
    assert r.segment_index[5, 5] == -1 and r.depth[5, 5] == 1e10 and r.color[5, 5, 3] == 0.0
    assert r.stats["points_drawn"] > 0 and "total_ms" in r.stats
    # Combined is scene-linear: an sRGB 230 red comes back as its linear value.
    assert r.color[120, 260, 2] == pytest.approx(((230 / 255 + 0.055) / 1.055) ** 2.4, abs=2e-3)


def test_progress_reports_and_cancels(renderer, two_planes, camera):
    seen = []
    renderer.render(two_planes, camera, 320, 240, progress=lambda f, what: seen.append((f, what)))
    assert seen[0] == (0.0, "near") and seen[-1][0] == 1.0
    with pytest.raises(pointnpr.RenderCancelled):
        renderer.render(two_planes, camera, 320, 240, progress=lambda f, what: False)


def test_bad_render_arguments_raise(renderer, two_planes, camera):
    with pytest.raises(ValueError):
        renderer.render(two_planes, camera, 0, 240)
    with pytest.raises(ValueError, match="rasterizer"):
        pointnpr.Style(mark=("points", {"rasterizer": "raytrace"}))
    with pytest.raises(ValueError, match="unknown mark"):
        pointnpr.Style(mark="cartoon")
    with pytest.raises(ValueError, match="not both"):
        pointnpr.Style(mark="points", rasterize={"point_size": 3})
    with pytest.raises(ValueError, match="mode"):
        renderer.render(two_planes, camera, 320, 240, composite={"mode": "magic"})
    with pytest.raises(ValueError):
        pointnpr.Camera.perspective(np.eye(3), width=320, height=240)
    with pytest.raises(TypeError):  # the render size is required: no silent 16:9 default
        pointnpr.Camera.perspective(np.eye(4))


def test_viewport_camera_from_matrices(renderer, two_planes):
    # A GL projection equivalent to the 50 mm camera renders the same image.
    n, f = 0.1, 1000.0
    right = n * 18.0 / 50.0
    top = right * 240 / 320
    proj = np.array([[n / right, 0, 0, 0], [0, n / top, 0, 0],
                     [0, 0, -(f + n) / (f - n), -2 * f * n / (f - n)], [0, 0, -1, 0]])
    a = renderer.render(two_planes, pointnpr.Camera.from_matrices(np.eye(4), proj), 320, 240)
    b = renderer.render(two_planes, pointnpr.Camera.perspective(np.eye(4), width=320, height=240), 320, 240)
    assert np.mean(a.segment_index != b.segment_index) < 0.001


def test_image_round_trip_through_openimageio(tmp_path):
    img = np.zeros((4, 6, 4), np.float32)
    img[0, :, 0] = 1.0  # bottom row red
    img[..., 3] = 1.0
    path = str(tmp_path / "x.png")
    pointnpr.save_image(path, img)
    back = pointnpr.load_image(path)
    assert back.shape == (4, 6, 4)
    assert back[0, 0, 0] == pytest.approx(1.0) and back[3, 0, 0] == pytest.approx(0.0)


RENDER_SCRIPT = textwrap.dedent("""
    import sys, hashlib, numpy as np
    sys.path.insert(0, sys.argv[1])
    import pointnpr
    from conftest import plane
    scene = pointnpr.Scene()
    scene.add_segment("a", pointnpr.Style(rasterize={"point_size": 3}, filters=["cartoon", "warp"]),
                      [plane(-1.2, 0.4, -0.6, 0.6, -5, 0.03, (230, 60, 40))])
    scene.add_segment("b", pointnpr.Style(rasterize={"point_size": 3}), [plane(-2, 3, -1.5, 1.5, -10, 0.05, (40, 60, 230))])
    cam = pointnpr.Camera.perspective(np.eye(4), width=320, height=240)
    r = pointnpr.Renderer().render(scene, cam, 320, 240, time=1.25)
    print(hashlib.sha256(r.color.tobytes() + r.depth.tobytes() + r.segment_index.tobytes()).hexdigest())
""")


def test_same_scene_renders_identical_bytes_in_separate_processes():
    env = dict(os.environ, PYTHONPATH=os.path.dirname(__file__))
    digests = [subprocess.run([sys.executable, "-c", RENDER_SCRIPT, os.path.abspath(BUILD_DIR)], env=env,
                              capture_output=True, text=True, check=True).stdout.strip() for _ in range(2)]
    assert len(digests[0]) == 64 and digests[0] == digests[1]


def test_missing_shaders_raise_a_gl_error_naming_the_path(tmp_path):
    script = textwrap.dedent(f"""
        import sys, numpy as np
        sys.path.insert(0, {os.path.abspath(BUILD_DIR)!r})
        import pointnpr
        pointnpr._pointnpr.set_shader_dir({str(tmp_path)!r})
        s = pointnpr.Scene()
        s.add_segment("a", pointnpr.Style(), [pointnpr.PointCloud(np.zeros((1, 3)) - [0, 0, 5])])
        try:
            pointnpr.Renderer().render(s, pointnpr.Camera.perspective(np.eye(4), width=64, height=64), 64, 64)
        except pointnpr.GLError as e:
            print("GLError:", e)
    """)
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True).stdout
    assert "GLError: shader file not found" in out and str(tmp_path) in out


def test_concurrent_renders_with_one_renderer_match_sequential_ones(renderer, camera):
    # Blender's render thread (F12) and its main thread (viewport) share one renderer.
    import threading

    two_planes = pointnpr.Scene()
    two_planes.add_segment("near", pointnpr.Style(rasterize={"point_size": 3}, filters=["warp"]),
                           [plane(-1.2, 0.4, -0.6, 0.6, -5, 0.03, (230, 60, 40))])
    two_planes.add_segment("far", pointnpr.Style(rasterize={"point_size": 3}, filters=["cartoon"]),
                           [plane(-2, 3, -1.5, 1.5, -10, 0.05, (40, 60, 230))])
    expected = [renderer.render(two_planes, camera, 320, 240, time=t).color.copy() for t in (0.0, 0.5)]
    assert not np.array_equal(expected[0], expected[1])  # the warp moves with time
    results = {}

    def work(i, t):
        results[i] = renderer.render(two_planes, camera, 320, 240, time=t).color.copy()

    threads = [threading.Thread(target=work, args=(i, t)) for i, t in enumerate((0.0, 0.5, 0.0, 0.5))]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    for i, t in enumerate((0.0, 0.5, 0.0, 0.5)):
        assert np.array_equal(results[i], expected[0 if t == 0.0 else 1])


def test_without_any_egl_driver_the_error_says_what_to_install():
    # libglvnd finds no EGL vendor: as on a machine without Mesa or a GPU driver.
    script = textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {os.path.abspath(BUILD_DIR)!r})
        import pointnpr
        try:
            pointnpr.gl_info()
        except pointnpr.GLError as e:
            print("GLError:", e)
    """)
    env = dict(os.environ, __EGL_VENDOR_LIBRARY_FILENAMES="/nonexistent/egl_vendor.json",
               __EGL_VENDOR_LIBRARY_DIRS="/nonexistent")
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True,
                         check=True, timeout=60).stdout
    assert "GLError: no EGL display could be opened" in out, out
    assert "apt install libegl1 libegl-mesa0" in out


def test_image_parameters_take_paths_and_reach_the_filter(renderer, camera, tmp_path):
    """A path parameter (color_grade.lut) accepts str and os.PathLike, is
    validated when the style is built, and its image changes the render."""
    n = 2  # a 4x2 strip LUT that swaps red and blue: entry (r, g, b) -> (b, g, r)
    lut = np.zeros((n, n * n, 3), np.float32)  # rows top first here, flipped below
    for g in range(n):
        for b in range(n):
            for r in range(n):
                lut[g, b * n + r] = (b, g, r)
    path = tmp_path / "swap.png"
    pointnpr.save_image(str(path), np.ascontiguousarray(lut[::-1]), srgb=False)  # bottom row first

    def render(lut_path):
        scene = pointnpr.Scene()
        style = pointnpr.Style(rasterize={"point_size": 3}, filters=[("color_grade", {"lut": lut_path})])
        scene.add_segment("red", style, [plane(-1, 1, -1, 1, -5, 0.02, (230, 60, 40))])
        return np.asarray(renderer.render(scene, camera, 320, 240, background=(0, 0, 0, 0)).color)

    plain, swapped = render(""), render(path)
    centre = (120, 160)
    assert plain[centre][0] > plain[centre][2] + 0.3          # red
    assert swapped[centre][2] > swapped[centre][0] + 0.3      # blue after the swap
    assert abs(swapped[centre][0] - plain[centre][2]) < 0.02
    assert pointnpr.Style(filters=[("color_grade", {"lut": path})]).filters[0][1]["lut"] == str(path)
    with pytest.raises(ValueError, match="no such file"):
        pointnpr.Style(filters=[("color_grade", {"lut": tmp_path / "missing.png"})])
    with pytest.raises(ValueError, match="file path"):
        pointnpr.Style(filters=[("color_grade", {"lut": 1.0})])
