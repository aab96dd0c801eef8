"""PointNPR geometry against its peers, side by side in one run.

1. Normals: pointnpr.estimate_normals vs Open3D 0.16
   estimate_normals(KDTreeSearchParamKNN(k)) (python3-open3d) on noisy
   synthetic shapes with analytic normals (time, mean and 95th-percentile
   angular error, sign ignored; both use the k nearest points including the
   point itself, both leave the sign unoriented), over k; and time on real
   scans.
2. Connected components: pointnpr.connected_components vs the CloudCompare
   2.11 CLI (-EXTRACT_CC <level> <min_points>) on real aerial scans: number
   of components, identical partition (components compared as multisets of
   coordinates), and time.

    /usr/bin/python3 bench/bench_geometry.py [build_dir] [--quick] [--normals | --cc]

Timings are the minimum over repeats, taken alternately (ours, theirs) so
that load from other processes hits both alike.
"""
import glob
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
args = [a for a in sys.argv[1:] if not a.startswith("--")]
QUICK = "--quick" in sys.argv
sys.path.insert(0, os.path.abspath(args[0] if args else os.path.join(ROOT, "build")))

import open3d as o3d  # noqa: E402

import pointnpr  # noqa: E402
from synthetic_shapes import angles, shapes  # noqa: E402

REPEATS = 2 if QUICK else 5
NOISE_FLOOR = 0.05  # s: CloudCompare extraction times below this are process-start noise


def best_of(fn, repeats=REPEATS):
    best, out = float("inf"), None
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def alternate(fa, fb, repeats=REPEATS):
    ta = tb = float("inf")
    ra = rb = None
    for _ in range(repeats):
        t = time.perf_counter()
        ra = fa()
        ta = min(ta, time.perf_counter() - t)
        t = time.perf_counter()
        rb = fb()
        tb = min(tb, time.perf_counter() - t)
    return ta, ra, tb, rb




def o3d_normals(p, k):
    pc = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(p))
    pc.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(k))
    return np.asarray(pc.normals)


def bench_normals():
    print("## Normals: pointnpr vs Open3D %s (unoriented, k nearest incl. the point)\n" % o3d.__version__)
    rng = np.random.default_rng(0)
    n = 50000 if QUICK else 200000
    ks = (6, 10, 16, 24, 32) if not QUICK else (10, 16)
    print(f"Synthetic shapes, {n} points each, noise 0.05% of the size:\n")
    print("| shape | k | pointnpr s | Open3D s | speed-up | pointnpr mean / p95 deg | Open3D mean / p95 deg |")
    print("|---|---|---|---|---|---|---|")
    for name, (p, truth) in shapes(n, rng).items():
        for k in ks:
            ta, na, tb, nb = alternate(lambda: pointnpr.estimate_normals(p, k=k, consistent=False),
                                       lambda: o3d_normals(p, k))
            ea, eb = angles(na, truth), angles(nb, truth)
            print(f"| {name} | {k} | {ta:.3f} | {tb:.3f} | {tb / ta:.2f}x | "
                  f"{ea.mean():.3f} / {np.percentile(ea, 95):.3f} | {eb.mean():.3f} / {np.percentile(eb, 95):.3f} |")
    print("\nNearly planar: a 1 km plane, 1 um noise (the closed-form 3x3 solvers' weak case):\n")
    nrm = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    t1 = np.cross(nrm, [1.0, 0, 0]); t1 /= np.linalg.norm(t1)
    t2 = np.cross(nrm, t1)
    uv = rng.uniform(-500, 500, (n, 2))
    p = uv[:, :1] * t1 + uv[:, 1:] * t2 + rng.normal(scale=1e-6, size=(n, 1)) * nrm
    truth = np.tile(nrm, (n, 1))
    na, nb = pointnpr.estimate_normals(p, k=12, consistent=False), o3d_normals(p, 12)
    ea, eb = angles(na, truth), angles(nb, truth)
    print(f"| solver | max error deg | mean error deg |\n|---|---|---|\n"
          f"| pointnpr | {ea.max():.2e} | {ea.mean():.2e} |\n| Open3D | {eb.max():.2e} | {eb.mean():.2e} |")

    print("\nReal scans (time only), and pointnpr with consistent orientation (MST):\n")
    print("| scan | points | k | pointnpr s | Open3D s | speed-up | pointnpr + MST orientation s |")
    print("|---|---|---|---|---|---|---|")
    scans = [os.path.join(ROOT, "data", "lion_takanawa.ply"),
             os.path.join(ROOT, "data", "lidarhd_myria3d_870000_6618000_subset.las")]
    for path in scans:
        p = np.asarray(pointnpr.read(path).positions, np.float64)
        for k in ((10, 16, 30) if not QUICK else (16,)):
            ta, _, tb, _ = alternate(lambda: pointnpr.estimate_normals(p, k=k, consistent=False),
                                     lambda: o3d_normals(p, k))
            tc, _ = best_of(lambda: pointnpr.estimate_normals(p, k=k), repeats=2)
            print(f"| {os.path.basename(path)} | {len(p)} | {k} | {ta:.3f} | {tb:.3f} | {tb / ta:.2f}x | {tc:.3f} |")


