#!/usr/bin/env bash
# Makes the two installable archives in build/dist/ (after scripts/build.sh):
#   pointnpr-extension-<version>.zip  Blender 4.2+ (Get Extensions > Install
#       from Disk): python_addon/extension (manifest + forwarding __init__)
#       and the self-contained wheel of scripts/build_wheel.sh in wheels/.
#   pointnpr-addon-<version>.zip      Blender 3.4-4.1 (Add-ons > Install):
#       the pointnpr package as built in build/pointnpr (bl_info), which
#       loads Debian's libraries (the Blender it is built for).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build_wheel.sh
# The cp313 wheel (Blender 5.1+): scripts/build.sh builds its module every time.
ABI=cp313 bash scripts/build_wheel.sh
cmake --build build --target pointnpr_package >/dev/null
/usr/bin/python3 - <<'PY'
import glob, os, tomllib, zipfile

dist = "build/dist"
source = "python_addon/extension"
with open(os.path.join(source, "blender_manifest.toml"), encoding="utf-8") as f:
    manifest_text = f.read()
manifest = tomllib.loads(manifest_text)
version = manifest["version"]
# Every wheel the manifest names must be there; the build fails otherwise.
wheels = {w: os.path.join(dist, os.path.basename(w)) for w in manifest["wheels"]}
missing = [w for w, path in wheels.items() if not os.path.isfile(path)]
if missing:
    raise SystemExit(f"build_extension: the manifest names wheels that were not built: {missing} "
                     f"(built: {sorted(os.path.basename(p) for p in glob.glob(dist + '/*.whl'))})")

extension = os.path.join(dist, f"pointnpr-extension-{version}.zip")
with zipfile.ZipFile(extension + ".tmp", "w", zipfile.ZIP_DEFLATED) as z:
    z.writestr("blender_manifest.toml", manifest_text)
    for name in ("__init__.py",):
        z.write(os.path.join(source, name), name)
    for entry, path in wheels.items():  # a wheel is compressed already
        z.write(path, os.path.normpath(entry), compress_type=zipfile.ZIP_STORED)
os.replace(extension + ".tmp", extension)

legacy = os.path.join(dist, f"pointnpr-addon-{version}.zip")
with zipfile.ZipFile(legacy + ".tmp", "w", zipfile.ZIP_DEFLATED) as z:
    for root, dirs, files in os.walk("build/pointnpr"):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            path = os.path.join(root, name)
            z.write(path, os.path.relpath(path, "build"))
os.replace(legacy + ".tmp", legacy)
for path in (extension, legacy):
    print(f"build_extension: {path} ({os.path.getsize(path) / 1e6:.1f} MB)")
PY
