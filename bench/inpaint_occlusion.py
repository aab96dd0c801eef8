"""The segment behind showing through the front segment's gaps (issue 40,
seed 000 Fig. 12 on real scans): with small (2 px) splats, how many pixels
show the wrong segment where the front segment's surface is, under the
depth test and under depth inpainting.

Protocol, per scan split into two segments (bench/inpaint_compositing.py's
scans), per filter: the truth is the unfiltered segments with dense (6 px)
splats under the depth test, whose splats close the gaps; only pixels at
least 3 px (the dense splat's radius; a disk) inside one segment's truth coverage
are judged, so silhouettes that the dense splats widen do not count. A
pixel is occlusion-wrong when the 2 px render, filtered, shows the other
segment there. The criterion: inpainting at most 0.5x the depth test's.

    PYTHONPATH=build:bench python3 bench/inpaint_occlusion.py

Prints a markdown table.
"""
import numpy as np

import pointnpr
from inpaint_compositing import FILTERS, H, MODES, SPLATS, W, render, scans
from look_audit import erode  # by a disk, as the look audit's closing

MARGIN = 3  # px: the dense splat's radius


def main():
    renderer = pointnpr.Renderer()
    modes = [m for m in MODES if m[0] != "layering"]
    names = ["depth test" if m == "depth_test" else f"inpaint ({i['method']})" for m, i in modes]
    print(f"{W}x{H}; occlusion-wrong pixels with {SPLATS['sparse']:g} px splats (the other segment shown where the "
          f"{SPLATS['dense']:g} px truth is at least {MARGIN} px inside a segment), and inpainting / depth test")
    print("| scan | filter | judged px | " + " | ".join(names) + " | best inpaint / depth test |")
    print("|---|---|---|" + "---|" * len(names) + "---|")
    for name, clouds, world_from_camera, clip in scans():
        cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                          width=W, height=H)
        truth, _, _ = render(renderer, clouds, cam, SPLATS["dense"], [], "depth_test", {})
        judged = np.zeros(truth.shape, bool)
        for k in range(len(clouds)):
            judged |= erode(truth == k, MARGIN)
        for filter_name, step in FILTERS.items():
            wrong = []
            for mode, inpaint in modes:
                idx, _, _ = render(renderer, clouds, cam, SPLATS["sparse"], [step], mode, inpaint)
                wrong.append(int((judged & (idx >= 0) & (idx != truth)).sum()))
            ratio = min(wrong[1:]) / wrong[0] if wrong[0] else float("nan")
            print(f"| {name} | {filter_name} | {int(judged.sum()):,} | " + " | ".join(f"{w:,}" for w in wrong) +
                  f" | {ratio:.2f} |", flush=True)


if __name__ == "__main__":
    main()