def run_cc(args, cwd):
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    t = time.perf_counter()
    r = subprocess.run(["CloudCompare", "-SILENT", "-NO_TIMESTAMP", *args], cwd=cwd, env=env,
                       capture_output=True, text=True, timeout=600)
    wall = time.perf_counter() - t
    m = re.search(r"Processed finished in ([0-9.]+) s", r.stdout + r.stderr)
    return wall, float(m.group(1)) if m else float("nan"), r.stdout + r.stderr


def rows(a):
    return sorted(map(tuple, np.asarray(a)))


def bench_cc():
    print("\n## Connected components: pointnpr vs CloudCompare 2.11 CLI (-EXTRACT_CC)\n")
    files = [os.path.join(ROOT, "data", "lidarhd_myria3d_870000_6618000_subset.las")]
    files += sorted(glob.glob(os.path.join(ROOT, "tests", "data", "io", "*.las")))
    files += [os.path.join(ROOT, "data", "lion_takanawa.ply")]
    clouds = []
    for path in files:
        try:
            p = np.asarray(pointnpr.read(path).positions, np.float64)
        except pointnpr.Error:
            continue
        if len(p) >= 1000:
            clouds.append((os.path.basename(path), p))
    # A larger aerial scan: the LiDAR HD tile subset repeated 4 x 4 (1.1 M points).
    tile = clouds[0][1]
    ext = tile.max(axis=0) - tile.min(axis=0)
    big = np.vstack([tile + [i * ext[0], j * ext[1], 0.0] for i in range(4) for j in range(4)])
    clouds.append(("lidarhd subset tiled 4x4", big))
    levels = (6, 8, 10) if not QUICK else (8,)
    min_points = 10
    print("CloudCompare time: wall time of the process that loads and extracts minus that of the process "
          "that only loads (best of 5 each; its own internal timer has a 10 ms resolution). pointnpr: "
          "the call on the same coordinates (as CloudCompare read them from the .xyz file), best of "
          f"{REPEATS}.\n")
    print("| cloud | points | level | components CC / ours | identical partition (double / float32) | "
          "CC extract s | pointnpr s | speed-up |")
    print("|---|---|---|---|---|---|---|---|")
    for name, p in clouds:
        with tempfile.TemporaryDirectory() as tmp:
            shifted = p - np.floor(p.min(axis=0))  # CloudCompare works in float: no global shift
            np.savetxt(os.path.join(tmp, "cloud.xyz"), shifted, fmt="%.3f")
            q = np.loadtxt(os.path.join(tmp, "cloud.xyz"))
            for level in levels:
                for f in glob.glob(os.path.join(tmp, "cloud_COMPONENT_*")):
                    os.remove(f)
                # Components written for the comparison...
                run_cc(["-C_EXPORT_FMT", "ASC", "-PREC", "3", "-O", "cloud.xyz", "-EXTRACT_CC", str(level),
                        str(min_points)], tmp)
                cc_parts = [rows(np.loadtxt(f, ndmin=2)[:, :3].round(3))
                            for f in glob.glob(os.path.join(tmp, "cloud_COMPONENT_*.asc"))]
                # ...and timed without writing them.
                t_load = min(run_cc(["-AUTO_SAVE", "OFF", "-O", "cloud.xyz"], tmp)[0] for _ in range(5))
                t_all = min(run_cc(["-AUTO_SAVE", "OFF", "-O", "cloud.xyz", "-EXTRACT_CC", str(level),
                                    str(min_points)], tmp)[0] for _ in range(5))
                t_cc = max(t_all - t_load, 0.0)
                t_ours, labels = best_of(lambda: pointnpr.connected_components(q, level, min_points))
                ours = [rows(q[labels == l].round(3)) for l in range(labels.max() + 1)]
                same = sorted(cc_parts) == sorted(ours)
                f32 = pointnpr.connected_components(q, level, min_points, float32=True)
                same32 = sorted(cc_parts) == sorted(rows(q[f32 == l].round(3)) for l in range(f32.max() + 1))
                # Below 50 ms the difference of two process wall times is noise.
                ratio = f"{t_cc / t_ours:.0f}x" if t_cc >= NOISE_FLOOR else "(below the noise)"
                print(f"| {name} | {len(p)} | {level} | {len(cc_parts)} / {len(ours)} | "
                      f"{'yes' if same else 'NO'} / {'yes' if same32 else 'NO'} | {t_cc:.3f} | {t_ours:.4f} | "
                      f"{ratio} |")


if __name__ == "__main__":
    print(f"pointnpr from {os.path.dirname(pointnpr.__file__)}; {os.cpu_count()} CPUs; "
          f"load average {os.getloadavg()[0]:.1f}\n")
    if "--cc" not in sys.argv:
        bench_normals()
    if "--normals" not in sys.argv:
        bench_cc()
