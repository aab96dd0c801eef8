"""Adds glib to a wheel auditwheel repaired (scripts/build_wheel.sh).

auditwheel's manylinux policy counts glib, gobject and gthread as part of
every system, so it leaves them out, yet 150+ of the libraries it vendors
(OpenImageIO's tree) need them and a render-farm image or a minimal container
may have no glib: the extension would then fail to enable with
"libgobject-2.0.so.0: cannot open shared object file". This copies them, and
whatever they need beyond the manylinux base that the wheel does not carry
already, into pointnpr.libs/ with hashed names (as auditwheel names its own),
and points every library needing them at the copies.

    python scripts/graft_libs.py <repaired wheel>     (patchelf on PATH)
"""
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile

import auditwheel

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pack_wheel import record_line  # noqa: E402

# Vendored although the policy admits them: no Blender needs glib.
GRAFTED = {"libglib-2.0.so.0", "libgobject-2.0.so.0", "libgthread-2.0.so.0", "libgmodule-2.0.so.0"}
SYSTEM_DIRS = ("/usr/lib/x86_64-linux-gnu", "/lib/x86_64-linux-gnu", "/usr/lib", "/lib")
LIBS = "pointnpr.libs"


def patchelf(*args):
    return subprocess.run(["patchelf", *args], check=True, capture_output=True, text=True).stdout.strip()


def manylinux_base(platform):
    """The libraries the wheel's policy lets the system provide, less GRAFTED."""
    path = os.path.join(os.path.dirname(auditwheel.__file__), "policy", "manylinux-policy.json")
    with open(path, encoding="utf-8") as f:
        policy = next(p for p in json.load(f) if p["name"] == platform)
    return set(policy["lib_whitelist"]) - GRAFTED | {"ld-linux-x86-64.so.2"}


def system_file(name):
    for folder in SYSTEM_DIRS:
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            return os.path.realpath(path)
    raise SystemExit("graft_libs: %s is needed but not on this system" % name)


def vendored_name(name, libs):
    """The hashed copy of ``name`` (libfoo-1.so.0 -> libfoo-1-<hash>.so...) the wheel has, if any."""
    stem = name.split(".so")[0]
    pattern = re.compile(re.escape(stem) + r"-[0-9a-f]{8}\.so")
    return next((f for f in sorted(os.listdir(libs)) if pattern.match(f)), None)


def graft(tree, base):
    libs = os.path.join(tree, LIBS)
    elves = [os.path.join(r, f) for r, _, fs in os.walk(tree) for f in fs if ".so" in f]
    needed = {path: set(patchelf("--print-needed", path).split()) for path in elves}
    renamed = {}  # original name -> vendored name
    queue = sorted(GRAFTED & set().union(*needed.values()))
    while queue:
        name = queue.pop(0)
        if name in renamed:
            continue
        source = system_file(name)
        with open(source, "rb") as f:
            digest = hashlib.sha256(f.read()).hexdigest()[:8]
        stem, _, version = name.partition(".so")
        copy = os.path.join(libs, "%s-%s.so%s" % (stem, digest, version))
        shutil.copyfile(source, copy)
        os.chmod(copy, 0o755)
        patchelf("--set-soname", os.path.basename(copy), copy)
        patchelf("--set-rpath", "$ORIGIN", copy)
        renamed[name] = os.path.basename(copy)
        own = set(patchelf("--print-needed", copy).split())
        needed[copy] = own
        for dep in sorted(own - base):
            if dep not in renamed and dep not in queue:
                present = vendored_name(dep, libs) if dep not in GRAFTED else None
                if present:
                    renamed[dep] = present
                else:
                    queue.append(dep)
    for path, names in needed.items():
        for name in sorted(names & set(renamed)):
            patchelf("--replace-needed", name, renamed[name], path)
    return renamed


def main(wheel):
    platform = re.search(r"-(manylinux_\d+_\d+)_x86_64\.whl$", wheel).group(1)
    with tempfile.TemporaryDirectory() as tree:
        with zipfile.ZipFile(wheel) as z:
            z.extractall(tree)
        renamed = graft(tree, manylinux_base(platform))
        files = sorted(os.path.relpath(os.path.join(r, f), tree) for r, _, fs in os.walk(tree) for f in fs)
        record = next(n for n in files if n.endswith(".dist-info/RECORD"))
        names = [n for n in files if n != record]
        lines = []
        with zipfile.ZipFile(wheel + ".tmp", "w", zipfile.ZIP_DEFLATED) as out:
            for name in names:
                with open(os.path.join(tree, name), "rb") as f:
                    data = f.read()
                info = zipfile.ZipInfo(name, date_time=(2026, 1, 1, 0, 0, 0))
                info.external_attr = (0o755 if ".so" in name else 0o644) << 16
                out.writestr(info, data, compress_type=zipfile.ZIP_DEFLATED)
                lines.append(record_line(name, data))
            lines.append(record + ",,")
            out.writestr(zipfile.ZipInfo(record, date_time=(2026, 1, 1, 0, 0, 0)), "\n".join(lines) + "\n")
    os.replace(wheel + ".tmp", wheel)
    print("graft_libs: %s: %s" % (os.path.basename(wheel),
                                  ", ".join("%s -> %s" % kv for kv in sorted(renamed.items())) or "nothing to graft"))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    main(sys.argv[1])
