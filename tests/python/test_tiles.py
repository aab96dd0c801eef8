"""Frames drawn in tiles (issue 17): the same bytes as the frame drawn whole,
progress per tile, cancelling between tiles, the memory budget."""
import numpy as np
import pytest

import pointnpr
from pointnpr import presets

FILTERS = [s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"]


def wavy_cloud(n, seed, z0, spread=2.0):
    """Random points on a wavy surface with random colours: every pixel differs."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(-spread, spread, n)
    y = rng.uniform(-0.75 * spread, 0.75 * spread, n)
    z = z0 + 0.4 * np.sin(3 * x) * np.cos(2 * y) + rng.normal(0, 0.01, n)
    return pointnpr.PointCloud(np.column_stack([x, y, z]), colors=rng.integers(0, 255, (n, 3)).astype(np.uint8))


def patches(cloud_args, columns, rows):
    """The wavy cloud cut into columns x rows clouds: chunks with small
    screen rectangles, so each tile draws only the patches near it and the
    halo, not the chunks' size, decides what reaches a tile."""
    n, seed, z0, spread = cloud_args
    rng = np.random.default_rng(seed)
    x = rng.uniform(-spread, spread, n)
    y = rng.uniform(-0.75 * spread, 0.75 * spread, n)
    z = z0 + 0.4 * np.sin(3 * x) * np.cos(2 * y) + rng.normal(0, 0.01, n)
    colors = rng.integers(0, 255, (n, 3)).astype(np.uint8)
    column = np.minimum(((x + spread) / (2 * spread) * columns).astype(int), columns - 1)
    row = np.minimum(((y + 0.75 * spread) / (1.5 * spread) * rows).astype(int), rows - 1)
    out = []
    for i in range(columns):
        for j in range(rows):
            m = (column == i) & (row == j)
            out.append(pointnpr.PointCloud(np.column_stack([x[m], y[m], z[m]]), colors=colors[m]))
    return out


@pytest.fixture(scope="module")
def clouds():
    return wavy_cloud(30000, 3, -6.0), wavy_cloud(12000, 4, -5.0, spread=1.0)


def two_segments(clouds, filters, rasterizer="compute"):
    scene = pointnpr.Scene()
    scene.add_segment("wall", pointnpr.Style(rasterize={"point_size": 3, "rasterizer": rasterizer}, filters=filters,
                                             inpaint={"radius": 4}), [clouds[0]])
    scene.add_segment("crown", pointnpr.Style(rasterize={"point_size": 2, "rasterizer": rasterizer},
                                              filters=[("cartoon", {})]), [clouds[1]])
    return scene


def assert_same_bytes(whole, tiled):
    assert tiled.width == whole.width and tiled.height == whole.height
    for name in ("color", "depth", "segment_index"):
        a, b = np.asarray(getattr(whole, name)), np.asarray(getattr(tiled, name))
        differing = int(np.count_nonzero(a != b))
        assert a.tobytes() == b.tobytes(), f"{name}: {differing} values differ"


def render_both(renderer, scene, width, height, tile_size):
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=width, height=height)
    whole = renderer.render(scene, cam, width, height)
    tiled = renderer.render(scene, cam, width, height, tile_size=tile_size)
    assert whole.stats["tiles"] == 1
    # Real tiles: more than one, and regions smaller than the frame.
    assert tiled.stats["tiles"] > 1
    assert tiled.stats["tile_region_width"] < width and tiled.stats["tile_region_height"] < height
    covered = np.asarray(whole.color).reshape(height, width, 4)[..., 3] > 0
    assert covered.mean() > 0.3  # a picture, not an empty frame
    return whole, tiled


@pytest.mark.parametrize("filter_id", FILTERS)
def test_each_filter_tiled_is_the_bytes_of_the_whole_frame(renderer, clouds, filter_id):
    whole, tiled = render_both(renderer, two_segments(clouds, [filter_id]), 341, 281, 64)
    assert_same_bytes(whole, tiled)


def test_flow_guided_lines_tiled_are_the_bytes_of_the_whole_frame(renderer, clouds):
    """xdog's FDoG reads along flow curves and across edges: its own passes
    and footprint (flow_length off by default, so the case above misses them)."""
    whole, tiled = render_both(renderer, two_segments(clouds, [("xdog", {"flow_length": 3.0})]), 301, 233, 64)
    assert_same_bytes(whole, tiled)


def test_every_filter_in_one_chain_tiled_is_the_bytes_of_the_whole_frame(renderer, clouds):
    # The chain's halo is the sum of every filter's footprint (140 px with
    # flow_oil's flow field): the frame stays larger than a tile's region.
    whole, tiled = render_both(renderer, two_segments(clouds, FILTERS), 520, 420, 64)
    assert tiled.stats["tile_halo"] > 50  # the chain's footprints, not just the splats'
    assert_same_bytes(whole, tiled)


