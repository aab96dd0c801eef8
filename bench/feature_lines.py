"""How the feature strokes' directional lines hold together (issue 39: "edge
strokes are short disconnected ticks"): each feature stroke preset drawn with
only its directional class (dithering and non-directional points off) on the
marks audit's scans at 1280x720, with `chain_lines` on and off in one run.
The ink (covered pixels whose mean colour is below 0.5) is split into 8-connected
components; a line that holds together is one long component, ticks are many
short ones. Printed per scan: ink pixels, components, and the share of the
ink in components whose bounding box is at least LONG_PX across its diagonal.

    PYTHONPATH=build python3 bench/feature_lines.py [--preset=NAME ...] [--scan=PREFIX ...]
"""
import os
import sys

import numpy as np
from scipy import ndimage

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pointnpr  # noqa: E402
from pointnpr import presets  # noqa: E402

import look_audit as la  # noqa: E402
import marks_audit as ma  # noqa: E402

LONG_PX = 40.0
PRESETS = ["Feature strokes + stipples", "Feature strokes + hatching"]


def lines(img):
    """(ink pixels, components, share of the ink in long components)."""
    ink = (img[..., 3] > 0.5) & (img[..., :3].mean(-1) < 0.5)
    labels, n = ndimage.label(ink, structure=np.ones((3, 3)))
    if n == 0:
        return 0, 0, 0.0
    sizes = np.bincount(labels.ravel())[1:]
    extent = np.array([np.hypot(o[0].stop - o[0].start, o[1].stop - o[1].start)
                       for o in ndimage.find_objects(labels)])
    return int(ink.sum()), n, float(sizes[extent >= LONG_PX].sum() / ink.sum())


def main():
    picked = [a.split("=", 1)[1] for a in sys.argv if a.startswith("--preset=")] or PRESETS
    only = [a.split("=", 1)[1] for a in sys.argv if a.startswith("--scan=")]
    renderer = pointnpr.Renderer()
    print("| scan | preset | ink px (off / on) | components (off / on) | ink in lines >= 40 px (off / on) |")
    print("|---|---|---|---|---|")
    for name, pos, attrs, world_from_camera, clip in ma.scans():
        if only and not any(name.startswith(o) for o in only):
            continue
        cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                          width=la.W, height=la.H)
        cloud, centre = la._cloud(pos, attrs)
        for preset in picked:
            spec = presets.PRESETS[preset]
            mark, params = spec["mark"][0], dict(spec["mark"][1], dithering="none", non_directional="none")
            got = [lines(la._render(renderer, cloud, centre, (mark, dict(params, chain_lines=on)), [], cam))
                   for on in (False, True)]
            print(f"| {name} | {preset} | {got[0][0]} / {got[1][0]} | {got[0][1]} / {got[1][1]} | "
                  f"{100 * got[0][2]:.0f} % / {100 * got[1][2]:.0f} % |", flush=True)


if __name__ == "__main__":
    main()
