"""The shipped presets validate against the C++ schemas and render; every
preset shows the tones of a scan that has intensity only."""
import os

import numpy as np
import pytest

from conftest import plane

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
POINTS_PRESETS = ["Toon", "Ink outlines", "Flow ink", "Watercolor", "Oil paint", "Flow oil paint", "Posterize",
                  "Urban map"]
HATCHING_PRESETS = ["Pencil", "Coloured crayons", "Wax crayons", "Blueprint", "Chalk", "Pointillism"]
FEATURE_PRESETS = ["Feature stippling", "Feature strokes + stipples", "Feature strokes + hatching"]
STIPPLES_PRESETS = ["Stipple diffuse", "Stipple specular", "Ink stippling"]
BRUSH_PRESETS = ["Impressionist", "Pointillist", "Painterly"]


def test_the_presets_are_all_there():
    from pointnpr import presets

    assert set(presets.PRESETS) == (set(POINTS_PRESETS) | set(HATCHING_PRESETS) | set(FEATURE_PRESETS) |
                                    set(STIPPLES_PRESETS) | set(BRUSH_PRESETS))
    for name in POINTS_PRESETS:
        assert presets.PRESETS[name]["mark"][0] == "points", name
    for name in HATCHING_PRESETS:
        assert presets.PRESETS[name]["mark"][0] == "hatching", name
    for name in FEATURE_PRESETS:
        assert presets.PRESETS[name]["mark"][0] == "feature_strokes", name
    for name in STIPPLES_PRESETS:
        assert presets.PRESETS[name]["mark"][0] == "stipples", name
    for name in BRUSH_PRESETS:
        assert presets.PRESETS[name]["mark"][0] == "brush_splats", name


def _plane_render(renderer, style):
    import pointnpr

    scene = pointnpr.Scene()
    scene.add_segment("plane", style, [(plane(-1, 1, -1, 1, 0, 0.04, (180, 120, 60)), np.eye(4))])
    cam = pointnpr.Camera.perspective(np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 6], [0, 0, 0, 1]], float),
                                      width=96, height=64)
    return renderer.render(scene, cam, 96, 64)


@pytest.mark.parametrize("name", POINTS_PRESETS + HATCHING_PRESETS + FEATURE_PRESETS + STIPPLES_PRESETS +
                         BRUSH_PRESETS)
