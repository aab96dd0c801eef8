"""Runs the PointNPR add-on tests inside Blender.

    blender -b --factory-startup --python-exit-code 1 \
        --python tests/blender/run.py -- <builddir> [pytest args...]

<builddir> holds the assembled package (<builddir>/pointnpr). The add-on is
enabled from there, then pytest runs tests/blender and Blender exits with
pytest's exit code.
"""
import os
import sys

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if not argv:
    print("usage: blender -b --python tests/blender/run.py -- <builddir> [pytest args]")
    sys.exit(2)
build_dir = os.path.abspath(argv[0])
if not os.path.isdir(os.path.join(build_dir, "pointnpr")):
    print("no pointnpr package in %s" % build_dir)
    sys.exit(2)
sys.path.insert(0, build_dir)
os.environ["POINTNPR_BUILD_DIR"] = build_dir

import pointnpr  # noqa: E402

pointnpr.register()

import pytest  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
code = pytest.main([here, "-p", "no:cacheprovider", "-ra", *argv[1:]])
sys.stdout.flush()
sys.exit(int(code))
