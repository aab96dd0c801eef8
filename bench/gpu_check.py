"""The GPU check's measurements (bench/gpu_check.sh runs this after the
parity and determinism tests): the device, the points mark's 64-bit-atomics
compute path against its 32-bit one, and each mark's frame on the lion at
1920x1080 on its GL backend against its native one, side by side in one
run. Writes a Markdown report.

    PYTHONPATH=build python3 bench/gpu_check.py REPORT.md [--frames N]

The timings are medians of N frames after a warm-up frame (uploads,
normals, shader compilation), with stage_timings on so that mark_ms holds
the GPU's work. On llvmpipe (CI) the same steps run: GL there is the CPU.
"""
import argparse
import hashlib
import os
import statistics
import sys
import time

import numpy as np

import pointnpr

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
W, H = 1920, 1080
# Every mark with a GL and a native backend, and its GL backends' values.
BACKENDS = {"points": ["compute", "gl_points", "native"], "brush_splats": ["gl", "native"],
            "stipples": ["gl", "native"], "feature_strokes": ["gl", "native"], "hatching": ["gl", "native"]}


def camera():
    return pointnpr.Camera.perspective(pointnpr.look_at((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)), lens=35.0,
                                       clip_start=0.1, clip_end=100.0, width=W, height=H)


def render(renderer, cloud, mark, params, **kw):
    scene = pointnpr.Scene()
    scene.add_segment("scan", pointnpr.Style(mark=(mark, params)), [(cloud, np.eye(4))])
    return renderer.render(scene, camera(), W, H, background=(1, 1, 1, 0), stage_timings=True, **kw)


def digest(result):
    return hashlib.sha256(np.asarray(result.color).tobytes() + np.asarray(result.depth).tobytes()).hexdigest()[:16]


def int64_check(renderer, cloud):
    """The compute splatting's two depth paths: with 64-bit atomics (one
    depth-and-key pass) and without (depth, then key): the same bytes."""
    has = bool(pointnpr.gl_info().get("int64_atomics"))
    a = render(renderer, cloud, "points", {"rasterizer": "compute"}, int64_atomics=True)
    b = render(renderer, cloud, "points", {"rasterizer": "compute"}, int64_atomics=False)
    same = digest(a) == digest(b)
    if has:
        return same, "64-bit atomics: yes; their compute path draws the 32-bit path's bytes: %s" % (
            "yes" if same else "**NO**")
    return same, "64-bit atomics: not on this device (the 32-bit path ran twice: %s)" % (
        "same bytes" if same else "**bytes differ**")


def timings(renderer, cloud, frames):
    """Rows of (mark, backend, frame ms, mark ms, ratio to the points
    mark's fastest backend by frame)."""
    rows = []
    for mark, backends in BACKENDS.items():
        for backend in backends:
            params = {"rasterizer": backend}
            render(renderer, cloud, mark, params)  # warm-up
            frame_ms, mark_ms = [], []
            for _ in range(frames):
                t = time.perf_counter()
                r = render(renderer, cloud, mark, params)
                frame_ms.append(1000.0 * (time.perf_counter() - t))
                mark_ms.append(r.stats.get("mark_ms", float("nan")))
            rows.append((mark, backend, statistics.median(frame_ms), statistics.median(mark_ms)))
    points = min(f for m, _b, f, _ms in rows if m == "points")
    return [(m, b, f, ms, f / points) for m, b, f, ms in rows]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("report", nargs="?", default=os.path.join(ROOT, "build", "gpu_check.md"))
    parser.add_argument("--frames", type=int, default=5)
    args = parser.parse_args()
    frames, out = args.frames, args.report
    info = pointnpr.gl_info()
    renderer = pointnpr.Renderer()
    cloud = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()
    same, int64_line = int64_check(renderer, cloud)
    rows = timings(renderer, cloud, frames)
    lines = ["# GPU check", "",
             "Device: %s (GL %s%s); %d CPU threads. Lion (%d points) at %dx%d, median of %d frames." % (
                 info.get("renderer"), info.get("version"), ", software" if info.get("software") else "",
                 os.cpu_count() or 0, cloud.num_points, W, H, frames), "",
             "- " + int64_line, "",
             "| mark | backend | frame ms | mark ms | frame vs points |", "|---|---|---|---|---|"]
    lines += ["| %s | %s | %.1f | %.1f | %.2fx |" % row for row in rows]
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
