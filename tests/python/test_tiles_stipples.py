"""The stipples mark drawn in tiles (issue 17): the same bytes as the frame
drawn whole, for the defaults, every stipple preset and the choices that
depend on every visible point of the frame (visible shadow casters, the
specular reference). Its per-frame state (the light-view quadtree, the
light cells' counts, the specular reference) is computed once, over windows
of the tile's size, so tiles of any size see the same numbers."""
import numpy as np
import pytest

import pointnpr
from pointnpr import presets
from test_tiles import assert_same_bytes, render_both, wavy_cloud

STIPPLE_PRESETS = [name for name, p in presets.PRESETS.items() if p["mark"][0] == "stipples"]


@pytest.fixture(scope="module")
def clouds():
    # The wall in 7 chunks: tiles see different subsets of them (the frame's
    # light bounds and point count are not any tile's).
    return wavy_cloud(100000, 3, -6.0), wavy_cloud(12000, 4, -5.0, spread=1.0)


@pytest.fixture(params=["gl", "native"])
def implementation(request):
    return request.param


def stipple_scene(clouds, mark_params, filters=(("blur", {}),), implementation="auto"):
    mark_params = dict(mark_params, rasterizer=implementation)
    scene = pointnpr.Scene()
    scene.add_segment("wall", pointnpr.Style(mark=("stipples", mark_params), filters=list(filters),
                                             inpaint={"radius": 4}), [clouds[0]])
    scene.add_segment("crown", pointnpr.Style(mark=("stipples", dict(mark_params, dot_size=3.0)),
                                              filters=[("cartoon", {})]), [clouds[1]])
    return scene


def test_presets_cover_the_stipple_looks():
    assert len(STIPPLE_PRESETS) >= 3 and "Stipple specular" in STIPPLE_PRESETS


@pytest.mark.parametrize("name", ["defaults"] + STIPPLE_PRESETS)
def test_stipples_tiled_are_the_bytes_of_the_whole_frame(renderer, clouds, name, implementation):
    params = {} if name == "defaults" else dict(presets.PRESETS[name]["mark"][1])
    whole, tiled = render_both(renderer, stipple_scene(clouds, params, implementation=implementation), 301, 233, 64)
    assert tiled.stats["tiles"] >= 12
    assert_same_bytes(whole, tiled)
    # Dots were drawn and thinned (not an empty or a saturated picture).
    assert 0 < whole.stats["stipples_drawn"] < whole.stats["stipples_visible"]


@pytest.mark.parametrize("params,size", [
    ({"shadow_casters": "visible", "specular": True, "tau": 0.3, "level": 5.5}, (297, 229)),
    ({"specular": True, "specular_cell": 16.0, "iterations": 5, "resolution_factor": 2.0, "diffuse": False},
     (431, 333)),
], ids=["visible casters", "wide cells"])
def test_frame_wide_choices_tiled_are_the_bytes_of_the_whole_frame(renderer, clouds, params, size, implementation):
    whole, tiled = render_both(renderer, stipple_scene(clouds, params, implementation=implementation), size[0],
                               size[1], 64)
    assert_same_bytes(whole, tiled)
    if params.get("specular_cell", 0) > 8:
        assert tiled.stats["tile_halo"] > 50  # the specular cells' reach, not just the dots'
