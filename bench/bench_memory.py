#!/usr/bin/env python3
"""Peak memory per point of a large scan: import + two F12 frames (issue 14).

Tiles the LiDAR HD subset (data/lidarhd_myria3d_870000_6618000_subset.las,
70,840 points, LAS 1.4 format 8) k x k times side by side, writes it once as
LAS into a temporary folder (its records copied with shifted X and Y, so the
file is the tile's format with every field; deleted afterwards), then
measures it in fresh
processes, one per (size, host), so each peak is that run's own:

- blender: ``blender -b --factory-startup``, File > Import through the
  add-on's operator, two F12 frames (bpy.ops.render.render) at 1920x1080 of
  the default style (plain points) from an orthographic camera above;
- bpy-X.Y: the same in each bpy venv (.venv-bpy-*) that exists;
- core: the Python module alone: pointnpr.read -> to_cloud -> two renders.

It reports the time and the process's peak RSS (ru_maxrss, which counts
file pages mapped while reading too) after each stage, and per point.

    /usr/bin/python3 bench/bench_memory.py [--build build] [--tiles 12 21] [--hosts core blender bpy | bpy-4.2 ...]

(12 x 12 tiles = 10.2M points, 21 x 21 = 31.2M, 38 x 38 = 102M.)
"""
import argparse
import json
import os
import pathlib
import resource
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
TILE = ROOT / "data" / "lidarhd_myria3d_870000_6618000_subset.las"
WIDTH, HEIGHT = 1920, 1080


def peak_rss():
    """Bytes: the process's peak resident set (VmHWM; ru_maxrss is the same in KiB)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


# ---------------------------------------------------------------------------
# The scan

def write_tiled_las(k, path):
    """k x k copies of the tile's point records, shifted by its extent (in the
    file's integer units, so every field is kept exactly), written tile by
    tile: the writer holds one tile, whatever k is. Returns the point count."""
    import struct

    import numpy as np

    raw = TILE.read_bytes()
    assert raw[:4] == b"LASF" and raw[25] == 4, "the tile is LAS 1.4"
    start = struct.unpack_from("<I", raw, 96)[0]
    record = struct.unpack_from("<H", raw, 105)[0]
    n = struct.unpack_from("<Q", raw, 247)[0]
    assert struct.unpack_from("<I", raw, 243)[0] == 0 and start + n * record == len(raw), "no EVLRs"
    scale = struct.unpack_from("<3d", raw, 131)
    offset = struct.unpack_from("<3d", raw, 155)
    records = np.frombuffer(raw, dtype=np.uint8, count=n * record, offset=start).reshape(n, record)
    xy = records[:, :8].copy().view("<i4")   # X, Y as stored
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    step = hi - lo + 1
    header = bytearray(raw[:start])
    total = n * k * k
    struct.pack_into("<Q", header, 247, total)
    if struct.unpack_from("<I", header, 107)[0]:
        struct.pack_into("<I", header, 107, total)
    bounds = struct.unpack_from("<6d", header, 179)   # max x, min x, max y, min y, max z, min z
    top = lo + step * (k - 1) + (hi - lo)
    struct.pack_into("<4d", header, 179, top[0] * scale[0] + offset[0], bounds[1],
                     top[1] * scale[1] + offset[1], bounds[3])
    with open(path, "wb") as f:
        f.write(header)
        tile = records.copy()
        for j in range(k):
            for i in range(k):
                tile[:, :8] = (xy + step * np.array([i, j], dtype=np.int32)).view(np.uint8).reshape(n, 8)
                f.write(tile.tobytes())
    return total


# ---------------------------------------------------------------------------
# Child processes (one measurement each)

def child_core(build, path, out):
    sys.path.insert(0, str(build))
    import numpy as np
    import pointnpr

    stages = [("start", 0.0, peak_rss())]
    t0 = time.perf_counter()
    data = pointnpr.read(path)
    cloud = data.to_cloud()
    n = len(data)
    lo, hi = data.positions.min(axis=0), data.positions.max(axis=0)
    del data
    stages.append(("read + PointCloud", time.perf_counter() - t0, peak_rss()))
    centre = (lo + hi) / 2
    eye = np.eye(4)
    eye[:3, 3] = (centre[0], centre[1], hi[2] + 100.0)
    camera = pointnpr.Camera.orthographic(eye, ortho_scale=float(max(hi - lo)), clip_start=1.0,
                                          clip_end=1000.0, width=WIDTH, height=HEIGHT)
    scene = pointnpr.Scene()
    scene.add_segment("scan", pointnpr.Style(), [cloud])
    renderer = pointnpr.Renderer()
    for i in (1, 2):
        t0 = time.perf_counter()
        result = renderer.render(scene, camera, WIDTH, HEIGHT)
        del result
        stages.append(("frame %d" % i, time.perf_counter() - t0, peak_rss()))
    json.dump({"points": n, "stages": stages}, open(out, "w"))


def pointnpr_scene(pointnpr):
    """Blender's startup scene (in blender -b) emptied but for its camera,
    rendered by PointNPR at WIDTH x HEIGHT."""
    import bpy

    pointnpr.register()
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):  # the startup cube would render as a mesh
        if obj.type != 'CAMERA':
            bpy.data.objects.remove(obj)
    scene.render.engine = "POINTNPR"
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    return scene


def camera_above(scene, obj):
    """The scene's camera looking straight down at all of ``obj``, orthographic."""
    import numpy as np

    lo = np.array([min(c[i] for c in obj.bound_box) for i in range(3)])
    hi = np.array([max(c[i] for c in obj.bound_box) for i in range(3)])
    cam = scene.camera
    cam.location = ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + 100.0)
    cam.rotation_euler = (0.0, 0.0, 0.0)
    cam.data.type = 'ORTHO'
    cam.data.ortho_scale = float(max(hi - lo))
    cam.data.clip_start, cam.data.clip_end = 1.0, 1000.0


