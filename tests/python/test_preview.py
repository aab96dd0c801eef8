"""Styles for reduced-resolution previews (pointnpr.preview, the viewport's
navigation frames): pixel-sized parameters scale with the resolution."""
import numpy as np
import pytest

import pointnpr
from pointnpr import preview


def test_pixel_parameters_divide_by_the_factor_and_others_stay():
    style = pointnpr.Style(mark=("points", {"point_size": 6.0, "color_source": "constant"}),
                           filters=[("cartoon", {"outline_width": 6, "fill_gaps": 1}),
                                    ("blur", {"sigma": 0.8})],
                           inpaint={"radius": 8})
    small = preview.scaled_style(style, 4)
    assert small.mark[1]["point_size"] == 1.5
    assert small.mark[1]["color_source"] == "constant"
    cartoon = dict(small.filters[0][1])
    assert cartoon["outline_width"] == 2            # 6 / 4 = 1.5, half up
    assert cartoon["fill_gaps"] == 1                # 0.25 would vanish: kept at one preview pixel
    assert small.filters[1][1]["sigma"] == 0.3      # 0.2 clamped to the schema's minimum
    assert small.inpaint["radius"] == 2
    # Parameters in other units are untouched.
    for (fid, before), (fid2, after) in zip(style.filters, small.filters):
        assert fid == fid2
        units = {p["name"]: p["unit"] for p in pointnpr.schema(fid, "filter")["params"]}
        assert {k: v for k, v in before.items() if units[k] != "px"} == \
               {k: v for k, v in after.items() if units[k] != "px"}
    assert preview.scaled_style(style, 1) is style


def covered(result):
    return np.asarray(result.color)[..., 3] > 0


def test_a_scaled_preview_covers_what_the_full_frame_covers(renderer):
    # Sparse 8 px splats: their coverage depends on the splat size in pixels.
    g = np.linspace(-1.5, 1.5, 20)
    x, y = np.meshgrid(g, g * 0.75)
    cloud = pointnpr.PointCloud(np.column_stack([x.ravel(), y.ravel(), np.full(x.size, -6.0)]))
    segments = [("grid", pointnpr.Style(rasterize={"point_size": 8.0, "color_source": "constant"}), [cloud])]
    full_scene = pointnpr.Scene()
    full_scene.add_segment(*segments[0])
    def cam(w, h):
        return pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=w, height=h)
    full = covered(renderer.render(full_scene, cam(400, 300), 400, 300)).mean()
    scaled = covered(renderer.render(preview.scaled_scene(segments, 4), cam(100, 75), 100, 75)).mean()
    unscaled = covered(renderer.render(full_scene, cam(100, 75), 100, 75)).mean()
    assert 0.05 < full < 0.8
    assert scaled == pytest.approx(full, rel=0.2)
    assert unscaled > 1.5 * full   # what the preview would look like without scaling


def test_a_scaled_scene_shares_the_clouds(renderer):
    cloud = pointnpr.PointCloud(np.random.default_rng(1).uniform(-1, 1, (5000, 3)) + [0, 0, -5])
    scene = preview.scaled_scene([("a", pointnpr.Style(), [cloud]), ("b", pointnpr.Style(), [cloud])], 2)
    assert scene.num_segments == 2
    cam = pointnpr.Camera.perspective(np.eye(4), width=64, height=48)
    before = renderer.upload_count()
    renderer.render(scene, cam, 64, 48)
    renderer.render(scene, cam, 64, 48)
    assert renderer.upload_count() - before <= 1   # one cloud, uploaded once
