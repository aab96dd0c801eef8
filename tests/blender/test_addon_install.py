"""The package installs and enables as users install it, in a separate
Blender process: the legacy add-on zip (Preferences > Add-ons > Install) in
Blender 3.4-4.1, the extension zip (Get Extensions > Install from Disk) in
4.2+."""
import os
import shutil
import subprocess
import sys
import zipfile

import bpy
import pytest

import helpers

SCRIPT = r'''
import sys, addon_utils, bpy

def engines():
    """{'POINTNPR'} when the engine can be selected, else empty."""
    render = bpy.context.scene.render
    try:
        render.engine = 'POINTNPR'
    except TypeError:
        return set()
    render.engine = 'BLENDER_WORKBENCH'
    return {'POINTNPR'}

bpy.ops.preferences.addon_install(filepath=sys.argv[-1], overwrite=True)
mod = addon_utils.enable("pointnpr", default_set=True, handle_error=None)
assert mod is not None, "enable failed"
assert "POINTNPR" in engines()
assert hasattr(bpy.types.Scene, "pointnpr")
print("BL_INFO", mod.bl_info["name"], mod.bl_info["blender"])
addon_utils.disable("pointnpr", default_set=True)
assert not hasattr(bpy.types.Scene, "pointnpr")
assert "POINTNPR" not in engines()
addon_utils.enable("pointnpr", default_set=True)
assert hasattr(bpy.types.Scene, "pointnpr") and "POINTNPR" in engines()
print("ADDON_OK")
'''



def _zip_and_user_dirs(tmp_path):
    """The built package as an add-on zip, and an environment whose Blender
    user folders are fresh ones under tmp_path."""
    package = os.path.join(os.environ["POINTNPR_BUILD_DIR"], "pointnpr")
    archive = tmp_path / "pointnpr-addon.zip"
    with zipfile.ZipFile(archive, "w", zipfile.ZIP_DEFLATED) as z:
        for root, dirs, files in os.walk(package):
            dirs[:] = [d for d in dirs if d != "__pycache__"]
            for name in files:
                path = os.path.join(root, name)
                z.write(path, os.path.join("pointnpr", os.path.relpath(path, package)))
    user = tmp_path / "user"
    return archive, dict(os.environ, BLENDER_USER_SCRIPTS=str(user), BLENDER_USER_CONFIG=str(user / "config"))

@pytest.mark.legacy_addon
def test_zip_installs_and_enables(tmp_path):
    archive, env = _zip_and_user_dirs(tmp_path)
    user = tmp_path / "user"
    script = tmp_path / "install.py"
    script.write_text(SCRIPT)
    proc = subprocess.run(
        [bpy.app.binary_path, "-b", "--factory-startup", "--python-exit-code", "1",
         "--python", str(script), "--", str(archive)],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=300)
    out = proc.stdout.decode(errors="replace")
    assert proc.returncode == 0 and "ADDON_OK" in out, out[-3000:]
    assert (user / "addons" / "pointnpr" / "blender" / "engine.py").exists()
    shutil.rmtree(user, ignore_errors=True)


INSTALL_AND_SAVE = r'''
import sys, addon_utils, bpy
bpy.ops.preferences.addon_install(filepath=sys.argv[-1], overwrite=True)
assert addon_utils.enable("pointnpr", default_set=True, handle_error=None) is not None
bpy.ops.wm.save_userpref()
print("SAVED_PREFS")
'''

CHECK_MIGRATED = r'''
import bpy
tree = bpy.data.node_groups["Constant"]
node = tree.nodes["Rasterize"]
print("MIGRATED", node.bl_idname, node.rasterizer, node.gl_method, node.color_source)
'''


@pytest.mark.legacy_addon
def test_installed_addon_migrates_the_legacy_file_it_opens(tmp_path):
    """An add-on enabled in the preferences registers at startup (bpy.data
    is not reachable then); the legacy file opened on the command line is
    migrated by the load_post handler."""
    archive, env = _zip_and_user_dirs(tmp_path)
    user = tmp_path / "user"
    install = tmp_path / "install.py"
    install.write_text(INSTALL_AND_SAVE)
    proc = subprocess.run([bpy.app.binary_path, "-b", "--python-exit-code", "1", "--python", str(install),
                           "--", str(archive)], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          timeout=300)
    out = proc.stdout.decode(errors="replace")
    assert proc.returncode == 0 and "SAVED_PREFS" in out, out[-3000:]
    check = tmp_path / "check.py"
    check.write_text(CHECK_MIGRATED)
    legacy = os.path.join(os.path.dirname(__file__), "..", "data", "legacy_rasterize_anim.blend")
    proc = subprocess.run([bpy.app.binary_path, "-b", os.path.abspath(legacy), "--python-exit-code", "1",
                           "--python", str(check)], env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, timeout=300)
    out = proc.stdout.decode(errors="replace")
    assert proc.returncode == 0, out[-3000:]
    assert "MIGRATED PointNPRMarkPointsNode gl gl_points constant" in out, out[-3000:]
    shutil.rmtree(user, ignore_errors=True)


