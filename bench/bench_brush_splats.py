"""Brush splats (issue 12, seed 004) measured:

1. ms per 1920x1080 frame, blur and A-buffer blending against the points
   mark, on the lion scan (342k points) and on a 1.7M-point lion (five
   copies with a seeded sub-millimetre jitter: the size of the seed's
   three-Buddhas cloud, 1.63M), timed alternately after a warm-up frame
   (uploads, neighbours, shaders). Median and best of N frames.
2. Coverage against point fraction (100 %, 40 %, 10 % of the lion, seeded
   subsets): the share of the pixels the full cloud's points cover (480 x
   336, the golden camera) that points and brush splats of the subset
   cover; a bar chart to docs/images/brush_splats_coverage.png.

The native rows are brush_splats' own rasterizer on the CPU's threads
(`rasterizer` native: what auto picks on a software GL for blur and none);
the gl rows its GL passes (the A-buffer is GL's on every device). With
POINTNPR_BENCH_TILE_INVARIANT=1 a row of the GL passes that can tile
(every fragment from its frame pixel; the frame here is one tile).

The CPU column is the process's CPU time (all of llvmpipe's threads): on
a machine shared with other work it moves far less than the wall clock.

    PYTHONPATH=build /usr/bin/python3 bench/bench_brush_splats.py [frames] [--no-a-buffer] [--timing-only]
"""
import os
import sys
import time

import numpy as np

import pointnpr

ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
FRAMES = int(ARGS[0]) if ARGS else 5
EYE, TARGET = (2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)
ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))


def camera(w, h):
    return pointnpr.Camera.perspective(pointnpr.look_at(EYE, TARGET), lens=35.0, clip_start=0.1, clip_end=100.0,
                                       width=w, height=h)


def render(renderer, style, cloud, w, h, background=(1, 1, 1, 1)):
    scene = pointnpr.Scene()
    scene.add_segment("scan", style, [(cloud, np.eye(4))])
    return renderer.render(scene, camera(w, h), w, h, background=background, stage_timings=True)


STYLES = {"points": pointnpr.Style(mark=("points", {"point_size": 2.0})),
          "brush_splats (blur, native)": pointnpr.Style(mark=("brush_splats", {"blending": "blur",
                                                                              "rasterizer": "native"})),
          "brush_splats (none, native)": pointnpr.Style(mark=("brush_splats", {"blending": "none",
                                                                              "rasterizer": "native"})),
          "brush_splats (blur, gl)": pointnpr.Style(mark=("brush_splats", {"blending": "blur", "rasterizer": "gl"})),
          "brush_splats (a_buffer)": pointnpr.Style(mark=("brush_splats", {"blending": "a_buffer"}))}
if "--no-a-buffer" in sys.argv:  # (15 s a frame on llvmpipe)
    del STYLES["brush_splats (a_buffer)"]
# The frame-pixel GL passes: POINTNPR_BENCH_TILE_INVARIANT=1 (slow on llvmpipe).
if os.environ.get("POINTNPR_BENCH_TILE_INVARIANT"):
    STYLES["brush_splats (blur, gl, tile_invariant)"] = pointnpr.Style(
        mark=("brush_splats", {"blending": "blur", "rasterizer": "gl", "tile_invariant": True}))


