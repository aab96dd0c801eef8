"""Cost of a frame per mark (issue 10): the hatching mark against the
points mark on the same cloud and view, 1920x1080, timed alternately in one
run (median and best of N frames after a warm-up frame that uploads,
estimates normals and compiles shaders).

    PYTHONPATH=build /usr/bin/python3 bench/bench_marks.py [frames] [--aerial]

Clouds: the lion scan (342k points) and a 3.4M-point lion (ten copies,
each moved by a seeded sub-millimetre jitter: the paper's smallest case is
3.5M points); with --aerial also a 3M-point aerial scene (the LiDAR HD
tile on a 6 x 7 grid). Reports the whole render call and the mark stage alone
(`mark_ms`), and the ratio hatching / points (goal: at most 3x), hatching by
its default backend (auto: native on llvmpipe) and by its GL passes. The
brush_splats rows (issue 12) blend by blur and by the A-buffer (its
strokes column: the A-buffer's fragments; goal for blur: at most 3x).
"""
import sys
import time

import numpy as np

import pointnpr

W, H = 1920, 1080
FRAMES = next((int(a) for a in sys.argv[1:] if a.isdigit()), 7)
EYE, TARGET = (2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)


def clouds():
    """(name, cloud, camera) per test cloud."""
    def camera(eye, target, clip):
        return pointnpr.Camera.perspective(pointnpr.look_at(eye, target), lens=35.0, clip_start=clip[0],
                                           clip_end=clip[1], width=W, height=H)
    data = pointnpr.read("data/lion_takanawa.ply")
    lion = data.to_cloud()
    pos = np.asarray(data.positions, float)
    colors = np.asarray(data.attributes["colors"]) if "colors" in data.attributes else None
    rng = np.random.default_rng(10)
    copies = [pos + rng.normal(scale=0.0005, size=pos.shape) for _ in range(10)]
    big = pointnpr.PointCloud(np.concatenate(copies),
                              colors=None if colors is None else np.concatenate([colors] * 10))
    lion_camera = camera(EYE, TARGET, (0.1, 100.0))
    out = [("lion (%dk)" % (lion.num_points // 1000), lion, lion_camera),
           ("lion x10 (%.1fM)" % (big.num_points / 1e6), big, lion_camera)]
    if "--aerial" in sys.argv:
        # A 3M-point aerial scene: the LiDAR HD tile repeated on a 6 x 7
        # grid (each copy mirrored in turn, so edges meet), seen obliquely.
        tile = pointnpr.read("data/lidarhd_myria3d_870000_6618000_subset.las")
        t = np.asarray(tile.positions, float)
        t = t - t.min(0)
        size = t.max(0)
        parts, cols = [], []
        for i in range(6):
            for j in range(7):
                q = t.copy()
                if i % 2:
                    q[:, 0] = size[0] - q[:, 0]
                if j % 2:
                    q[:, 1] = size[1] - q[:, 1]
                parts.append(q + [i * size[0], j * size[1], 0.0])
                cols.append(np.asarray(tile.attributes["colors"]))
        aerial = np.concatenate(parts)
        aerial -= (aerial.min(0) + aerial.max(0)) / 2
        cloud = pointnpr.PointCloud(aerial, colors=np.concatenate(cols))
        extent = np.ptp(aerial, axis=0)
        out.append(("aerial tile x42 (%.1fM)" % (cloud.num_points / 1e6), cloud,
                    camera((0.0, -0.75 * extent[1], 0.45 * extent[1]), (0.0, 0.0, 0.0), (1.0, 5000.0))))
    return out


def main():
    renderer = pointnpr.Renderer()
    marks = {"points": pointnpr.Style(mark=("points", {"point_size": 2.0})),
             "hatching": pointnpr.Style(mark="hatching"),
             "hatching (gl)": pointnpr.Style(mark=("hatching", {"rasterizer": "gl"})),
             "feature_strokes": pointnpr.Style(mark="feature_strokes"),
             "feature_strokes (queue)": pointnpr.Style(mark=("feature_strokes", {"density_mode": "constant_on_screen",
                                                                                  "queue_level": 0.25})),
             "stipples": pointnpr.Style(mark=("stipples", {"specular": True, "level_scale": "point_count",
                                                           "level": 8.0})),
             "brush_splats (blur)": pointnpr.Style(mark=("brush_splats", {"blending": "blur"})),
             "brush_splats (a_buffer)": pointnpr.Style(mark=("brush_splats", {"blending": "a_buffer"}))}
    print(f"{W}x{H}, {FRAMES} frames each, alternating; {pointnpr.gl_info()['renderer']}")
    print("| cloud | mark | frame ms (median) | frame ms (best) | mark ms (median) | strokes / dots | vs. points (frame) |")
    print("|---|---|---|---|---|---|---|")
    for cloud_name, cloud, camera in clouds():
        scenes = {}
        for name, style in marks.items():
            scene = pointnpr.Scene()
            scene.add_segment("scan", style, [(cloud, np.eye(4))])
            scenes[name] = scene
            renderer.render(scene, camera, W, H)  # warm-up
        times = {name: [] for name in marks}
        mark_ms = {name: [] for name in marks}
        strokes = {}
        for _ in range(FRAMES):
            for name, scene in scenes.items():
                t0 = time.perf_counter()
                r = renderer.render(scene, camera, W, H, stage_timings=True)
                times[name].append(1000 * (time.perf_counter() - t0))
                mark_ms[name].append(r.stats["mark_ms"])
                strokes[name] = int(r.stats.get("strokes_drawn", r.stats.get("stipples_drawn",
                                                                             r.stats.get("a_buffer_fragments", 0))))
                if r.warnings:
                    print(f"  {cloud_name} {name}: {'; '.join(r.warnings)}", flush=True)
        base = np.median(times["points"])
        for name in marks:
            t = np.median(times[name])
            print(f"| {cloud_name} | {name} | {t:.0f} | {min(times[name]):.0f} | {np.median(mark_ms[name]):.0f} | "
                  f"{strokes[name] or '-'} | {t / base:.2f}x |", flush=True)


if __name__ == "__main__":
    main()
