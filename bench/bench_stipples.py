"""The stipples mark against the points mark, both implementations of its
passes (gl, auto = native on software GL), side by side in one run:
1920x1080, 3 frames each after a warm-up, alternating; medians of the frame,
the mark stage and the process CPU time.

    PYTHONPATH=build /usr/bin/python3 bench/bench_stipples.py --aerial
"""
import sys, time
sys.path.insert(0, __import__("os").path.dirname(__file__))
import numpy as np, pointnpr, bench_marks as bm
styles = {"points": pointnpr.Style(mark=("points", {"point_size": 2.0})),
          "stipples (gl)": pointnpr.Style(mark=("stipples", {"specular": True, "level_scale": "point_count", "level": 8.0, "rasterizer": "gl"})),
          "stipples (auto: native)": pointnpr.Style(mark=("stipples", {"specular": True, "level_scale": "point_count", "level": 8.0})),
          # The defaults since 2026-12-05: the tone and each point's level from its spacing.
          "stipples (defaults, native)": pointnpr.Style(mark=("stipples", {}))}
r = pointnpr.Renderer()
for cname, cloud, cam in bm.clouds():
    scenes = {}
    for n, st in styles.items():
        sc = pointnpr.Scene(); sc.add_segment("scan", st, [(cloud, np.eye(4))]); scenes[n] = sc; r.render(sc, cam, bm.W, bm.H)
    t = {n: [] for n in styles}; m = {n: [] for n in styles}; c = {n: [] for n in styles}
    for _ in range(3):
        for n, sc in scenes.items():
            c0 = time.process_time(); t0 = time.perf_counter(); res = r.render(sc, cam, bm.W, bm.H, stage_timings=True)
            t[n].append(1000*(time.perf_counter()-t0)); c[n].append(1000*(time.process_time()-c0)); m[n].append(res.stats["mark_ms"])
    base = np.median(t["points"])
    for n in styles:
        print(f"| {cname} | {n} | {np.median(t[n]):.0f} | {np.median(m[n]):.0f} | {np.median(c[n]):.0f} | {np.median(t[n])/base:.2f}x |", flush=True)
