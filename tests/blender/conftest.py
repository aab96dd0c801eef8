import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import helpers  # noqa: E402


def pytest_configure(config):
    # bpy (Blender as a module) has no window: run.py deselects these there,
    # and they run in Debian's Blender 3.4 (the viewport test stays there too).
    config.addinivalue_line("markers", "window: needs a Blender with a window (Xvfb), not bpy")
    # Each install path is tested on the Blenders that use it (run.py).
    config.addinivalue_line("markers", "legacy_addon: the legacy add-on zip (Blender 3.4-4.1)")
    config.addinivalue_line("markers", "extension: the extension zip (Blender 4.2+)")
    # An API Blender deprecates (e.g. 5.2's Scene.compositing_node_group)
    # fails the suite on that version instead of printing a warning.
    config.addinivalue_line("filterwarnings", "error::DeprecationWarning")


@pytest.fixture
def scene():
    """A fresh empty PointNPR scene."""
    return helpers.reset_scene()
