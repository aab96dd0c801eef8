#!/usr/bin/env python3
"""Read speed of pointnpr.read against Open3D 0.16 (open3d.io.read_point_cloud).

Reads, in one run: the largest .ply and the largest .pcd found under the given
paths (default: ../shared/data/scans relative to the repository), each also
re-saved in the other encodings Open3D reads (PCD binary and ascii written by
Open3D, PLY binary written by pointnpr), with both libraries; and every .las
file with pointnpr only (Open3D has no LAS reader). Each file is read
--repeat times after one warm-up read (files come from the page cache); the
median is reported as MB/s (file bytes) and points/s.

    POINTNPR_BUILD_DIR=build /usr/bin/python3 bench/bench_io.py [paths...] [--repeat 9]
"""
import argparse
import os
import pathlib
import statistics
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, os.path.abspath(os.environ.get("POINTNPR_BUILD_DIR", ROOT / "build")))

import pointnpr  # noqa: E402

try:
    import open3d as o3d  # noqa: E402
except ImportError:  # pragma: no cover - the comparison needs it
    o3d = None


def files_under(paths):
    out = []
    for p in map(pathlib.Path, paths):
        if p.is_dir():
            out += [f for f in p.rglob("*") if f.is_file()]
        elif p.is_file():
            out.append(p)
    return out


def encoding_of(path):
    with open(path, "rb") as f:
        head = f.read(4096)
    for line in head.split(b"\n"):
        if line.startswith(b"format ") or line.startswith(b"DATA "):
            return line.split()[1].decode()
    return "las" if head[:4] == b"LASF" else "?"


def median_time(fn, repeat):
    fn()  # warm-up: page cache, lazy initialisation
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("paths", nargs="*", default=[str(ROOT / ".." / "shared" / "data" / "scans")])
    ap.add_argument("--repeat", type=int, default=9)
    ap.add_argument("--no-variants", action="store_true",
                    help="only the files found, not their re-saved encodings")
    args = ap.parse_args()

    files = files_under(args.paths)
    if not files:
        sys.exit(f"no files under {args.paths}")
    largest = {}
    for ext in (".ply", ".pcd"):
        cands = [f for f in files if f.suffix.lower() == ext]
        if cands:
            largest[ext] = max(cands, key=lambda f: f.stat().st_size)
    las = sorted((f for f in files if f.suffix.lower() == ".las"), key=lambda f: -f.stat().st_size)

    tmp = tempfile.TemporaryDirectory(prefix="bench_io_")
    compared = list(largest.values())
    if not args.no_variants and o3d is not None:
        if ".pcd" in largest:
            pc = o3d.io.read_point_cloud(str(largest[".pcd"]))
            for ascii_, name in ((False, "binary"), (True, "ascii")):
                out = pathlib.Path(tmp.name) / f"{largest['.pcd'].stem}_{name}.pcd"
                o3d.io.write_point_cloud(str(out), pc, write_ascii=ascii_, compressed=False)
                compared.append(out)
        if ".ply" in largest:
            out = pathlib.Path(tmp.name) / f"{largest['.ply'].stem}_pointnpr.ply"
            pointnpr.write(out, pointnpr.read(largest[".ply"]))
            compared.append(out)

    print(f"pointnpr read vs Open3D {o3d.__version__ if o3d else '(not installed)'}; "
          f"median of {args.repeat} reads after a warm-up; {os.cpu_count()} CPUs")
    print()
    print("| file | encoding | MB | points | pointnpr ms | MB/s | Mpoints/s | Open3D ms | MB/s | "
          "Mpoints/s | speed-up |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for f in compared + las:
        mb = f.stat().st_size / 1e6
        n = pointnpr.read(f).num_points
        t = median_time(lambda: pointnpr.read(f), args.repeat)
        row = (f"| {f.name} | {encoding_of(f)} | {mb:.2f} | {n} | {t * 1e3:.1f} | {mb / t:.0f} | "
               f"{n / t / 1e6:.1f} |")
        if f.suffix.lower() in (".ply", ".pcd") and o3d is not None:
            n3 = len(o3d.io.read_point_cloud(str(f)).points)
            t3 = median_time(lambda: o3d.io.read_point_cloud(str(f)), args.repeat)
            note = "" if n3 == n else f" ({n3} pts)"
            row += f" {t3 * 1e3:.1f}{note} | {mb / t3:.0f} | {n3 / t3 / 1e6:.1f} | {t3 / t:.1f}x |"
        else:
            row += " - | - | - | - |"
        print(row, flush=True)
    tmp.cleanup()


if __name__ == "__main__":
    main()
