"""Runs the PointNPR add-on tests inside Blender, two ways:

    blender -b --factory-startup --python-exit-code 1 \\
        --python tests/blender/run.py -- <builddir> [pytest args...]

Blender 3.4 (Debian's): the package <builddir>/pointnpr is registered
directly (the legacy zip install is tested by test_addon_install.py).

    .venv-bpy-4.2/bin/python tests/blender/run.py \\
        --extension <builddir>/dist/pointnpr-extension-<version>.zip -- <builddir> [pytest args...]

bpy 4.2+ from PyPI (Blender as a Python module): a fresh user folder, the
extension zip installed and enabled through Blender's own operator, as a
user installs it; the tests then import the pointnpr package Blender
installed from the extension's wheel, never the build folder's.

Blender exits with pytest's exit code; a run that collects no test fails.
"""
import os
import sys
import tempfile

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
before = sys.argv[:sys.argv.index("--")] if "--" in sys.argv else sys.argv
extension = before[before.index("--extension") + 1] if "--extension" in before else None
if not argv:
    print(__doc__)
    sys.exit(2)
build_dir = os.path.abspath(argv[0])
if not os.path.isdir(os.path.join(build_dir, "pointnpr")):
    print("no pointnpr package in %s" % build_dir)
    sys.exit(2)
os.environ["POINTNPR_BUILD_DIR"] = build_dir

if extension:
    # Before bpy loads: Blender reads its user folders (preferences,
    # extension repositories) from here.
    user = tempfile.mkdtemp(prefix="pointnpr-bpy-user-")
    os.environ["BLENDER_USER_RESOURCES"] = user
    import bpy

    result = bpy.ops.extensions.package_install_files(
        filepath=os.path.abspath(extension), repo="user_default", enable_on_install=True)
    if result != {'FINISHED'} or "bl_ext.user_default.pointnpr" not in bpy.context.preferences.addons:
        print("the extension %s did not install and enable: %s" % (extension, result))
        sys.exit(3)
    import pointnpr  # noqa: E402

    if not os.path.abspath(pointnpr.__file__).startswith(user):
        print("pointnpr imported from %s, not from the installed extension" % pointnpr.__file__)
        sys.exit(3)
    os.environ["POINTNPR_TESTED_PACKAGE"] = "extension"
else:
    sys.path.insert(0, build_dir)
    import pointnpr  # noqa: E402

    pointnpr.register()
    os.environ["POINTNPR_TESTED_PACKAGE"] = "build"

import bpy  # noqa: E402
import pytest  # noqa: E402

print("PointNPR tests in Blender %s, package %s" % (bpy.app.version_string, os.path.dirname(pointnpr.__file__)))
here = os.path.dirname(os.path.abspath(__file__))
# bpy has no window: the tests that open one run in Blender 3.4 only; each
# install path (legacy add-on zip, extension zip) on the Blenders that use it.
only = ["-m", "not window and not legacy_addon"] if extension else ["-m", "not extension"]
code = pytest.main([here, "-p", "no:cacheprovider", "-ra", *only, *argv[1:]])
sys.stdout.flush()
sys.stderr.flush()
# pytest's "no tests collected" (5) stays a failure: a suite that silently
# ran nothing must not pass.
if extension:
    # bpy's own exit crashes (4.2) or hangs (4.5) once any Panel class was
    # registered, add-on or not: it frees the classes after Python is gone.
    # The Blender executable frees them first, so users never see it.
    # os._exit skips every cleanup: the installed extension (its wheel's
    # 0.5 GB) would stay in /tmp after each run.
    import shutil
    shutil.rmtree(user, ignore_errors=True)
    os._exit(int(code))
sys.exit(int(code))