@pytest.mark.parametrize("rasterizer", ["compute", "gl_points", "native"])
def test_points_tiled_are_the_bytes_of_the_whole_frame_for_both_rasterizers(renderer, clouds, rasterizer):
    whole, tiled = render_both(renderer, two_segments(clouds, [], rasterizer), 257, 199, 64)
    assert_same_bytes(whole, tiled)


def test_the_memory_budget_chooses_the_tiles(renderer, clouds):
    scene = two_segments(clouds, [("cartoon", {})])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=400, height=300)
    whole = renderer.render(scene, cam, 400, 300)
    budget_gb = 0.01  # 10.7 MB: regions of about 204 x 204 pixels at 256 B each
    tiled = renderer.render(scene, cam, 400, 300, memory_budget_gb=budget_gb)
    assert tiled.stats["tiles"] > 1
    region = tiled.stats["tile_region_width"] * tiled.stats["tile_region_height"]
    assert region * 256 <= budget_gb * 2**30
    assert_same_bytes(whole, tiled)
    with pytest.raises(ValueError, match="memory_budget_gb"):
        renderer.render(scene, cam, 400, 300, memory_budget_gb=-1.0)
    with pytest.raises(ValueError, match="tile_size"):
        renderer.render(scene, cam, 400, 300, tile_size=-5)


def test_progress_advances_per_tile(renderer, clouds):
    scene = two_segments(clouds, [])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=300, height=200)
    calls = []
    result = renderer.render(scene, cam, 300, 200, tile_size=64, progress=lambda f, what: calls.append((f, what)))
    tiles = int(result.stats["tiles"])
    assert tiles == 5 * 4
    fractions = [f for f, _ in calls]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0
    for t in range(1, tiles + 1):
        assert any(what.startswith(f"tile {t}/{tiles}: ") for _, what in calls), t
    # Within a tile, one call per segment, in order.
    assert [w for _, w in calls[:2]] == [f"tile 1/{tiles}: wall", f"tile 1/{tiles}: crown"]


def test_cancelling_stops_between_tiles_and_the_renderer_renders_on(renderer, clouds):
    scene = two_segments(clouds, [])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=300, height=200)
    seen = []

    def cancel_at_third_tile(fraction, what):
        seen.append(what)
        return not what.startswith("tile 3/")

    with pytest.raises(pointnpr.RenderCancelled):
        renderer.render(scene, cam, 300, 200, tile_size=64, progress=cancel_at_third_tile)
    assert seen[-1].startswith("tile 3/") and not any(w.startswith("tile 4/") for w in seen)
    whole = renderer.render(scene, cam, 300, 200)
    again = renderer.render(scene, cam, 300, 200, tile_size=64)
    assert_same_bytes(whole, again)


def test_frames_that_capture_marks_are_drawn_whole(renderer, clouds):
    # Captured marks are listed once per frame: such frames are not cut.
    scene = pointnpr.Scene()
    scene.add_segment("hatched", pointnpr.Style(mark=("hatching", {})), [clouds[0]])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=200, height=150)
    result = renderer.render(scene, cam, 200, 150, memory_budget_gb=0.001, capture_marks=True)
    assert result.stats["tiles"] == 1 and len(result.marks["point_id"]) > 100
    assert renderer.render(scene, cam, 200, 150, memory_budget_gb=0.001).stats["tiles"] > 1


@pytest.mark.parametrize("params", [{"units": "world"},
                                    {"units": "world", "world_length": 0.4, "world_width": 0.02,
                                     "placement": "irregular"}])
def test_hatching_in_scene_units_tiled_is_the_bytes_of_the_whole_frame(renderer, clouds, wall_patches, params):
    # Strokes sized in the scene: each chunk's bounds grown by the stroke's
    # reach in scene units bound where its strokes fall on screen, so every
    # tile draws each stroke reaching its region.
    scene = pointnpr.Scene()
    scene.add_segment("hatched", pointnpr.Style(mark=("hatching", params), filters=[("cartoon", {})]), wall_patches)
    scene.add_segment("crown", pointnpr.Style(rasterize={"point_size": 2}), [clouds[1]])
    whole, tiled = render_both(renderer, scene, 301, 233, 64)
    assert whole.stats["strokes_drawn"] > 1000
    assert_same_bytes(whole, tiled)


