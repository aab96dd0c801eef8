"""Enables PointNPR from a build folder without installing the add-on, for
headless renders of a .blend that uses it:

    POINTNPR_BUILD_DIR=$PWD/build blender -b --python scripts/enable_addon.py scene.blend -o //out_#### -a

Blender runs its arguments in order: named before the .blend, the script
registers the engine before the file is read (after it, loading prints
"Engine 'POINTNPR' not available"). With the add-on installed in Blender's
preferences this script is not needed.
"""
import os
import sys

build_dir = os.environ.get("POINTNPR_BUILD_DIR")
if not build_dir:
    build_dir = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "build")
sys.path.insert(0, os.path.abspath(build_dir))
import pointnpr  # noqa: E402

pointnpr.register()
