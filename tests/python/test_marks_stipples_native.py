"""The stipples mark's two implementations of its passes: GL compute
shaders (for GPUs) and native passes on the CPU's threads (auto picks them
on software GL). The same float operations in the same order: the same
dots, colour and depth (tests/python/test_marks_stipples.py runs every
behaviour test on both; tests/cpp/test_marks_marks/stipples/native.cpp threads
and tiles)."""
import numpy as np
import pytest

import pointnpr
from test_marks import render, sphere


@pytest.fixture(scope="module")
def ball():
    return pointnpr.PointCloud(sphere(12000)[0])


@pytest.mark.parametrize("params", [{}, {"specular": True, "size_jitter": 0.5, "level": 5.5},
                                    {"shadow_casters": "visible", "specular": True, "tau": 0.3},
                                    {"shadow_casters": "all", "light_space": "world"},  # the share rule's shadows
                                    {"lit_rule": "nearest", "shadow_casters": "all"},  # the paper's rule
                                    {"resolution_factor": 2.0, "iterations": 5},
                                    {"density_mode": "constant_on_screen", "queue_level": 0.05, "tone": 0.0,
                                     "level_scale": "absolute", "level": 7.0},
                                    {"level_scale": "absolute", "tone": 0.9, "dot_size": 1.5},
                                    # a jitter that is no power of two: its product rounds
                                    {"specular": True, "size_jitter": 0.8, "level": 7.7, "dot_size": 3.3}])
def test_native_passes_draw_the_gl_passes_bytes(renderer, ball, params):
    out = {impl: render(renderer, pointnpr.Style(mark=("stipples", dict(params, rasterizer=impl))), [ball])
           for impl in ("gl", "native")}
    gl, native = out["gl"], out["native"]
    assert gl.stats["stipples_drawn"] > 200
    assert np.array_equal(np.sort(gl.marks["point_id"]), np.sort(native.marks["point_id"]))
    assert np.asarray(gl.color).tobytes() == np.asarray(native.color).tobytes()
    assert np.asarray(gl.depth).tobytes() == np.asarray(native.depth).tobytes()
    assert gl.stats["stipples_visible"] == native.stats["stipples_visible"]
    assert "stipples_native_dots_ms" in native.stats and "stipples_native_dots_ms" not in gl.stats


def test_auto_is_native_on_software_gl_and_gl_on_a_gpu(renderer, ball):
    r = render(renderer, pointnpr.Style(mark="stipples"), [ball])
    assert ("stipples_native_dots_ms" in r.stats) == bool(pointnpr.gl_info()["software"])