# The stroke marks (hatching, feature_strokes): with their defaults and with
# every preset of theirs, a filter chain after the mark, over a second
# segment of points they composite with.
STROKE_STYLES = [("hatching", None), ("feature_strokes", None)] + [
    (spec["mark"][0], name) for name, spec in presets.PRESETS.items()
    if spec["mark"][0] in ("hatching", "feature_strokes")]


@pytest.fixture(scope="module")
def wall_patches():
    return patches((30000, 3, -6.0, 2.0), 6, 4)


def stroke_scene(clouds, mark, preset, params=None):
    if preset is None:
        style = pointnpr.Style(mark=(mark, params or {}), filters=[("edge_enhance", {}), ("color_grade", {"saturation": 1.3})])
    else:
        spec = presets.PRESETS[preset]
        style = pointnpr.Style(mark=spec["mark"], filters=list(spec["filters"]) + [("xdog", {})])
    scene = pointnpr.Scene()
    scene.add_segment("strokes", style, clouds[0])
    scene.add_segment("crown", pointnpr.Style(rasterize={"point_size": 2}, filters=[("cartoon", {})]), [clouds[1]])
    return scene


@pytest.mark.parametrize("mark,preset", STROKE_STYLES, ids=[p or m for m, p in STROKE_STYLES])
def test_stroke_marks_tiled_are_the_bytes_of_the_whole_frame(renderer, clouds, wall_patches, mark, preset):
    scene = stroke_scene((wall_patches, clouds[1]), mark, preset)
    whole, tiled = render_both(renderer, scene, 301, 233, 64)
    assert whole.stats["strokes_drawn"] > 1000
    assert_same_bytes(whole, tiled)


# feature_strokes on both of its paths (auto is native on software GL).
@pytest.mark.parametrize("mark,params", [("hatching", {}), ("feature_strokes", {"rasterizer": "native"}),
                                         ("feature_strokes", {"rasterizer": "gl"})])
def test_stroke_marks_in_odd_tiles_over_the_budget_are_the_bytes_of_the_whole_frame_and_say_nothing(
        renderer, clouds, wall_patches, mark, params):
    scene = stroke_scene((wall_patches, clouds[1]), mark, None, params)
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=297, height=229)
    whole = renderer.render(scene, cam, 297, 229)
    odd = renderer.render(scene, cam, 297, 229, tile_size=97)
    assert odd.stats["tiles"] == 4 * 3
    assert_same_bytes(whole, odd)
    # Chosen by the memory budget: tiles, and no word of drawing the frame whole.
    budget = renderer.render(scene, cam, 297, 229, memory_budget_gb=0.005)
    assert budget.stats["tiles"] > 1
    assert not any("does not draw in tiles" in w for w in budget.warnings), budget.warnings
    assert_same_bytes(whole, budget)


@pytest.mark.parametrize("mark,params", [("hatching", {}), ("hatching", {"depth_pass": False, "placement": "irregular"}),
                                         ("feature_strokes", {"directional": "line_segment", "rasterizer": "native"}),
                                         ("feature_strokes", {"directional": "line_segment", "rasterizer": "gl"})])
def test_stroke_marks_under_an_orthographic_camera_tiled_are_the_bytes_of_the_whole_frame(
        renderer, clouds, wall_patches, mark, params):
    scene = pointnpr.Scene()
    scene.add_segment("strokes", pointnpr.Style(mark=(mark, params), filters=[("cartoon", {})]), wall_patches)
    scene.add_segment("crown", pointnpr.Style(rasterize={"point_size": 2}), [clouds[1]])
    cam = pointnpr.Camera.orthographic(np.eye(4), 5.0, width=301, height=233)
    whole = renderer.render(scene, cam, 301, 233)
    tiled = renderer.render(scene, cam, 301, 233, tile_size=64)
    assert tiled.stats["tiles"] == 5 * 4 and whole.stats["strokes_drawn"] > 1000
    assert (np.asarray(whole.color)[..., 3] > 0).mean() > 0.3
    assert_same_bytes(whole, tiled)


