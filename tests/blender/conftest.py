import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import helpers  # noqa: E402


@pytest.fixture
def scene():
    """A fresh empty PointNPR scene."""
    return helpers.reset_scene()