def child_blender(build, path, out, in_core=False):
    import bpy
    import numpy as np

    sys.path.insert(0, str(build))
    import pointnpr

    scene = pointnpr_scene(pointnpr)
    scene.render.filepath = os.path.join(os.path.dirname(out), "frame")
    stages = [("start", 0.0, peak_rss())]
    t0 = time.perf_counter()
    # The operator's defaults put scans above its threshold (20M) out of core
    # (a proxy object and an on-disk cache the render streams); --in-core
    # holds every point in the mesh, as before that option existed.
    options = {"out_of_core": False} if in_core else {}
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=path, **options) == {'FINISHED'}
    stages.append(("import", time.perf_counter() - t0, peak_rss()))
    obj = next(o for o in scene.objects if o.type == 'MESH')
    n = pointnpr.read_header(path)["point_count"]   # the scan's, not a proxy's
    camera_above(scene, obj)
    for i in (1, 2):
        t0 = time.perf_counter()
        bpy.ops.render.render()
        stages.append(("F12 %d" % i, time.perf_counter() - t0, peak_rss()))
    json.dump({"points": n, "stages": stages, "blender": bpy.app.version_string,
               "out_of_core": bool(obj.get("pointnpr_cache"))}, open(out, "w"))
    if not bpy.app.binary_path:
        # bpy as a module can hang in its own exit handlers (its delayed-close
        # thread); the result is written, so leave at once, as tests/blender/run.py does.
        sys.stdout.flush()
        os._exit(0)


# ---------------------------------------------------------------------------
# The driver

def hosts(requested):
    """[(label, argv prefix to run this file as a child)]"""
    out = []
    if "core" in requested:
        out.append(("core", ["/usr/bin/python3", __file__, "--child", "core"]))
    if "blender" in requested and shutil.which("blender"):
        out.append(("Blender 3.4 (Debian)", ["blender", "-b", "--factory-startup", "--python-exit-code", "1",
                                             "--python", __file__, "--", "--child", "blender"]))
    for venv in sorted(ROOT.glob(".venv-bpy-*")):   # "bpy": every one; "bpy-4.2": that one
        line = venv.name[len(".venv-bpy-"):]
        python = venv / "bin" / "python"
        if python.exists() and ("bpy" in requested or "bpy-" + line in requested):
            out.append(("bpy " + line, [str(python), __file__, "--child", "blender"]))
    return out


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--tiles", type=int, nargs="+", default=[12, 21])
    ap.add_argument("--hosts", nargs="+", default=["core", "blender", "bpy"])
    ap.add_argument("--in-core", action="store_true",
                    help="import every point into the mesh (out_of_core off) instead of the operator's defaults")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--path", help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    build = pathlib.Path(args.build).resolve()
    if args.child == "core":
        return child_core(build, args.path, args.out)
    if args.child == "blender":
        return child_blender(build, args.path, args.out, args.in_core)

    print("| host | points | stage | time | peak RSS | per point |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="bench_memory_") as tmp:
        for k in args.tiles:
            las = pathlib.Path(tmp) / ("tile_%dx%d.las" % (k, k))
            write_tiled_las(k, las)
            for label, cmd in hosts(args.hosts):
                out = pathlib.Path(tmp) / "result.json"
                run = subprocess.run(cmd + ["--build", str(build), "--path", str(las), "--out", str(out)] +
                                     (["--in-core"] if args.in_core else []),
                                     capture_output=True, text=True)
                if not out.exists():
                    print("| %s | %dx%d tiles | failed (exit %d): %s |" % (label, k, k, run.returncode,
                                                                         run.stderr.strip()[-300:]))
                    continue
                res = json.load(open(out))
                out.unlink()
                n = res["points"]
                if res.get("out_of_core"):
                    label += " (out of core)"
                for stage, seconds, rss in res["stages"]:
                    print("| %s | %.1fM | %s | %s | %.2f GB | %.0f B |" % (
                        label, n / 1e6, stage, "%.1f s" % seconds if seconds else "", rss / 1e9, rss / n))
                if run.returncode != 0:   # after its last stage (its result was written)
                    print("| %s | %.1fM | exit | exit status %d after the last stage | | |" % (
                        label, n / 1e6, run.returncode))
                sys.stdout.flush()
            las.unlink()


if __name__ == "__main__":
    main()
