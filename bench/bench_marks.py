"""Cost of a frame per mark (issue 10): the hatching mark against the
points mark on the same cloud and view, 1920x1080, timed alternately in one
run (median and best of N frames after a warm-up frame that uploads,
estimates normals and compiles shaders).

    PYTHONPATH=build /usr/bin/python3 bench/bench_marks.py [frames]

Clouds: the lion scan (342k points) and a 3.4M-point lion (ten copies,
each moved by a seeded sub-millimetre jitter: the paper's smallest case is
3.5M points). Reports the whole render call and the mark stage alone
(`mark_ms`), and the ratio hatching / points (goal: at most 3x). The
brush_splats rows (issue 12) blend by blur and by the A-buffer (its
strokes column: the A-buffer's fragments; goal for blur: at most 3x).
"""
import sys
import time

import numpy as np

import pointnpr

W, H = 1920, 1080
FRAMES = int(sys.argv[1]) if len(sys.argv) > 1 else 7
EYE, TARGET = (2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)


def clouds():
    data = pointnpr.read("data/lion_takanawa.ply")
    lion = data.to_cloud()
    pos = np.asarray(data.positions, float)
    colors = np.asarray(data.attributes["colors"]) if "colors" in data.attributes else None
    rng = np.random.default_rng(10)
    copies = [pos + rng.normal(scale=0.0005, size=pos.shape) for _ in range(10)]
    big = pointnpr.PointCloud(np.concatenate(copies),
                              colors=None if colors is None else np.concatenate([colors] * 10))
    return {"lion (%dk)" % (lion.num_points // 1000): lion, "lion x10 (%.1fM)" % (big.num_points / 1e6): big}


def main():
    renderer = pointnpr.Renderer()
    camera = pointnpr.Camera.perspective(pointnpr.look_at(EYE, TARGET), lens=35.0, clip_start=0.1, clip_end=100.0,
                                         width=W, height=H)
    marks = {"points": pointnpr.Style(mark=("points", {"point_size": 2.0})),
             "hatching": pointnpr.Style(mark="hatching"),
             "brush_splats (blur)": pointnpr.Style(mark=("brush_splats", {"blending": "blur"})),
             "brush_splats (a_buffer)": pointnpr.Style(mark=("brush_splats", {"blending": "a_buffer"}))}
    print(f"{W}x{H}, {FRAMES} frames each, alternating; {pointnpr.gl_info()['renderer']}")
    print("| cloud | mark | frame ms (median) | frame ms (best) | mark ms (median) | strokes | vs. points (frame) |")
    print("|---|---|---|---|---|---|---|")
    for cloud_name, cloud in clouds().items():
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
                r = renderer.render(scene, camera, W, H)
                times[name].append(1000 * (time.perf_counter() - t0))
                mark_ms[name].append(r.stats["mark_ms"])
                strokes[name] = int(r.stats.get("strokes_drawn", r.stats.get("a_buffer_fragments", 0)))
                if r.warnings:
                    print(f"  {cloud_name} {name}: {'; '.join(r.warnings)}", flush=True)
        base = np.median(times["points"])
        for name in marks:
            t = np.median(times[name])
            print(f"| {cloud_name} | {name} | {t:.0f} | {min(times[name]):.0f} | {np.median(mark_ms[name]):.0f} | "
                  f"{strokes[name] or '-'} | {t / base:.2f}x |", flush=True)


if __name__ == "__main__":
    main()
