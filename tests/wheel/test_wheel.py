"""The self-contained wheels (scripts/build_wheel.sh) import, render and
write an image in a clean venv (no system site packages) where the build's
libraries cannot be loaded:
- cp311 (Blender 4.2 to 5.0) here, in a process where Debian's OpenImageIO,
  OpenEXR, Imath, OpenColorIO and TBB cannot be loaded: a private mount
  namespace (unshare -m) binds /dev/null over each of those files, so a
  module still needing them fails to import;
- cp313 (Blender 5.1+) in the Debian 13 root (scripts/debian13_root.sh),
  which has none of Debian 12's libraries and no glib: a bare system.

    scripts/build_extension.sh && python3 -m pytest -q tests/wheel
"""
import glob
import json
import os
import re
import subprocess
import sys
import textwrap
import zipfile

import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DIST = os.path.join(REPO, "build", "dist")
# How each wheel's clean venv is made and run: cp311 with Debian's python3
# here, cp313 with python3.13 in the Debian 13 root (its venv in build/, which
# the root sees at the same path).
ROOT13 = os.path.join(REPO, "build", "debian13-root")
IN_ROOT13 = ["bash", os.path.join(REPO, "scripts", "debian13_root.sh"), "run"]
INTERPRETERS = {"cp311": ["/usr/bin/python3"], "cp313": IN_ROOT13 + ["python3.13"]}
# Each wheel with the numpy its Blenders ship, and cp311 with numpy 2 too
# (a plain Python 3.11; its pybind11 must read numpy 2's arrays).
VENVS = {"cp311": "numpy==1.26.4", "cp311-numpy2": "numpy==2.3.5", "cp313": "numpy==2.3.5"}
# Debian's libraries the compiled module reaches (directly or through OIIO).
HIDDEN_NAMES = r"lib(OpenImageIO|OpenImageIO_Util|OpenEXR|OpenEXRCore|Imath|Iex|IlmThread|OpenColorIO|tbb)[-.]"
LIBDIR = "/usr/lib/x86_64-linux-gnu"

CHECK = textwrap.dedent("""
    import hashlib, json, sys
    import numpy as np
    import pointnpr

    def plane(z, spacing, rgb, half):
        xs = np.arange(-half, half + 1e-9, spacing)
        X, Y = np.meshgrid(xs, xs)
        pos = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, float(z))])
        return pointnpr.PointCloud(pos, colors=np.tile(np.array(rgb, np.uint8), (X.size, 1)))

    scene = pointnpr.Scene()
    scene.add_segment("near", pointnpr.Style(rasterize={"point_size": 3}, filters=["cartoon"]),
                      [plane(-5, 0.03, (230, 60, 40), 0.8)])
    scene.add_segment("far", pointnpr.Style(rasterize={"point_size": 3}), [plane(-10, 0.05, (40, 60, 230), 3)])
    camera = pointnpr.Camera.perspective(np.eye(4), width=160, height=120)
    result = pointnpr.Renderer().render(scene, camera, 160, 120, background=(0, 0, 0, 1))
    # Arrays the bindings make, read through this numpy: a local resolution
    # per point of an unevenly spaced line (one value repeated: misread).
    spacing, _ = pointnpr.local_resolution(np.column_stack([np.arange(50.0) ** 2, np.zeros(50), np.zeros(50)]), k=2)
    pointnpr.save_image(sys.argv[1], np.ascontiguousarray(result.color))
    back = pointnpr.load_image(sys.argv[1])
    maps = sorted({line.split()[-1] for line in open("/proc/self/maps") if ".so" in line.split()[-1]})
    print("RESULT " + json.dumps({
        "package": pointnpr.__file__, "maps": maps, "shape": list(back.shape),
        "centre": [float(v) for v in back[60, 80, :3]], "side": [float(v) for v in back[60, 40, :3]],
        "digest": hashlib.sha256(np.asarray(result.color).tobytes()).hexdigest(),
        "numpy": np.__version__, "distinct_spacings": int(np.unique(spacing).size)}))
""")


def _wheel(abi):
    wheels = glob.glob(os.path.join(DIST, "pointnpr-*-%s-%s-manylinux_*_x86_64.whl" % (abi, abi)))
    assert len(wheels) == 1, "scripts/build_wheel.sh makes one repaired wheel per ABI in %s: %s" % (DIST, wheels)
    return wheels[0]


def _hidden_files():
    files = sorted({os.path.realpath(os.path.join(LIBDIR, f)) for f in os.listdir(LIBDIR)
                    if re.match(HIDDEN_NAMES, f) and ".so" in f})
    assert any("libOpenImageIO.so" in f for f in files), files  # Debian's OIIO is there to hide
    return files


def _hiding(command):
    """``command`` in a private mount namespace where the hidden files read
    as empty (root, or password-less sudo, for unshare)."""
    binds = " ".join("mount --bind /dev/null %s &&" % f for f in _hidden_files())
    prefix = [] if os.geteuid() == 0 else ["sudo", "-n"]
    return prefix + ["unshare", "-m", "sh", "-c", binds + ' exec "$@"', "sh"] + command


