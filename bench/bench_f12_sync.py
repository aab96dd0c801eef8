#!/usr/bin/env python3
"""The F12 of a large scan and its scene sync, repeated (issue 14).

The LiDAR HD subset tiled k x k times (bench_memory.write_tiled_las: 12 ->
10.2M points), imported through the add-on's operator in ``blender -b``,
then F12 at 1920x1080 (plain points, orthographic camera above) several
times; per F12 its wall time and the time of the sync inside it
(sync.build_scene), in a fresh Blender per build folder, the builds
interleaved round by round so that each sees the same load:

    /usr/bin/python3 bench/bench_f12_sync.py --builds build [other_build ...] [--tiles 12] [--frames 3] [--rounds 2]

A build folder is anything with an importable ``pointnpr`` package (e.g. a
copy of build/ with another commit's python_addon/pointnpr in it).
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]


def child(build, path, frames, out):
    import bpy

    sys.path.insert(0, str(build))
    import pointnpr
    from pointnpr.blender import sync

    sys.path.insert(0, str(ROOT / "bench"))
    from bench_memory import camera_above, peak_rss, pointnpr_scene

    scene = pointnpr_scene(pointnpr)
    assert bpy.ops.import_scene.pointnpr_cloud(filepath=path) == {'FINISHED'}
    obj = next(o for o in scene.objects if o.type == 'MESH')
    camera_above(scene, obj)

    sync_s = []
    build_scene = sync.build_scene

    def timed(*args, **kwargs):
        t0 = time.perf_counter()
        try:
            return build_scene(*args, **kwargs)
        finally:
            sync_s.append(time.perf_counter() - t0)

    sync.build_scene = timed
    rows = []
    for _ in range(frames):
        t0 = time.perf_counter()
        bpy.ops.render.render()
        rows.append((time.perf_counter() - t0, sync_s[-1]))
    json.dump({"points": len(obj.data.vertices), "frames": rows, "blender": bpy.app.version_string,
               "stats": sync.cache_stats(), "peak_rss": peak_rss()}, open(out, "w"))


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--builds", nargs="+", default=[str(ROOT / "build")])
    ap.add_argument("--tiles", type=int, default=12)
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--path", help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return child(pathlib.Path(args.builds[0]).resolve(), args.path, args.frames, args.out)

    sys.path.insert(0, str(ROOT / "bench"))
    from bench_memory import write_tiled_las

    print("load average at the start: %s" % " ".join(open("/proc/loadavg").read().split()[:3]))
    print("| build | round | points | F12 | time | of which sync | peak RSS after the last |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory(prefix="bench_f12_sync_") as tmp:
        las = pathlib.Path(tmp) / "tiles.las"
        write_tiled_las(args.tiles, las)
        for r in range(args.rounds):
            for build in args.builds:
                out = pathlib.Path(tmp) / "result.json"
                cmd = ["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python", __file__,
                       "--", "--child", "--builds", str(pathlib.Path(build).resolve()), "--path", str(las),
                       "--frames", str(args.frames), "--out", str(out)]
                run = subprocess.run(cmd, capture_output=True, text=True)
                if not out.exists():
                    print("| %s | %d | failed (exit %d): %s |" % (build, r + 1, run.returncode,
                                                                 run.stderr.strip()[-300:]))
                    continue
                res = json.load(open(out))
                out.unlink()
                for i, (total, sync_s) in enumerate(res["frames"]):
                    last = i + 1 == len(res["frames"])
                    print("| %s | %d | %.1fM | %d | %.2f s | %.2f s | %s |" % (
                        build, r + 1, res["points"] / 1e6, i + 1, total, sync_s,
                        "%.2f GB" % (res["peak_rss"] / 1e9) if last else ""))
                sys.stdout.flush()
    print("load average at the end: %s" % " ".join(open("/proc/loadavg").read().split()[:3]))


if __name__ == "__main__":
    main()
