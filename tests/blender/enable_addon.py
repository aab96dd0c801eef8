"""Enables the add-on from $POINTNPR_BUILD_DIR; for `blender -b file --python enable_addon.py -f 1`."""
import os
import sys

sys.path.insert(0, os.environ["POINTNPR_BUILD_DIR"])
import pointnpr  # noqa: E402

pointnpr.register()