@pytest.fixture(scope="module", params=sorted(VENVS))
def venv(request, tmp_path_factory):
    """A clean venv (no system site packages) with the wheel of an ABI and
    numpy: the command that runs its python, and a scratch folder it sees."""
    abi = request.param.split("-")[0]
    if abi == "cp313":
        assert os.path.isfile(os.path.join(ROOT13, ".recipe")), "scripts/debian13_root.sh make"
        scratch = os.path.join(REPO, "build", "wheel-test-cp313")
        subprocess.run(["rm", "-rf", scratch], check=True)
        os.makedirs(scratch)
        prefix = IN_ROOT13
    else:
        scratch, prefix = str(tmp_path_factory.mktemp("wheel-" + abi)), []
    path = os.path.join(scratch, "venv")
    subprocess.run(INTERPRETERS[abi] + ["-m", "venv", path], check=True)
    python = prefix + [os.path.join(path, "bin", "python")]
    out = subprocess.run(python + ["-c", "import sys; print(sys.flags.no_site, sys.path)"],
                         capture_output=True, text=True, check=True).stdout
    assert "/usr/lib/python3/dist-packages" not in out, out
    version = subprocess.run(python + ["-c", "import sys; print('cp%d%d' % sys.version_info[:2])"],
                             capture_output=True, text=True, check=True).stdout.strip()
    assert version == abi, (version, abi)
    subprocess.run(python + ["-m", "pip", "install", "-q", _wheel(abi), VENVS[request.param]], check=True)
    return abi, python, scratch


def test_hiding_really_hides_debians_openimageio():
    proc = subprocess.run(_hiding(["/usr/bin/python3", "-c",
                                   "import ctypes; ctypes.CDLL('%s/libOpenImageIO.so.2.4')" % LIBDIR]),
                          capture_output=True, text=True)
    assert proc.returncode != 0 and "OSError" in proc.stderr, proc.stderr[-2000:]


def test_the_debian13_root_is_a_bare_system():
    """What the cp313 test proves rests on this: the root has no glib and
    none of the Debian 12 libraries the module was linked against."""
    found = [os.path.join(r, f) for r, _, fs in os.walk(os.path.join(ROOT13, "usr", "lib"))
             for f in fs if re.match(r"lib(glib|gobject|gthread)-2\.0\.so|" + HIDDEN_NAMES, f)]
    assert not found, found


def test_wheel_renders_and_writes_an_image_without_debians_libraries(venv, tmp_path):
    abi, python, scratch = venv
    image = os.path.join(scratch, "frame.png")
    script = os.path.join(scratch, "check.py")
    with open(script, "w") as f:
        f.write(CHECK)
    command = python + [script, image]
    proc = subprocess.run(_hiding(command) if abi == "cp311" else command, capture_output=True, text=True,
                          timeout=300, cwd=scratch)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    result = json.loads(proc.stdout.split("RESULT ", 1)[1])
    # Arrays made by the bindings hold their own values under this numpy.
    assert result["distinct_spacings"] > 40, (result["numpy"], result["distinct_spacings"])
    site = os.path.dirname(os.path.dirname(result["package"]))
    assert site.startswith(scratch) and site.endswith("site-packages"), result["package"]
    hidden = set(_hidden_files())
    assert not hidden & set(result["maps"]), sorted(hidden & set(result["maps"]))
    vendored = [m for m in result["maps"] if "/pointnpr.libs/" in m]
    assert any(os.path.basename(m).startswith("libOpenImageIO-") for m in vendored), result["maps"]
    # glib comes from the wheel (scripts/graft_libs.py), never the system.
    glib = [m for m in result["maps"] if re.search(r"/lib(glib|gobject)-2\.0", m)]
    assert glib and all("/pointnpr.libs/" in m for m in glib), glib
    # The picture, read back from the file: 160x120, the red near plane in
    # the middle, the blue far one around it.
    assert result["shape"][:2] == [120, 160] and os.path.getsize(image) > 0
    r, g, b = result["centre"]
    assert r > 0.3 and r > 2 * b, result["centre"]
    r, g, b = result["side"]
    assert b > 0.1 and b > 2 * r, result["side"]
    # Same pixels as the module built against Debian's libraries.
    env = dict(os.environ, PYTHONPATH=os.path.join(REPO, "build"))
    reference = subprocess.run(["/usr/bin/python3", script, str(tmp_path / "reference.png")], env=env,
                               capture_output=True, text=True, timeout=300, check=True).stdout
    assert json.loads(reference.split("RESULT ", 1)[1])["digest"] == result["digest"]


@pytest.mark.parametrize("abi", sorted(INTERPRETERS))
def test_vendored_libraries_are_renamed_and_gl_stays_the_systems(abi):
    """auditwheel gives every vendored library a hashed name (and SONAME), so
    it cannot be mistaken for a copy Blender ships; libEGL/libOpenGL, which
    pick the GPU driver, are not vendored."""
    names = [n for n in zipfile.ZipFile(_wheel(abi)).namelist() if n.startswith("pointnpr.libs/") and n[-1] != "/"]
    assert len(names) > 50, names   # OIIO's whole dependency tree
    libs = [os.path.basename(n) for n in names]
    assert all(re.search(r"-[0-9a-f]{8}\.", n) for n in libs), [n for n in libs
                                                                  if not re.search(r"-[0-9a-f]{8}\.", n)]
    assert not [n for n in libs if re.match(r"lib(EGL|GL|OpenGL|GLX|GLdispatch)[-.]", n)]
    assert any(n.startswith("libOpenImageIO-") for n in libs) and any(n.startswith("libtbb-") for n in libs)
