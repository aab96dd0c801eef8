"""The native brush splats on their SIMD lanes against Highway's one-lane
target (`native_limits={"scalar_lanes": True}`: the same kernels, the same
bytes), on the lion at 1920x1080: what a single scalar kernel source would
cost on the CPU (docs/architecture.md, "The brush splats' two sources").

    PYTHONPATH=build /usr/bin/python3 bench/brush_lanes.py [rounds]

Prints, per round, the best of 3 `mark_ms` of each, alternating.
"""
import os
import sys

import numpy as np

import pointnpr

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import look_audit  # noqa: E402  (its scans and framing)

W, H = 1920, 1080


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    renderer = pointnpr.Renderer()
    _name, pos, attrs, world_from_camera, clip = next(look_audit.scans())  # the lion
    cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                      width=W, height=H)
    cloud, centre = look_audit._cloud(pos, attrs)
    m = np.eye(4)
    m[:3, 3] = centre
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("brush_splats", {"rasterizer": "native"})), [(cloud, m)])
    renderer.render(scene, cam, W, H)  # the cloud's caches
    print("| round | lanes | mark ms | scalar lanes mark ms | ratio |")
    print("|---|---|---|---|---|")
    for r in range(rounds):
        best = {}
        for scalar in (False, True):
            limits = {"native_limits": {"scalar_lanes": True}} if scalar else {}
            runs = [renderer.render(scene, cam, W, H, stage_timings=True, **limits) for _ in range(3)]
            best[scalar] = (min(x.stats["mark_ms"] for x in runs), runs[-1].stats["brush_native_lanes"])
        print(f"| {r + 1} | {best[False][1]:.0f} | {best[False][0]:.0f} | {best[True][0]:.0f} | "
              f"{best[True][0] / best[False][0]:.2f}x |")


if __name__ == "__main__":
    main()
