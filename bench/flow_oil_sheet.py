"""Contact sheet of the flow-based oil paint (issue 40): for each scan of the
look audit (bench/look_audit.py: its scans and cameras, 1280x720), the Oil
paint preset (Kuwahara) and the Flow oil paint preset, each as the whole
frame at half scale beside a crop at full scale (the strokes are pixels
wide, so only the crop shows them), one row per scan.

    PYTHONPATH=build python3 bench/flow_oil_sheet.py OUT.jpg [--scan=lion ...]
"""
import os
import sys

import numpy as np

import pointnpr
from pointnpr import presets

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import look_audit  # noqa: E402

PRESETS = ["Oil paint", "Flow oil paint"]
GAP = 4  # px of white between pictures


def on_white(rgba):
    a = rgba[..., 3:4]
    return rgba[..., :3] * a + (1.0 - a)


def half(rgb):
    h, w = rgb.shape[0] // 2, rgb.shape[1] // 2
    return rgb[:2 * h, :2 * w].reshape(h, 2, w, 2, 3).mean((1, 3))


def crop_at_the_middle(rgb, covered, size):
    """A size x size crop centred on the covered pixels' median (the scan's
    body, not the frame's empty corners)."""
    ys, xs = np.nonzero(covered)
    cy, cx = int(np.median(ys)), int(np.median(xs))
    y0 = min(max(cy - size // 2, 0), rgb.shape[0] - size)
    x0 = min(max(cx - size // 2, 0), rgb.shape[1] - size)
    return rgb[y0:y0 + size, x0:x0 + size]


def main():
    out = next(a for a in sys.argv[1:] if not a.startswith("--"))
    only = [a.split("=", 1)[1] for a in sys.argv if a.startswith("--scan=")]
    renderer = pointnpr.Renderer()
    rows = []
    for name, pos, attrs, world_from_camera, clip in look_audit.scans():
        if only and not any(o.lower() in name.lower() for o in only):
            continue
        cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                          width=look_audit.W, height=look_audit.H)
        cloud, centre = look_audit._cloud(pos, attrs)
        pictures = []
        for preset in PRESETS:
            spec = presets.PRESETS[preset]
            rgba = look_audit._render(renderer, cloud, centre, spec["mark"], spec["filters"], cam)
            rgb = on_white(rgba)
            small = half(rgb)
            pictures += [small, crop_at_the_middle(rgb, rgba[..., 3] > 0, small.shape[0])]
        height = pictures[0].shape[0]
        row = np.ones((height, sum(p.shape[1] for p in pictures) + GAP * (len(pictures) - 1), 3), np.float32)
        x = 0
        for p in pictures:
            row[:, x:x + p.shape[1]] = p
            x += p.shape[1] + GAP
        rows.append(row)
        print(name, flush=True)
    # save_image writes the bottom row first: the first scan goes last.
    sheet = np.ones((sum(r.shape[0] for r in rows) + GAP * (len(rows) - 1), rows[0].shape[1], 3), np.float32)
    y = 0
    for r in reversed(rows):
        sheet[y:y + r.shape[0]] = r
        y += r.shape[0] + GAP
    pointnpr.save_image(out, np.ascontiguousarray(sheet), srgb=True)


if __name__ == "__main__":
    main()
