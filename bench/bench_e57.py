#!/usr/bin/env python3
"""E57 decoding speed of pointnpr.read_e57_scans against pye57 (libE57Format)
on the same files, in one run.

Files: pye57's pump scan (tests/data/io/e57: 155,201 points, scaled-integer
coordinates, intensity, colour, row/column) and two files written at the
start of the run by libE57Format through pye57: a terrestrial-scanner-like
scan (--points points: cartesian coordinates as 0.1 mm scaled integers,
12-bit intensity, 8-bit colour, row/column indices, an invalid state) and
the same points as single-precision floats. Each file is read --repeat times
per reader after one warm-up (files from the page cache); the readers take
turns, so a change in the load of other processes falls on both alike.
pye57 reads every field of every point (E57.read_scan with intensity,
colours and row/column, which also drops invalid points and applies the
pose); pointnpr does the same and checks every page's CRC-32C (pye57's
libE57 checks them too, checksum policy "all"). Reported: the median wall
time as MB/s of file bytes and million points/s.

    POINTNPR_BUILD_DIR=build .venv-test/bin/python bench/bench_e57.py [--repeat 5] [--points 2000000]
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
sys.path.insert(0, str(ROOT / "tests" / "python"))

import pye57  # noqa: E402
import pointnpr  # noqa: E402
from test_io_e57 import integer, scaled, single, write_e57  # noqa: E402


def make_scan(path, n, coordinates):
    rng = np.random.default_rng(0)
    rows, cols = np.divmod(np.arange(n), 5000)
    xyz = rng.uniform(-50, 50, (n, 3))
    if coordinates == "scaled":
        make = [scaled(-600000, 600000, 1e-4)] * 3
        xyz = np.rint(xyz * 1e4) * 1e-4
    else:
        make = [single(-50, 50)] * 3
    fields = [("cartesian" + a, make[i], xyz[:, i]) for i, a in enumerate("XYZ")]
    fields += [("intensity", integer(0, 4095), rng.integers(0, 4096, n)),
               ("colorRed", integer(0, 255), rng.integers(0, 256, n)),
               ("colorGreen", integer(0, 255), rng.integers(0, 256, n)),
               ("colorBlue", integer(0, 255), rng.integers(0, 256, n)),
               ("rowIndex", integer(0, int(rows.max())), rows),
               ("columnIndex", integer(0, 4999), cols),
               ("cartesianInvalidState", integer(0, 2), (rng.random(n) < 0.02) * 2)]
    write_e57(path, [{"name": "bench", "rotation": (0.9238795, 0, 0, 0.3826834), "translation": (1000, 2000, 30),
                      "intensity_limits": (0, 4095), "color_limits": (0, 255), "fields": fields}])


def read_pointnpr(path):
    return sum(s.num_points for s in pointnpr.read_e57_scans(str(path)))


def read_pye57(path):
    e = pye57.E57(str(path))
    n = 0
    for i in range(e.scan_count):
        n += len(e.read_scan(i, intensity=True, colors=True, row_column=True, ignore_missing_fields=True)["cartesianX"])
    e.close()
    return n


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--points", type=int, default=2000000)
    args = parser.parse_args()
    print("load average before: %.2f %.2f %.2f" % os.getloadavg())
    with tempfile.TemporaryDirectory() as tmp:
        files = [ROOT / "tests" / "data" / "io" / "e57" / "pye57_pumpAVisualReferenceImage.e57"]
        for kind in ("scaled", "single"):
            files.append(pathlib.Path(tmp) / ("scan_%s_%d.e57" % (kind, args.points)))
            make_scan(files[-1], args.points, kind)
        readers = [("pointnpr", read_pointnpr), ("pye57", read_pye57)]
        print("| file | MB | points | pointnpr ms | MB/s | pye57 ms | MB/s | speed-up |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        for path in files:
            counts = {name: read(path) for name, read in readers}  # warm-up
            assert counts["pointnpr"] == counts["pye57"], counts
            times = {name: [] for name, _ in readers}
            for r in range(args.repeat):
                for name, read in readers[r % 2:] + readers[:r % 2]:
                    t0 = time.perf_counter()
                    read(path)
                    times[name].append(time.perf_counter() - t0)
            mb = path.stat().st_size / 1e6
            ms = {name: statistics.median(t) * 1e3 for name, t in times.items()}
            print("| %s | %.2f | %d | %.1f | %.0f | %.1f | %.0f | %.1fx |" % (
                path.name, mb, counts["pointnpr"], ms["pointnpr"], mb / ms["pointnpr"] * 1e3,
                ms["pye57"], mb / ms["pye57"] * 1e3, ms["pye57"] / ms["pointnpr"]))
    print("load average after: %.2f %.2f %.2f" % os.getloadavg())


if __name__ == "__main__":
    main()