# Blender 4.2+: the extension zip, through Blender's own operator, into a
# fresh user folder, as Get Extensions > Install from Disk does.
EXTENSION_SCRIPT = r'''
import sys, addon_utils, bpy
result = bpy.ops.extensions.package_install_files(filepath=sys.argv[-1], repo="user_default",
                                                  enable_on_install=True)
assert result == {'FINISHED'}, result
module = "bl_ext.user_default.pointnpr"
assert module in bpy.context.preferences.addons
import pointnpr
print("PACKAGE", pointnpr.__file__)
render = bpy.context.scene.render
render.engine = 'POINTNPR'
assert hasattr(bpy.types.Scene, "pointnpr")
addon_utils.disable(module, default_set=True)
assert not hasattr(bpy.types.Scene, "pointnpr")
try:
    render.engine = 'POINTNPR'
    raise AssertionError("the engine outlived disabling")
except TypeError:
    pass
addon_utils.enable(module, default_set=True)
assert hasattr(bpy.types.Scene, "pointnpr")
render.engine = 'POINTNPR'
bpy.ops.wm.save_userpref()
print("EXTENSION_OK")
'''


def _extension_zip():
    import glob

    zips = glob.glob(os.path.join(os.environ["POINTNPR_BUILD_DIR"], "dist", "pointnpr-extension-*.zip"))
    assert len(zips) == 1, "scripts/build_extension.sh makes exactly one extension zip: %s" % zips
    return zips[0]


def _run_fresh(args, user, installed=False, timeout=300):
    """Another Blender on the user folder ``user``; bpy_blender.py enables
    the extension installed there when ``installed`` (bpy does not read
    saved preferences)."""
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(user),
               POINTNPR_TESTED_PACKAGE="extension" if installed else "")
    proc = subprocess.run(helpers.blender_command() + args, env=env, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, timeout=timeout)
    return proc.returncode, proc.stdout.decode(errors="replace")


@pytest.mark.extension
def test_extension_installs_enables_and_migrates_a_legacy_file(tmp_path):
    user = tmp_path / "user"
    script = tmp_path / "install.py"
    script.write_text(EXTENSION_SCRIPT)
    code, out = _run_fresh(["-b", "--factory-startup", "--python-exit-code", "1", "--python", str(script),
                            "--", _extension_zip()], user)
    assert code == 0 and "EXTENSION_OK" in out, out[-3000:]
    # The wheel went into the extensions' site-packages, not next to the add-on.
    assert str(user) in out.split("PACKAGE ")[1].split("\n")[0]
    assert list(user.glob("extensions/.local/lib/python3.*/site-packages/pointnpr.libs/libOpenImageIO*"))
    # A new session, with it enabled (from the saved preferences in Blender),
    # migrates the legacy file it opens.
    check = tmp_path / "check.py"
    check.write_text(CHECK_MIGRATED)
    legacy = os.path.join(os.path.dirname(__file__), "..", "data", "legacy_rasterize_anim.blend")
    code, out = _run_fresh(["-b", os.path.abspath(legacy), "--python-exit-code", "1", "--python", str(check)],
                           user, installed=True)
    assert code == 0, out[-3000:]
    assert "MIGRATED PointNPRMarkPointsNode gl gl_points constant" in out, out[-3000:]


def _tested_blenders():
    """The Blender lines of tests/blender/versions.txt, as (major, minor)."""
    with open(os.path.join(os.path.dirname(__file__), "versions.txt"), encoding="utf-8") as f:
        lines = [line.split()[0] for line in f if line.strip() and not line.startswith("#")]
    return [tuple(int(v) for v in line.split(".")) for line in lines]


@pytest.mark.extension
def test_extension_zip_passes_blenders_own_validation():
    """Blender's extension tool (what `blender --command extension validate`
    runs) accepts the zip: the manifest's fields and types, tagline and
    permission wording, wheel paths; and what the manifest names is there."""
    import tomllib

    zip_path = _extension_zip()
    import bl_pkg  # Blender's extensions add-on (addons_core), enabled by default

    tool = os.path.join(os.path.dirname(bl_pkg.__file__), "cli", "blender_ext.py")
    assert os.path.isfile(tool), tool
    proc = subprocess.run([sys.executable, tool, "validate", zip_path], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, timeout=120)
    out = proc.stdout.decode(errors="replace")
    assert proc.returncode == 0 and "Success" in out, out[-3000:]
    with zipfile.ZipFile(zip_path) as z:
        manifest = tomllib.loads(z.read("blender_manifest.toml").decode())
        names = set(z.namelist())
    assert manifest["id"] == "pointnpr" and manifest["type"] == "add-on"
    assert manifest["blender_version_min"] == "4.2.0" and manifest["platforms"] == ["linux-x64"]
    assert "files" in manifest["permissions"]
    # One wheel per CPython ABI: 3.11 (Blender 4.2 to 5.0) and 3.13 (5.1 and
    # later), always both; and no maximum that shuts out a tested Blender.
    assert manifest["wheels"] and all(w[2:] in names for w in manifest["wheels"]), (manifest["wheels"], names)
    abis = {w.split("-")[2] for w in manifest["wheels"]}
    assert abis == {"cp311", "cp313"}, manifest["wheels"]
    newest = max(_tested_blenders())
    assert newest >= (5, 3), newest
    if "blender_version_max" in manifest:  # exclusive: every patch of the newest line stays in
        maximum = tuple(int(v) for v in manifest["blender_version_max"].split("."))
        assert maximum[:2] > newest, (manifest["blender_version_max"], newest)
    assert "__init__.py" in names
