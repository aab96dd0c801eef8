"""Packs an assembled pointnpr package folder (scripts/build.sh's
build/pointnpr) into a wheel, with the metadata of pyproject.toml: the same
files `pip wheel .` installs, without configuring and compiling again.

    python3 scripts/pack_wheel.py <package dir> <out dir> [cpXY]     -> prints the wheel's path

The tag is the interpreter's (cp311-cp311-linux_x86_64 for Debian's
python3), or the ABI given (cp313: the module built from Debian 13's headers,
with no 3.13 interpreter here); auditwheel (scripts/build_wheel.sh) then
makes it manylinux.
"""
import base64
import hashlib
import os
import sys
import sysconfig
import tomllib
import zipfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return "%s,sha256=%s,%d" % (name, digest, len(data))


def main(package_dir, out_dir, abi=None):
    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as f:
        project = tomllib.load(f)["project"]
    name, version = project["name"], project["version"]
    abi = abi or "cp%d%d" % sys.version_info[:2]
    suffix = ".cpython-%s-%s.so" % (abi[2:], sysconfig.get_config_var("MULTIARCH"))
    if not any(f.startswith("_pointnpr") and f.endswith(suffix) for f in os.listdir(package_dir)):
        raise SystemExit("pack_wheel: no _pointnpr%s in %s (built for another Python?)" % (suffix, package_dir))
    tag = "%s-%s-%s" % (abi, abi, sysconfig.get_platform().replace("-", "_").replace(".", "_"))
    dist_info = "%s-%s.dist-info" % (name, version)
    metadata = ["Metadata-Version: 2.1", "Name: " + name, "Version: " + version,
                "Summary: " + project["description"], "Requires-Python: " + project["requires-python"],
                "License: " + project["license"]["text"]]
    metadata += ["Requires-Dist: " + d for d in project.get("dependencies", [])]
    wheel_meta = ["Wheel-Version: 1.0", "Generator: pointnpr scripts/pack_wheel.py", "Root-Is-Purelib: false",
                  "Tag: " + tag]
    path = os.path.join(out_dir, "%s-%s-%s.whl" % (name, version, tag))
    records = []
    with zipfile.ZipFile(path + ".tmp", "w", zipfile.ZIP_DEFLATED) as z:
        def add(arcname, data):
            z.writestr(zipfile.ZipInfo(arcname, date_time=(2026, 1, 1, 0, 0, 0)), data,
                       compress_type=zipfile.ZIP_DEFLATED)
            records.append(record_line(arcname, data))

        for root, dirs, files in os.walk(package_dir):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__")
            for f in sorted(files):
                if f.endswith(".pyc"):
                    continue
                full = os.path.join(root, f)
                with open(full, "rb") as fh:
                    add(name + "/" + os.path.relpath(full, package_dir).replace(os.sep, "/"), fh.read())
        add(dist_info + "/METADATA", ("\n".join(metadata) + "\n").encode())
        add(dist_info + "/WHEEL", ("\n".join(wheel_meta) + "\n").encode())
        records.append(dist_info + "/RECORD,,")
        z.writestr(dist_info + "/RECORD", "\n".join(records) + "\n")
    os.replace(path + ".tmp", path)
    print(path)


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        raise SystemExit(__doc__)
    main(*sys.argv[1:])
