"""The stroke marks in tiles (issue 17): time per pixel of a frame drawn
whole against the same frame in tiles (a small memory budget), side by
side, interleaved, best of N, and whether the bytes are the same. The
LiDAR HD tile of data/ split into 4 x 4 clouds (so tiles draw only the
chunks near them), one preset per stroke mark plus the points mark as the
reference of what tiles cost anyway.

    PYTHONPATH=build /usr/bin/python3 bench/bench_stroke_tiles.py [frames] [WIDTH HEIGHT] [BUDGET_GB]
"""
import sys
import time

import numpy as np

import pointnpr
from pointnpr import presets

args = [a for a in sys.argv[1:]]
FRAMES = int(args[0]) if args else 3
W, H = (int(args[1]), int(args[2])) if len(args) > 2 else (1920, 1080)
BUDGET = float(args[3]) if len(args) > 3 else 0.25

tile = pointnpr.read("data/lidarhd_myria3d_870000_6618000_subset.las")
pos = np.asarray(tile.positions)
pos = pos - (pos.min(0) + pos.max(0)) / 2
colors = np.asarray(tile.attributes["colors"])
lo, hi = pos.min(0), pos.max(0)
cell = np.minimum(((pos[:, :2] - lo[:2]) / (hi[:2] - lo[:2]) * 4).astype(int), 3)
clouds = [pointnpr.PointCloud(pos[m], colors=colors[m])
          for m in ((cell[:, 0] == i) & (cell[:, 1] == j) for i in range(4) for j in range(4))]
camera = pointnpr.Camera.perspective(pointnpr.look_at((0.0, -70.0, 60.0), (0.0, 0.0, 0.0)), lens=35.0,
                                     clip_start=0.5, clip_end=1000.0, width=W, height=H)
renderer = pointnpr.Renderer()
print(f"{W}x{H}, budget {BUDGET} GB, best of {FRAMES}")
print("| style | mark | whole ms | tiled ms | tiles | tiled / whole | same bytes |")
print("|---|---|---|---|---|---|---|")
for name in ["Toon", "Pencil", "Feature strokes + stipples"]:
    scene = pointnpr.Scene()
    scene.add_segment("scan", presets.style(name), clouds)
    renderer.render(scene, camera, W, H)  # uploads, normals, shaders
    best = {"whole": 1e30, "tiled": 1e30}
    for _ in range(FRAMES):
        for kind in ("whole", "tiled"):
            t0 = time.perf_counter()
            result = (renderer.render(scene, camera, W, H, memory_budget_gb=64.0) if kind == "whole" else
                      renderer.render(scene, camera, W, H, memory_budget_gb=BUDGET))
            best[kind] = min(best[kind], (time.perf_counter() - t0) * 1e3)
            if kind == "whole":
                whole = result
            else:
                tiled = result
    same = all(np.asarray(getattr(whole, k)).tobytes() == np.asarray(getattr(tiled, k)).tobytes()
               for k in ("color", "depth", "segment_index"))
    print(f"| {name} | {presets.PRESETS[name]['mark'][0]} | {best['whole']:.0f} | {best['tiled']:.0f} | "
          f"{int(tiled.stats['tiles'])} of {int(tiled.stats['tile_region_width'])}x"
          f"{int(tiled.stats['tile_region_height'])} | {best['tiled'] / best['whole']:.2f}x | {same} |")
