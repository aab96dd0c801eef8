"""The feature strokes' tone (issue 39): seed 001 keeps its dithering points
uniform in 3D, so their ink follows how densely the scan lies on screen (a
dense or near surface dark, a sparse or far one light) more than the light.
With `tone`, a point's odds are its share of the surface on screen over a
dithering mark's area, times the tone and its darkness: the same ink at any
density, distance and output size, darker where the surface turns from the
light. Both paths."""
import numpy as np
import pytest

import pointnpr
from test_marks_feature_strokes import camera, wall


@pytest.fixture(params=["gl", "native"])
def path(request):
    return request.param


def wall_ink(renderer, spacing, width, height, elevation, path, tone):
    """Mean ink (1 - luminance over white paper) in the middle of a flat,
    colourless wall facing the camera, lit from `elevation` degrees off its
    normal (the camera light)."""
    pos, _ = wall(3.0, 2.4, spacing, -5.0)
    params = {"tone": tone, "dither": 0.3, "shading": "diffuse", "shading_strength": 1.0, "color_source": "constant",
              "dithering": "point_sprite", "sprite_size": 2.0, "light_space": "camera", "light_azimuth": 0.0,
              "light_elevation": elevation, "rasterizer": path}
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("feature_strokes", params)), [(pointnpr.PointCloud(pos), np.eye(4))])
    img = np.asarray(renderer.render(scene, camera(width=width, height=height), width, height).color)
    return float(1.0 - img[height // 4:3 * height // 4, width // 4:3 * width // 4, :3].mean())


def test_the_tone_keeps_the_dithering_s_ink_at_any_density_and_output_size(renderer, path):
    # Walls with 0.02 and 0.04 between points at 320x240 and 480x360, lit
    # 70 degrees off their normal (dark) and 20 degrees off it (light).
    # The paper's dithering: ink 0.24, 0.17, 0.14, 0.12. With the tone (1):
    # 0.46 in all four turned away, 0.14 in all four lit.
    cases = [(s, w, h) for s in (0.02, 0.04) for w, h in ((320, 240), (480, 360))]
    paper = [wall_ink(renderer, s, w, h, 70.0, path, 0.0) for s, w, h in cases]
    dark = [wall_ink(renderer, s, w, h, 70.0, path, 1.0) for s, w, h in cases]
    light = [wall_ink(renderer, s, w, h, 20.0, path, 1.0) for s, w, h in cases]
    assert max(paper) > 1.6 * min(paper), paper
    assert max(dark) - min(dark) < 0.03 and max(light) - min(light) < 0.03, (dark, light)
    assert min(dark) > 1.5 * max(light) and min(light) > 0.01, (dark, light)


def test_an_unlit_tone_draws_the_same_strokes_on_both_paths(renderer):
    # Shading none binds no normals: the tone's foreshortening takes none
    # (native read a null array, GL the positions in the normals' binding).
    pos, _ = wall(3.0, 2.4, 0.03, -5.0)
    ids = {}
    for path in ("gl", "native"):
        scene = pointnpr.Scene()
        params = {"tone": 1.0, "shading": "none", "rasterizer": path}
        scene.add_segment("s", pointnpr.Style(mark=("feature_strokes", params)), [(pointnpr.PointCloud(pos), np.eye(4))])
        r = renderer.render(scene, camera(width=320, height=240), 320, 240, capture_marks=True)
        ids[path] = np.sort(np.asarray(r.marks["point_id"]))
    assert len(ids["gl"]) > 100
    assert np.array_equal(ids["gl"], ids["native"])


def test_the_line_tone_thins_feature_lines_in_the_light(renderer, path):
    # A wall whose every point is a feature point (colour noise: edges
    # everywhere), drawn as short lines only, lit 20 and 70 degrees off its
    # normal. With line_tone 1 the lines are thinner in the light (width x
    # 2 (1 - shade), at least a fifth); with 0 the light leaves them alone.
    pos, _ = wall(3.0, 2.4, 0.08, -5.0)
    colors = np.random.default_rng(5).random((len(pos), 3)).astype(np.float32)
    c = pointnpr.PointCloud(pos, colors=colors)

    def ink(elevation, line_tone):
        params = {"feature_threshold": 0.0, "directional": "none", "non_directional": "line_segment",
                  "dithering": "none", "line_width": 1.0, "other_length": 4.0, "line_tone": line_tone,
                  "shading": "diffuse", "shading_strength": 1.0, "color_source": "constant", "light_space": "camera",
                  "light_azimuth": 0.0, "light_elevation": elevation, "rasterizer": path}
        scene = pointnpr.Scene()
        scene.add_segment("s", pointnpr.Style(mark=("feature_strokes", params)), [(c, np.eye(4))])
        img = np.asarray(renderer.render(scene, camera(width=320, height=240), 320, 240).color)
        return float(1.0 - img[60:180, 80:240, :3].mean())

    plain = ink(20.0, 0.0), ink(70.0, 0.0)
    toned = ink(20.0, 1.0), ink(70.0, 1.0)
    assert plain[0] > 0.1 and abs(plain[0] - plain[1]) < 0.01, plain
    # Measured: 0.18 and 0.18 plain; 0.13 and 0.20 toned (a line a fifth of a
    # pixel wide still darkens the pixels it crosses a little).
    assert toned[1] > 1.3 * toned[0] and toned[0] < plain[0] < toned[1], (plain, toned)


def test_a_rough_surface_s_feature_marks_keep_the_tone_where_they_are_sparse(renderer, path):
    # A wall whose every point is a non-directional feature point (colour
    # noise), drawn as sprites with no dithering: foliage on an aerial tile
    # is such a surface, with no dithering points to give it tone. Its
    # sprites used to keep their size, so its ink followed the points'
    # spacing (measured 0.28, 0.17 at 0.03 and 0.05 between points); with a
    # tone they grow where too sparse for it, as the dithering's: 0.63, 0.62
    # (the tone's 1 - exp(-1)), and at 0.08 the growth's cap (3x) leaves 0.32.
    def ink(spacing, tone):
        pos, _ = wall(3.0, 2.4, spacing, -5.0)
        colors = np.random.default_rng(5).random((len(pos), 3)).astype(np.float32)
        params = {"feature_threshold": 0.0, "directional": "none", "non_directional": "point_sprite",
                  "sprite_size": 2.0, "dithering": "none", "tone": tone, "shading": "diffuse",
                  "color_source": "constant", "light_space": "camera", "light_elevation": 20.0, "rasterizer": path}
        scene = pointnpr.Scene()
        scene.add_segment("s", pointnpr.Style(mark=("feature_strokes", params)),
                          [(pointnpr.PointCloud(pos, colors=colors), np.eye(4))])
        img = np.asarray(renderer.render(scene, camera(width=320, height=240), 320, 240).color)
        return float(1.0 - img[60:180, 80:240, :3].mean())

    plain = [ink(s, 0.0) for s in (0.03, 0.05)]
    toned = [ink(s, 1.0) for s in (0.03, 0.05)]
    assert plain[0] > 1.4 * plain[1], plain
    assert abs(toned[0] - toned[1]) < 0.03 and min(toned) > 2.0 * max(plain), toned
    assert ink(0.08, 1.0) < min(toned) - 0.1  # at most 3x the sprite: a very sparse surface stays lighter
