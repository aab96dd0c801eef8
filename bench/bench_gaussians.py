"""Cost of the gaussians mark (issue 42): ms per 1920x1080 frame for about
1M splats, the native backend (TBB over 16 px tiles) against the points
mark on the same centres, timed alternately in one run (median and best of
N frames after a warm-up), with the numpy reference rasterizer's time
(tests/python/gaussian_reference.py, one frame) beside them.

    PYTHONPATH=build:tests/python /usr/bin/python3 bench/bench_gaussians.py [frames] [--no-reference]

Splats: the lion scan's 342k points, three copies moved by a seeded 2 mm
jitter (1,025,967 splats), each a Gaussian of seeded random rotation and
axes of 3-12 mm (the scan's spacing is about 1 cm), opacity 0.3-1, its
colour as the DC term and SH degree 3 bands of small seeded values; the
lion benchmark's camera. The compute row composites by GL's compute pass
(projection, SH and sort on the CPU's threads in both).
"""
import sys
import time

import numpy as np

import pointnpr

W, H = 1920, 1080
FRAMES = next((int(a) for a in sys.argv[1:] if a.isdigit()), 5)
EYE, TARGET = (2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)


def splats():
    data = pointnpr.read("data/lion_takanawa.ply")
    pos = np.asarray(data.positions, float)
    rgb = np.asarray(data.attributes["colors"], float) / 255.0
    rng = np.random.default_rng(42)
    means = np.concatenate([pos + rng.normal(scale=0.002, size=pos.shape) for _ in range(3)])
    n = len(means)
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    scales = rng.uniform(0.003, 0.012, (n, 3))
    opacity = rng.uniform(0.3, 1.0, n)
    sh = rng.normal(0.0, 0.05, (n, 16, 3))
    sh[:, 0] = (np.tile(rgb, (3, 1)) - 0.5) / 0.28209479177387814
    return means, q, scales, opacity, sh


def capture_and_camera(width, height):
    """The splats as a cloud (DC colour as its colours), the lion benchmark's
    camera, and the splats' arrays (splats())."""
    means, q, scales, opacity, sh = splats()
    n = len(means)
    cloud = pointnpr.PointCloud(means, colors=np.clip(0.5 + 0.28209479177387814 * sh[:, 0], 0, 1),
                                opacity=opacity.astype(np.float32), scales=scales.astype(np.float32),
                                rotations=q.astype(np.float32), sh=sh.reshape(n, -1).astype(np.float32),
                                sh_degree=3)
    camera = pointnpr.Camera.perspective(pointnpr.look_at(EYE, TARGET), lens=35.0, clip_start=0.1,
                                         clip_end=100.0, width=width, height=height)
    return cloud, camera, (means, q, scales, opacity, sh)


def warmed_scenes(renderer, cloud, camera, width, height, marks):
    """One scene per (name, mark) with the cloud, each rendered once (the warm-up)."""
    scenes = {}
    for name, mark in marks:
        scene = pointnpr.Scene()
        scene.add_segment("s", pointnpr.Style(mark=mark), [(cloud, np.eye(4))])
        renderer.render(scene, camera, width, height)
        scenes[name] = scene
    return scenes


def main():
    cloud, camera, (means, q, scales, opacity, sh) = capture_and_camera(W, H)
    n = len(means)
    marks = {"gaussians (native)": ("gaussians", {"rasterizer": "native"}),
             "gaussians (compute)": ("gaussians", {"rasterizer": "compute"}),
             "points (native, 2 px)": ("points", {"rasterizer": "native", "color_source": "rgb"})}
    renderer = pointnpr.Renderer()
    scenes = warmed_scenes(renderer, cloud, camera, W, H, marks.items())
    times = {name: [] for name in marks}
    mark_ms = {name: [] for name in marks}
    stats = {}
    for _ in range(FRAMES):
        for name, scene in scenes.items():
            t = time.perf_counter()
            r = renderer.render(scene, camera, W, H, stage_timings=True)
            times[name].append((time.perf_counter() - t) * 1000.0)
            mark_ms[name].append(r.stats["mark_ms"])
            stats[name] = r.stats
    print(f"{n:,} splats, {W}x{H}, {FRAMES} frames, gl: {pointnpr.gl_info()['renderer']}")
    print("| mark | frame ms (median) | best | mark ms (median) |")
    print("|---|---|---|---|")
    for name in marks:
        print(f"| {name} | {np.median(times[name]):.0f} | {min(times[name]):.0f} | {np.median(mark_ms[name]):.0f} |")
    g = stats["gaussians (native)"]
    print("gaussians stages ms: preprocess %.0f, bin %.0f, raster %.0f; drawn %d, tile entries %d" % (
        g["gaussians_preprocess_ms"], g["gaussians_bin_ms"], g["gaussians_raster_ms"], g["gaussians_drawn"],
        g["gaussians_tile_entries"]))
    if "--no-reference" not in sys.argv:
        from gaussian_reference import render
        view = np.linalg.inv(pointnpr.look_at(EYE, TARGET))
        proj = np.zeros((4, 4))
        f = 35.0 / 18.0  # lens / half the 36 mm sensor (horizontal fit)
        proj[0, 0], proj[1, 1] = f, f * W / H
        proj[2, 2], proj[2, 3], proj[3, 2] = -100.1 / 99.9, -2 * 100 * 0.1 / 99.9, -1.0
        t = time.perf_counter()
        render(means, q, scales, opacity, sh, 3, view, proj, W, H)
        print("numpy reference, one frame: %.0f ms" % ((time.perf_counter() - t) * 1000.0))


if __name__ == "__main__":
    main()
