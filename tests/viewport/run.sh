#!/bin/sh
# Runs the viewport test under a virtual X server.
#   tests/viewport/run.sh <builddir> [out.png]
set -eu
here=$(cd "$(dirname "$0")" && pwd)
build=${1:?usage: run.sh <builddir> [out.png]}
out=${2:-$(mktemp -d)/viewport.png}
exec timeout 300 xvfb-run -a -s "-screen 0 1280x800x24" \
  blender --factory-startup --enable-event-simulate --python-exit-code 1 --python "$here/viewport_test.py" -- "$build" "$out"
