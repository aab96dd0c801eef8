#!/usr/bin/env python3
"""Out-of-core scans (docs/io.md#scan-cache): write a large synthetic scan's
cache, then render it with the default point budget, against the same scan
rendered from memory, side by side in one run.

Each step runs in its own process, so that its peak RSS (ru_maxrss) is its
own: (1) build the scan and write its cache; (2) open the cache and render
--frames frames at 1920x1080 from views that move over the scan (each frame
streams new prefixes), reporting ms per frame and peak RSS; (3) the
reference: the same scan as an in-memory PointCloud, rendered from the same
views. The cache file is removed at the end.

    POINTNPR_BUILD_DIR=build /usr/bin/python3 bench/bench_cache.py --points 30000000 [--folder /work/tmp]
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
sys.path.insert(0, os.path.abspath(os.environ.get("POINTNPR_BUILD_DIR", ROOT / "build")))

W, H = 1920, 1080


def make_scan(n, seed=14):
    """An aerial-like tile: 1 km x 1 km of terrain with relief, coloured by height."""
    import numpy as np

    rng = np.random.default_rng(seed)
    pos = np.empty((n, 3))
    pos[:, 0] = rng.uniform(0.0, 1000.0, n)
    pos[:, 1] = rng.uniform(0.0, 1000.0, n)
    pos[:, 2] = 20.0 * np.sin(pos[:, 0] / 60.0) * np.cos(pos[:, 1] / 80.0) + rng.normal(0.0, 0.3, n)
    level = np.clip((pos[:, 2] + 20.0) / 40.0 * 255.0, 0, 255).astype(np.uint8)
    colors = np.stack([level, 255 - level, np.full(n, 120, np.uint8)], axis=1)
    return pos, colors


def views(frames):
    """Cameras flying over the tile at 150 m, looking down and ahead."""
    import numpy as np
    import pointnpr

    cams = []
    for k in range(frames):
        m = np.eye(4)
        tilt = np.radians(50.0)
        m[:3, :3] = [[1, 0, 0], [0, np.cos(tilt), -np.sin(tilt)], [0, np.sin(tilt), np.cos(tilt)]]
        m[:3, 3] = [200.0 + 600.0 * k / max(frames - 1, 1), 100.0, 150.0]
        cams.append(pointnpr.Camera.perspective(m, lens=24.0, clip_end=5000.0, width=W, height=H))
    return cams


def peak_rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def child_write(args):
    import pointnpr

    t0 = time.perf_counter()
    pos, colors = make_scan(args.points)
    cloud = pointnpr.PointCloud(pos, colors=colors)
    del pos, colors
    t1 = time.perf_counter()
    pointnpr.write_scan_cache(args.path, cloud)
    t2 = time.perf_counter()
    return {"build_s": t1 - t0, "write_s": t2 - t1, "file_mb": os.path.getsize(args.path) / 2**20,
            "peak_rss_mb": peak_rss_mb()}


def render_frames(instance, frames):
    import pointnpr

    renderer = pointnpr.Renderer()
    style = pointnpr.Style(rasterize={"point_size": 2})
    times, drawn = [], []
    for cam in views(frames):
        scene = pointnpr.Scene()
        scene.add_segment("scan", style, [instance])
        t0 = time.perf_counter()
        result = renderer.render(scene, cam, W, H)
        times.append((time.perf_counter() - t0) * 1000.0)
        drawn.append(result.stats.get("points_drawn", 0.0))
    return times, drawn


def child_cached(args):
    import pointnpr

    t0 = time.perf_counter()
    cached = pointnpr.CachedCloud(args.path)
    open_ms = (time.perf_counter() - t0) * 1000.0
    times, drawn = render_frames(cached, args.frames)
    return {"open_ms": open_ms, "budget": cached.point_budget, "frame_ms": times, "points_drawn": drawn,
            "stream_mb": cached.stream_bytes / 2**20, "peak_rss_mb": peak_rss_mb()}


def child_memory(args):
    import pointnpr

    pos, colors = make_scan(args.points)
    cloud = pointnpr.PointCloud(pos, colors=colors)
    del pos, colors
    times, drawn = render_frames(cloud, args.frames)
    return {"frame_ms": times, "points_drawn": drawn, "peak_rss_mb": peak_rss_mb()}


def run_child(step, args):
    cmd = [sys.executable, __file__, "--child", step, "--points", str(args.points), "--frames", str(args.frames),
           "--path", args.path]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", type=int, default=30_000_000)
    ap.add_argument("--frames", type=int, default=4)
    ap.add_argument("--folder", default=None, help="where the cache is written (default: a temporary folder)")
    ap.add_argument("--no-reference", action="store_true", help="skip the in-memory reference")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--path", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        print(json.dumps({"write": child_write, "cached": child_cached, "memory": child_memory}[args.child](args)))
        return
    folder = tempfile.mkdtemp(prefix="pointnpr-bench-cache-", dir=args.folder)
    args.path = os.path.join(folder, "scan.pnprcache")
    try:
        need = args.points * 37 / 2**30
        free = shutil.disk_usage(folder).free / 2**30
        if free < 2 * need:
            sys.exit("need about %.1f GB free for the cache, %.1f GB there" % (need, free))
        written = run_child("write", args)
        cached = run_child("cached", args)
        memory = None if args.no_reference else run_child("memory", args)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    mean = lambda v: sum(v) / len(v)  # noqa: E731
    print("%s points, %dx%d, %d frames from moving views, points mark 2 px (compute)" % (
        format(args.points, ","), W, H, args.frames))
    print("write: build %.1f s, write %.1f s, cache %.0f MB, peak RSS %.0f MB" % (
        written["build_s"], written["write_s"], written["file_mb"], written["peak_rss_mb"]))
    print("| run | points drawn per frame | ms per frame (first / mean of the rest) | peak RSS |")
    print("|---|---|---|---|")
    rest = lambda v: mean(v[1:]) if len(v) > 1 else v[0]  # noqa: E731
    print("| cached, budget %s (open %.0f ms, stream pool %.0f MB) | %s | %.0f / %.0f | %.0f MB |" % (
        format(cached["budget"], ","), cached["open_ms"], cached["stream_mb"],
        format(int(mean(cached["points_drawn"])), ","), cached["frame_ms"][0], rest(cached["frame_ms"]),
        cached["peak_rss_mb"]))
    if memory:
        print("| in memory, every point | %s | %.0f / %.0f | %.0f MB |" % (
            format(int(mean(memory["points_drawn"])), ","), memory["frame_ms"][0], rest(memory["frame_ms"]),
            memory["peak_rss_mb"]))


if __name__ == "__main__":
    main()