@pytest.fixture(scope="module")
def slope_patches():
    """A plane at 45 degrees to the view, from 1.5 m to 6.5 m, in 6 x 5 patches."""
    rng = np.random.default_rng(7)
    n = 20000
    x, t = rng.uniform(-3, 3, n), rng.uniform(-2.5, 2.5, n)
    pos = np.column_stack([x, 0.707 * t, -4.0 - 0.707 * t])
    column, row = np.minimum(((x + 3) // 1).astype(int), 5), np.minimum(((t + 2.5) // 1).astype(int), 4)
    return [pointnpr.PointCloud(pos[(column == i) & (row == j)]) for i in range(6) for j in range(5)]


@pytest.mark.parametrize("size", [{"line_length": 60.0},                       # pixels: cut at the halo
                                  {"units": "world", "world_length": 0.5}],   # scene: hundreds of pixels near
                         ids=["pixels", "scene_units"])
def test_long_strokes_turned_toward_a_wide_angle_camera_tiled_are_the_bytes_of_the_whole_frame(
        renderer, slope_patches, size):
    # Strokes along the slope, not cut to the surface: their near halves
    # project longer than their length, across many tiles, from patches
    # each tile may not draw.
    scene = pointnpr.Scene()
    scene.add_segment("slope", pointnpr.Style(mark=("hatching", dict(size, **{
        "length_jitter": 1.0, "direction_azimuth": 90.0, "direction_elevation": -45.0,
        "stroke_coverage": 0.0, "density": 0.3, "light_elevation": -90.0, "clip_to_surface": False}))),
        slope_patches)
    cam = pointnpr.Camera.perspective(np.eye(4), lens=12.0, clip_start=0.05, width=257, height=201)
    whole = renderer.render(scene, cam, 257, 201)
    tiled = renderer.render(scene, cam, 257, 201, tile_size=64)
    assert tiled.stats["tiles"] > 1 and whole.stats["strokes_drawn"] > (100 if "units" in size else 3000)
    assert_same_bytes(whole, tiled)


def test_gl_points_just_beyond_the_frame_in_tiles_of_a_power_of_two_are_the_bytes_of_the_whole_frame(renderer):
    # Splats centred past the frame's right and top edges still cover its
    # last pixels; a region of 256 pixels there once clipped them away.
    cloud = wavy_cloud(40000, 8, -6.0, spread=3.5)
    scene = pointnpr.Scene()
    scene.add_segment("wide", pointnpr.Style(rasterize={"point_size": 6, "rasterizer": "gl_points"}), [cloud])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=500, height=400)
    whole = renderer.render(scene, cam, 500, 400)
    halo = renderer.render(scene, cam, 500, 400, tile_size=100).stats["tile_halo"]
    tiled = renderer.render(scene, cam, 500, 400, tile_size=int(256 - 2 * halo))
    assert tiled.stats["tile_region_width"] == 256 and tiled.stats["tiles"] > 1
    assert_same_bytes(whole, tiled)


def test_one_size_limit_and_frames_beyond_the_gl_limit(renderer, clouds):
    scene = two_segments(clouds, [])
    with pytest.raises(ValueError, match=r"between 1 and 32768 pixels per side, got 40000x10"):
        renderer.render(scene, pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=40000, height=10), 40000, 10)
    # Wider than any GL image (16384 on llvmpipe): drawn in tiles.
    width = 17000
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=width, height=24)
    result = renderer.render(scene, cam, width, 24)
    assert result.stats["tiles"] > 1 and result.stats["tile_region_width"] <= 16384
    assert np.asarray(result.color).reshape(24, width, 4)[..., 3].max() > 0


@pytest.mark.parametrize("mode,method", [("inpaint", "surface"), ("inpaint", "strict"), ("inpaint", "paper"),
                                         ("depth_test", "surface"), ("layering", "surface")])
def test_every_compositing_and_inpainting_method_tiled_is_the_bytes_of_the_whole_frame(renderer, clouds, mode,
                                                                                        method):
    scene = pointnpr.Scene()
    scene.add_segment("wall", pointnpr.Style(rasterize={"point_size": 2}, filters=[("cartoon", {})],
                                             inpaint={"radius": 6, "method": method}), [clouds[0]])
    scene.add_segment("crown", pointnpr.Style(rasterize={"point_size": 2}, filters=[("xdog", {})],
                                              inpaint={"radius": 3, "method": method}), [clouds[1]])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=280, height=210)
    whole = renderer.render(scene, cam, 280, 210, composite={"mode": mode})
    tiled = renderer.render(scene, cam, 280, 210, composite={"mode": mode}, tile_size=64)
    assert tiled.stats["tiles"] == 5 * 4 and tiled.stats["tile_region_width"] < 280
    assert_same_bytes(whole, tiled)


@pytest.mark.parametrize("rasterizer", ["compute", "gl_points", "native"])
def test_many_splats_over_a_large_frame_tiled_are_the_bytes_of_the_whole_frame(renderer, rasterizer):
    # Subpixel rounding that follows the tile's origin (the GL's viewport
    # transform, gl_PointCoord) flips a few dozen edge pixels at this scale.
    cloud = wavy_cloud(200000, 5, -6.0)
    scene = pointnpr.Scene()
    scene.add_segment("dense", pointnpr.Style(rasterize={"point_size": 3.3, "rasterizer": rasterizer}), [cloud])
    whole, tiled = render_both(renderer, scene, 1500, 1100, 400)
    assert_same_bytes(whole, tiled)
