import os
import sys

import numpy as np
import pytest

# The built package lives in the build folder: POINTNPR_BUILD_DIR or ./build.
BUILD_DIR = os.environ.get("POINTNPR_BUILD_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "build"))
sys.path.insert(0, os.path.abspath(BUILD_DIR))


_ONE_THREAD_SCRIPT = r"""
import importlib, os, sys
os.sched_setaffinity(0, {sorted(os.sched_getaffinity(0))[0]})  # one CPU: TBB runs one thread
sys.path.insert(0, sys.argv[1])
sys.path.insert(0, sys.argv[2])
import pointnpr
print(getattr(importlib.import_module(sys.argv[3]), sys.argv[4])(pointnpr.Renderer()))
"""


def one_thread_in_another_process(module, function):
    """What `module.function(pointnpr.Renderer())` returns (its str) in a new
    process of this Python on one CPU, where TBB runs one thread: the
    native backends' bytes must not depend on the thread count or process."""
    import subprocess

    assert len(os.sched_getaffinity(0)) > 1  # else this process would run one thread too
    return subprocess.run([sys.executable, "-c", _ONE_THREAD_SCRIPT, os.path.abspath(BUILD_DIR),
                           os.path.dirname(os.path.abspath(__file__)), module, function], capture_output=True,
                          text=True, check=True, timeout=600).stdout.strip()


def plane(x0, x1, y0, y1, z, spacing, color, offset=(0.0, 0.0, 0.0)):
    """Points on a regular grid, one colour: a surface with known extent."""
    import pointnpr

    xs = np.arange(x0, x1 + 1e-9, spacing)
    ys = np.arange(y0, y1 + 1e-9, spacing)
    X, Y = np.meshgrid(xs, ys)
    n = X.size
    pos = np.column_stack([X.ravel(), Y.ravel(), np.full(n, float(z))]) + np.asarray(offset)
    return pointnpr.PointCloud(pos, colors=np.tile(np.asarray(color, np.uint8), (n, 1)))


@pytest.fixture(scope="session")
def renderer():
    import pointnpr

    return pointnpr.Renderer()


@pytest.fixture
def two_planes():
    import pointnpr

    scene = pointnpr.Scene()
    scene.add_segment("near", pointnpr.Style(rasterize={"point_size": 3}, filters=[("cartoon", {})]),
                      [plane(-1.2, 0.4, -0.6, 0.6, -5, 0.03, (230, 60, 40))])
    scene.add_segment("far", pointnpr.Style(rasterize={"point_size": 3}),
                      [plane(-2, 3, -1.5, 1.5, -10, 0.05, (40, 60, 230))])
    return scene


@pytest.fixture
def camera():
    import pointnpr

    return pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=320, height=240)
