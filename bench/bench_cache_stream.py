#!/usr/bin/env python3
"""Scan caches written straight from a LAS file (pointnpr.write_scan_caches,
docs/io.md#scan-cache) against the in-memory way (read the file whole, a
PointCloud of float32 offsets, write_scan_cache), side by side in one run,
then frames rendered from the streamed cache with the default point budget.

A synthetic aerial tile (bench_cache.make_scan's terrain, in blocks) is
written as LAS 1.2 point format 2 (RGB, 1 mm grid); each step runs in its own
process for its own peak RSS. Files are removed at the end.

    POINTNPR_BUILD_DIR=build /usr/bin/python3 bench/bench_cache_stream.py --points 30000000 [--folder /work/tmp]
    ... --points 300000000 --no-reference   (the in-memory way does not fit then)
"""
import argparse
import json
import os
import pathlib
import shutil
import struct
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import bench_cache  # noqa: E402  (the scan, views, frames and RSS of the cache benchmark)

BLOCK = 5_000_000


def write_las(path, n):
    """LAS 1.2, point format 2, written block by block (bounded memory)."""
    import numpy as np

    record = np.dtype([("xyz", "<i4", 3), ("intensity", "<u2"), ("bits", "u1"), ("cls", "u1"), ("angle", "i1"),
                       ("user", "u1"), ("source", "<u2"), ("rgb", "<u2", 3)])
    assert record.itemsize == 26
    scale, offset = 0.001, (650000.0, 6800000.0, 0.0)
    header = bytearray(227)
    header[0:4] = b"LASF"
    header[24], header[25] = 1, 2
    struct.pack_into("<HIIBHI", header, 94, 227, 227, 0, 2, 26, n if n < 2**32 else 0)
    struct.pack_into("<3d3d", header, 131, scale, scale, scale, *offset)
    struct.pack_into("<6d", header, 179, offset[0] + 1000, offset[0], offset[1] + 1000, offset[1], 40.0, -40.0)
    with open(path, "wb") as f:
        f.write(header)
        for first in range(0, n, BLOCK):
            m = min(BLOCK, n - first)
            pos, colors = bench_cache.make_scan(m, seed=first // BLOCK)
            rec = np.zeros(m, record)
            rec["xyz"] = np.rint(pos / scale)
            rec["intensity"] = (pos[:, 2] * 1000).astype(np.int64) & 0xFFFF
            rec["cls"] = np.where(pos[:, 2] > 5.0, 5, 2)
            rec["rgb"] = colors.astype(np.uint16) * 257
            f.write(rec.tobytes())


def child_stream(args):
    import pointnpr

    t0 = time.perf_counter()
    written = pointnpr.write_scan_caches(args.las, lambda c: args.path)
    return {"s": time.perf_counter() - t0, "file_mb": os.path.getsize(args.path) / 2**20,
            "runs": written[0]["runs"], "peak_rss_mb": bench_cache.peak_rss_mb()}


def child_whole(args):
    import numpy as np
    import pointnpr

    t0 = time.perf_counter()
    data = pointnpr.read(args.las)
    attrs = dict(data.attributes)
    positions = np.asarray(data.positions)
    origin = np.round((positions.min(axis=0) + positions.max(axis=0)) * 0.5)
    local = (positions - origin).astype(np.float32)
    del positions
    cloud = pointnpr.PointCloud(local, colors=attrs["colors"], intensity=attrs["intensity"],
                                classification=attrs["classification"])
    del data, attrs, local
    pointnpr.write_scan_cache(args.path + ".whole", cloud)
    same = open(args.path + ".whole", "rb").read() == open(args.path, "rb").read() \
        if os.path.getsize(args.path) < 2**31 else None
    os.remove(args.path + ".whole")
    return {"s": time.perf_counter() - t0, "same_bytes": same, "peak_rss_mb": bench_cache.peak_rss_mb()}


def child_render(args):
    import pointnpr

    cached = pointnpr.CachedCloud(args.path)
    times, drawn = bench_cache.render_frames(cached, args.frames)
    return {"budget": cached.point_budget, "frame_ms": times, "points_drawn": drawn,
            "peak_rss_mb": bench_cache.peak_rss_mb()}


def run_child(step, args):
    cmd = [sys.executable, __file__, "--child", step, "--points", str(args.points), "--frames", str(args.frames),
           "--path", args.path, "--las", args.las]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", type=int, default=30_000_000)
    ap.add_argument("--frames", type=int, default=3)
    ap.add_argument("--folder", default=None)
    ap.add_argument("--no-reference", action="store_true", help="skip the in-memory way")
    ap.add_argument("--child", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--path", default=None, help=argparse.SUPPRESS)
    ap.add_argument("--las", default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        steps = {"stream": child_stream, "whole": child_whole, "render": child_render}
        print(json.dumps(steps[args.child](args)))
        return
    folder = tempfile.mkdtemp(prefix="pointnpr-bench-stream-", dir=args.folder)
    args.las, args.path = os.path.join(folder, "scan.las"), os.path.join(folder, "scan.pnprcache")
    try:
        need = args.points * (26 + 25 + 29) / 2**30
        free = shutil.disk_usage(folder).free / 2**30
        if free < 1.2 * need:
            sys.exit("need about %.1f GB free, %.1f GB there" % (need, free))
        t0 = time.perf_counter()
        write_las(args.las, args.points)
        las_s = time.perf_counter() - t0
        stream = run_child("stream", args)
        whole = None if args.no_reference else run_child("whole", args)
        render = run_child("render", args)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    print("%s points, LAS %.0f MB written in %.0f s" % (format(args.points, ","), args.points * 26 / 2**20, las_s))
    print("| step | s | peak RSS | bytes per point |")
    print("|---|---|---|---|")
    print("| cache written from the file (write_scan_caches, %d runs, %.0f MB) | %.1f | %.0f MB | %.1f |" % (
        stream["runs"], stream["file_mb"], stream["s"], stream["peak_rss_mb"],
        stream["peak_rss_mb"] * 2**20 / args.points))
    if whole:
        print("| read whole, PointCloud, write_scan_cache (same bytes: %s) | %.1f | %.0f MB | %.1f |" % (
            whole["same_bytes"], whole["s"], whole["peak_rss_mb"], whole["peak_rss_mb"] * 2**20 / args.points))
    rest = render["frame_ms"][1:] or render["frame_ms"]
    print("render, 1920x1080, budget %s: %s points a frame, %.0f ms first frame, %.0f ms mean of the rest, "
          "peak RSS %.0f MB" % (format(render["budget"], ","), format(int(sum(render["points_drawn"]) /
                                len(render["points_drawn"])), ","), render["frame_ms"][0],
                                sum(rest) / len(rest), render["peak_rss_mb"]))


if __name__ == "__main__":
    main()
