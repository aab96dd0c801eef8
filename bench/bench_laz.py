#!/usr/bin/env python3
"""LAZ decoding speed of pointnpr.read against laspy + lazrs, single-threaded
(LazBackend.Lazrs) and parallel (LazBackend.LazrsParallel), in one run.

Files: the largest LAZ test files (tests/data/io/laz), plus two larger files
made at the start of the run with lazrs itself from autzen_trim (110,000
points, tiled --tiles times with shifted coordinates): one point format 3
(point-wise chunked, the items of LAS 1.2-1.3 files) and one point format 7
(layered chunked, LAS 1.4). Each file is read --repeat times per reader after
one warm-up read (files come from the page cache). The readers take turns
(each round reads the file once with every reader, the order rotating from
round to round), so a change in the load of other processes on a shared
machine falls on all of them alike. Reported: the median wall time as MB/s
(compressed file bytes) and million points/s, and the median CPU time of the
process (all threads) per point, which depends much less on that load; the
load average is printed before and after. pointnpr.read returns columns
(positions as float64 etc.), laspy its packed record array: both decode
every field of every point.

    POINTNPR_BUILD_DIR=build .venv-test/bin/python bench/bench_laz.py [--repeat 7] [--tiles 20]
"""
import argparse
import os
import pathlib
import statistics
import sys
import tempfile
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, os.path.abspath(os.environ.get("POINTNPR_BUILD_DIR", ROOT / "build")))

import laspy  # noqa: E402
import pointnpr  # noqa: E402

LAZ = ROOT / "tests" / "data" / "io" / "laz"


def make_tiled(path, tiles, point_format):
    src = laspy.read(str(LAZ / "laspy_autzen_trim.laz"))
    pts = src.points
    if point_format != src.header.point_format.id:
        pts = laspy.convert(src, point_format_id=point_format).points
    n = len(pts)
    span = int(src.X.max() - src.X.min()) + 1
    header = laspy.LasHeader(point_format=point_format, version="1.4" if point_format >= 6 else "1.2")
    header.scales, header.offsets = src.header.scales, src.header.offsets
    out = laspy.ScaleAwarePointRecord.zeros(n * tiles, header=header)
    for t in range(tiles):
        sl = slice(t * n, (t + 1) * n)
        for dim in pts.array.dtype.names:
            out.array[dim][sl] = pts.array[dim]
        out.array["X"][sl] = pts.array["X"] + t * span
        if point_format >= 6:
            out.array["gps_time"][sl] = pts.array["gps_time"] + t * 1000.0
    las = laspy.LasData(header=header, points=out)
    las.write(str(path), laz_backend=laspy.LazBackend.Lazrs)


def interleaved_times(readers, path, repeat):
    """Median wall and process CPU seconds of each reader, the readers taking
    turns within each round (after one warm-up read each)."""
    for read in readers.values():
        read(path)
    names = list(readers)
    wall = {name: [] for name in names}
    cpu = {name: [] for name in names}
    for r in range(repeat):
        for name in names[r % len(names):] + names[:r % len(names)]:
            w0, c0 = time.perf_counter(), time.process_time()
            readers[name](path)
            cpu[name].append(time.process_time() - c0)
            wall[name].append(time.perf_counter() - w0)
    return {name: (statistics.median(wall[name]), statistics.median(cpu[name])) for name in names}


def load():
    return "load average %.2f %.2f %.2f" % os.getloadavg()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--tiles", type=int, default=20)
    args = ap.parse_args()
    readers = {
        "pointnpr": lambda f: pointnpr.read(f),
        "laspy+lazrs (1 thread)": lambda f: laspy.read(f, laz_backend=laspy.LazBackend.Lazrs),
        "laspy+lazrs (parallel)": lambda f: laspy.read(f, laz_backend=laspy.LazBackend.LazrsParallel),
    }
    with tempfile.TemporaryDirectory() as tmp:
        files = [LAZ / "pdal_lone-star-split-1.laz", LAZ / "laspy_autzen_trim.laz"]
        for pf in (3, 7):
            f = pathlib.Path(tmp) / ("autzen_x%d_pf%d.laz" % (args.tiles, pf))
            make_tiled(f, args.tiles, pf)
            files.append(f)
        print("cores: %d, repeat: %d (median), %s, %s" % (os.cpu_count(), args.repeat, time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), load()))
        print("| file | points | MB | " + " | ".join("%s MB/s, Mpts/s, CPU ns/point" % r for r in readers) + " |")
        print("|---|---|---|" + "---|" * len(readers))
        for f in files:
            path = str(f)
            n = pointnpr.read(path).num_points
            assert n == len(laspy.read(path).points)
            mb = f.stat().st_size / 1e6
            times = interleaved_times(readers, path, args.repeat)
            cells = ["%.1f, %.2f, %.0f" % (mb / w, n / w / 1e6, c / n * 1e9) for w, c in times.values()]
            print("| %s | %d | %.2f | %s |" % (f.name, n, mb, " | ".join(cells)), flush=True)
        print(load())


if __name__ == "__main__":
    main()
