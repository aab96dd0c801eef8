"""What a Gaussian splat's scales and opacity cost the other marks (issue
42, docs/marks.md "A splat's scales and opacity in the other marks"): ms per
960x720 frame of each mark on bench_gaussians.py's splats (the lion scan
three times over, 1,025,967 splats, opacity 0.3-1), without and with its
splat parameters, every row timed alternately in one run (median and best
of N frames after a warm-up frame: uploads, neighbours, shaders).

    PYTHONPATH=build /usr/bin/python3 bench/bench_splat_weights.py [frames] [--gl]

The marks' native rasterizers by default (what auto picks on llvmpipe);
--gl adds the GL rows of the marks that have both. The CPU column is the
process's CPU time (every thread's): on a machine shared with other work
it moves far less than the wall clock.
"""
import os
import sys
import time

import numpy as np

import pointnpr

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_gaussians import capture_and_camera, warmed_scenes  # noqa: E402

W, H = 960, 720
FRAMES = next((int(a) for a in sys.argv[1:] if a.isdigit()), 5)
# mark: (its parameters, [what it reads of the splats, one row each])
WEIGHTS = {"brush_splats": ({"blending": "blur"}, [{"size_mode": "splat"}, {"opacity_weight": True},
                                                   {"size_mode": "splat", "opacity_weight": True}]),
           "points": ({}, [{"size_mode": "splat"}, {"opacity_draws": True},
                           {"size_mode": "splat", "opacity_draws": True}]),
           "hatching": ({}, [{"opacity_draws": True}]),
           "stipples": ({}, [{"opacity_draws": True}]),
           "feature_strokes": ({}, [{"opacity_draws": True}])}


def rows():
    backends = ["native"] + (["gl"] if "--gl" in sys.argv else [])
    for mark, (base, variants) in WEIGHTS.items():
        for backend in backends:
            rasterizer = "compute" if mark == "points" and backend == "gl" else backend
            for weights in [{}] + variants:
                label = "%s (%s)%s" % (mark, rasterizer, "".join(
                    " + %s" % (k if v is True else "%s %s" % (k, v)) for k, v in weights.items()))
                yield label, (mark, dict(base, rasterizer=rasterizer, **weights))


def main():
    cloud, camera, arrays = capture_and_camera(W, H)
    n = len(arrays[0])
    renderer = pointnpr.Renderer()
    scenes = warmed_scenes(renderer, cloud, camera, W, H, rows())
    times = {name: [] for name in scenes}
    cpu = {name: [] for name in scenes}
    for _ in range(FRAMES):
        for name, scene in scenes.items():
            t, c = time.perf_counter(), time.process_time()
            renderer.render(scene, camera, W, H)
            times[name].append((time.perf_counter() - t) * 1000.0)
            cpu[name].append((time.process_time() - c) * 1000.0)
    print(f"{n:,} splats, {W}x{H}, {FRAMES} frames, gl: {pointnpr.gl_info()['renderer']}")
    print("| mark | frame ms (median) | best | CPU ms (median) |")
    print("|---|---|---|---|")
    for name in scenes:
        print(f"| {name} | {np.median(times[name]):.1f} | {min(times[name]):.1f} | {np.median(cpu[name]):.0f} |")


if __name__ == "__main__":
    main()