def timing(data):
    pos = np.asarray(data.positions, float)
    colors = np.asarray(data.attributes["colors"])
    rng = np.random.default_rng(10)
    big = pointnpr.PointCloud(np.concatenate([pos + rng.normal(scale=0.0005, size=pos.shape) for _ in range(5)]),
                              colors=np.concatenate([colors] * 5))
    lion = data.to_cloud()
    renderer = pointnpr.Renderer()
    W, H = 1920, 1080
    print(f"{W}x{H}, {FRAMES} frames each, alternating; {pointnpr.gl_info()['renderer']}")
    print("| cloud | mark | frame ms (median) | frame ms (best) | mark ms (median) | CPU ms (median) | A-buffer "
          "fragments | vs. points (frame) | vs. points (CPU) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for cloud_name, cloud in (("lion (%dk)" % (lion.num_points // 1000), lion),
                              ("lion x5 (%.1fM)" % (big.num_points / 1e6), big)):
        warnings = {}
        for style in STYLES.values():
            render(renderer, style, cloud, W, H)  # warm-up
        times = {name: [] for name in STYLES}
        cpu = {name: [] for name in STYLES}
        mark_ms = {name: [] for name in STYLES}
        fragments = {}
        for _ in range(FRAMES):
            for name, style in STYLES.items():
                t0, c0 = time.perf_counter(), time.process_time()
                r = render(renderer, style, cloud, W, H)
                times[name].append(1000 * (time.perf_counter() - t0))
                cpu[name].append(1000 * (time.process_time() - c0))
                mark_ms[name].append(r.stats["mark_ms"])
                fragments[name] = int(r.stats.get("a_buffer_fragments", 0))
                if r.warnings:
                    warnings[name] = r.warnings[0]
        base, cpu_base = np.median(times["points"]), np.median(cpu["points"])
        for name in STYLES:
            t, c = np.median(times[name]), np.median(cpu[name])
            print(f"| {cloud_name} | {name} | {t:.0f} | {min(times[name]):.0f} | {np.median(mark_ms[name]):.0f} | "
                  f"{c:.0f} | {fragments[name] or '-'} | {t / base:.2f}x | {c / cpu_base:.2f}x |", flush=True)
        for name, w in warnings.items():
            print(f"  {cloud_name}, {name}: {w}")


def coverage(data):
    pos = np.asarray(data.positions, float)
    colors = np.asarray(data.attributes["colors"])
    renderer = pointnpr.Renderer()
    W, H = 480, 336
    full = None
    rows = []
    for fraction in (1.0, 0.4, 0.1):
        keep = np.sort(np.random.default_rng(0).choice(len(pos), int(round(fraction * len(pos))), replace=False))
        cloud = pointnpr.PointCloud(pos[keep], colors=colors[keep])
        covered = {name: np.asarray(render(renderer, STYLES[name], cloud, W, H, (0, 0, 0, 0)).color)[..., 3] > 0
                   for name in ("points", "brush_splats (blur, native)")}
        if full is None:
            full = covered["points"]
        rows.append((fraction, *[(covered[n] & full).sum() / full.sum() for n in covered],
                     *[covered[n].sum() / full.sum() for n in covered]))
    print("| points kept | points: share of the full cloud's pixels | brush splats: share | points: all covered / full | brush splats: all covered / full |")
    print("|---|---|---|---|---|")
    for f, p, b, pa, ba in rows:
        print(f"| {f:.0%} | {p:.1%} | {b:.1%} | {pa:.2f} | {ba:.2f} |")
    # Bar chart: per fraction, points (grey) and brush splats (orange), 0..100 %.
    img = np.ones((200, 300, 3), np.float32)
    for i, (f, p, b, _, _) in enumerate(rows):
        for j, (v, col) in enumerate(((p, (0.45, 0.45, 0.5)), (b, (0.9, 0.5, 0.15)))):
            x0 = 30 + i * 90 + j * 32
            img[200 - 20 - int(round(v * 160)):200 - 20, x0:x0 + 28] = col
    img[200 - 20 - 160, 20:290] = (0.2, 0.2, 0.2)   # 100 % line
    img[200 - 20 - 152, 20:290:4] = (0.6, 0.1, 0.1)  # 95 % (dotted)
    img[200 - 20, 20:290] = (0.0, 0.0, 0.0)          # 0 %
    out = os.path.join(ROOT, "docs", "images", "brush_splats_coverage.png")
    pointnpr.save_image(out, np.ascontiguousarray(img[::-1]), srgb=False)  # rows bottom-up, as the renderer's
    print("chart:", out)


def main():
    data = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply"))
    if "--timing-only" not in sys.argv:
        coverage(data)
    timing(data)


if __name__ == "__main__":
    main()
