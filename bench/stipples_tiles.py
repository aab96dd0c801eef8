"""Cost of drawing the stipples mark in tiles (issue 17) against the frame
drawn whole: the lion at 1920x1080 from the first camera of
bench/filter_flicker.py's orbit, each stipple preset, whole (tile_size 0)
and in tiles of 512 px, 3 frames each after a warm-up (median); checks that
the bytes agree.

    PYTHONPATH=build /usr/bin/python3 bench/stipples_tiles.py [tile_size]
"""
import sys
import time

import numpy as np

import pointnpr
from pointnpr import presets
from filter_flicker import LENS, orbit_camera

W, H = 1920, 1080


def main():
    tile_size = int(sys.argv[1]) if len(sys.argv) > 1 else 512
    lion = pointnpr.read("data/lion_takanawa.ply").to_cloud()
    renderer = pointnpr.Renderer()
    cam = pointnpr.Camera.perspective(orbit_camera(0), lens=LENS, clip_start=0.1, clip_end=100.0, width=W, height=H)
    print("| preset | tiles | frame ms | mark ms | vs. whole (mark) | same bytes |")
    print("|---|---|---|---|---|---|")
    for name, p in presets.PRESETS.items():
        if p["mark"][0] != "stipples":
            continue
        scene = pointnpr.Scene()
        scene.add_segment("lion", presets.style(name), [(lion, np.eye(4))])
        renderer.render(scene, cam, W, H)
        results = {}
        for size in (0, tile_size):
            runs = []
            for _ in range(3):
                t = time.perf_counter()
                res = renderer.render(scene, cam, W, H, tile_size=size, stage_timings=True)
                runs.append((time.perf_counter() - t, res.stats["mark_ms"], res))
            runs.sort(key=lambda r: r[0])
            results[size] = runs[1]
        whole, tiled = results[0], results[tile_size]
        same = all(np.asarray(getattr(whole[2], k)).tobytes() == np.asarray(getattr(tiled[2], k)).tobytes()
                   for k in ("color", "depth", "segment_index"))
        for size, (sec, mark_ms, res) in results.items():
            print(f"| {name} | {int(res.stats['tiles'])} | {1000 * sec:.0f} | {mark_ms:.0f} | "
                  f"{mark_ms / whole[1]:.2f}x | {'-' if size == 0 else same} |", flush=True)


if __name__ == "__main__":
    main()