def test_preset_validates_and_renders(renderer, name):
    import pointnpr
    from pointnpr import presets

    preset = presets.PRESETS[name]
    mark_id, mark_params = preset["mark"]
    mark_schema = pointnpr.schema(mark_id, kind="mark")
    assert set(mark_params) <= {p["name"] for p in mark_schema["params"]}, name
    filters = {s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"}
    for step in preset["filters"]:
        step_id = step[0] if isinstance(step, tuple) else step
        assert step_id in filters
    style = presets.style(name)
    assert style.mark[0] == mark_id
    for key, value in mark_params.items():  # validated, kept (not reset to a default)
        got = style.mark[1][key]
        assert (tuple(got) == tuple(value)) if isinstance(value, tuple) else got == pytest.approx(value), (name, key)
    assert [f[0] for f in style.filters] == [s[0] for s in preset["filters"]]
    result = _plane_render(renderer, style)
    assert np.isfinite(result.color).all()
    assert (result.color[..., 3] > 0).sum() > 500
    if mark_id in ("hatching", "feature_strokes"):
        assert result.stats["strokes_drawn"] > 0, name
    if mark_id == "stipples":
        assert 0 < result.stats["stipples_drawn"] < result.stats["stipples_visible"], name  # dots, thinned


def test_unknown_preset_names_the_known_ones():
    from pointnpr import presets

    with pytest.raises(KeyError, match="Watercolor"):
        presets.style("Pastel")


# --- Intensity-only scans ---------------------------------------------------
#
# A LiDAR tile often has intensity and nothing else. The colour source
# defaults to "auto" (RGB, else intensity, else the class palette), so a
# preset must show the scan's tones, not a flat grey. Measured on the LiDAR
# HD tile's positions and intensity, 320x224, transparent background, over
# the covered pixels (alpha > 0.5), luminance of the display-sRGB colour:
#
#  - MIN_STD: the luminance varies with a standard deviation above 0.06
#    (15/255). A flat grey (3 px splats of the constant colour, no filter)
#    measures 0; the presets measure 0.16-0.37 once the intensity is read
#    at a usable scale, so 0.06 leaves room for drivers and still fails a
#    flat or near-black image.
#  - MIN_CORRELATION: presets that colour by the points must show the
#    intensity, not only the light: their luminance, averaged over 8x8 px
#    blocks, correlates with that of plain splats of the intensity (the
#    intensity image) by more than 0.5 (measured 0.72-0.99; strokes in the
#    constant colour, which ignore the intensity, measure -0.4-0.4).
#  - Presets whose strokes have a constant or X-Toon colour ignore the
#    intensity by design; their tone comes from the light (lighting by
#    omission), and only MIN_STD applies.
#  - "Urban map" colours by classification on purpose: on the tile without
#    classes it warns that the constant colour is used and still renders
#    the whole tile, shaded by eye-dome lighting (MIN_STD holds, 0.18); no
#    correlation with the intensity is asked of it.
#
# The core maps intensity's 99th percentile to white (cpp/render/gpu_cloud.cpp):
# this tile's peak is 21014 where its 99th percentile is 4172, and a peak
# scale drew it nearly black (std 0.04-0.05, below MIN_STD).
MIN_STD = 0.06
MIN_CORRELATION = 0.5
W, H = 320, 224


def _colours_by_point(preset):
    mark_id, params = preset["mark"]
    if mark_id == "points":
        return params.get("color_source", "auto") in ("auto", "intensity")
    return params.get("coloring") == "point" and params.get("color_source", "auto") in ("auto", "intensity")


@pytest.fixture(scope="module")
def intensity_tile():
    import pointnpr

    tile = pointnpr.read(os.path.join(ROOT, "data", "lidarhd_myria3d_870000_6618000_subset.las"))
    pos = np.asarray(tile.positions)
    pos = pos - (pos.min(0) + pos.max(0)) / 2
    intensity = np.asarray(tile.attributes["intensity"], np.float32)
    camera = pointnpr.Camera.perspective(pointnpr.look_at((0.0, -70.0, 60.0), (0.0, 0.0, 0.0)), lens=35.0,
                                         clip_start=0.5, clip_end=1000.0, width=W, height=H)
    return pointnpr.PointCloud(pos, intensity=intensity), camera


def _luminance(renderer, style, cloud, camera):
    import pointnpr

    scene = pointnpr.Scene()
    scene.add_segment("tile", style, [(cloud, np.eye(4))])
    result = renderer.render(scene, camera, W, H, background=(0, 0, 0, 0))
    color = np.asarray(result.color)
    assert np.isfinite(color).all()
    linear = np.clip(color[..., :3], 0.0, 1.0)
    display = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)
    return display @ np.array([0.2126, 0.7152, 0.0722]), color[..., 3] > 0.5, list(result.warnings)


def _block_correlation(a, a_covered, b, b_covered, block=8):
    def blocks(img, covered):
        shape = (H // block, block, W // block, block)
        return np.where(covered, img, 0.0).reshape(shape).sum((1, 3)), covered.reshape(shape).sum((1, 3))

    sa, na = blocks(a, a_covered)
    sb, nb = blocks(b, b_covered)
    full = (na == block * block) & (nb == block * block)
    return np.corrcoef(sa[full], sb[full])[0, 1]


def _check_intensity_tones(renderer, name, cloud, camera):
    import pointnpr
    from pointnpr import presets

    lum, covered, warnings = _luminance(renderer, presets.style(name), cloud, camera)
    assert covered.mean() > 0.4, f"{name}: the tile covers {covered.mean():.0%} of the image"
    if name == "Urban map":
        assert any("classification" in w for w in warnings), warnings
    else:
        assert not warnings, warnings
    std = lum[covered].std()
    assert std > MIN_STD, f"{name}: flat image (luminance std {std:.4f}, mean {lum[covered].mean():.3f})"
    if _colours_by_point(presets.PRESETS[name]):
        ref, ref_covered, _ = _luminance(renderer, pointnpr.Style(mark=("points", {"point_size": 3.0})), cloud, camera)
        corr = _block_correlation(lum, covered, ref, ref_covered)
        assert corr > MIN_CORRELATION, f"{name}: the intensity does not show (correlation {corr:.3f})"


@pytest.mark.parametrize("name", POINTS_PRESETS + HATCHING_PRESETS + FEATURE_PRESETS + STIPPLES_PRESETS +
                         BRUSH_PRESETS)
def test_preset_shows_the_tones_of_an_intensity_only_scan(renderer, intensity_tile, name):
    # The tile's intensity has glints far above the rest (peak 21014, 99th
    # percentile 4172): the core maps its 99th percentile to white.
    cloud, camera = intensity_tile
    _check_intensity_tones(renderer, name, cloud, camera)
