"""Speed against error of depth inpainting (issue 18): wrong front-segment
pixels (the protocol of bench/inpaint_compositing.py: inside the unfiltered
reference's coverage / among the pixels the filters added) and the
inpainting's ms per frame, as the radius grows, for each method; and
Listing 1's threshold. The LiDAR HD tile, buildings vs the rest, cartoon
(outline width 3), 1280x720, sparse (2 px) splats, where inpainting matters.

    PYTHONPATH=build:bench /usr/bin/python3 bench/inpaint_sweep.py [docs/images/inpaint_sweep.svg]

Prints markdown tables; writes an SVG chart (hand-drawn: no plotting
library is needed) when given a path.
"""
import sys

import numpy as np

import pointnpr
from inpaint_compositing import FILTERS, H, W, nearest_index, render, scans

RADII = [1, 2, 4, 8, 16]
THRESHOLDS = [0.005, 0.02, 0.08, 0.3]
METHODS = ["paper", "surface", "strict"]
COLOURS = {"paper": "#c0392b", "surface": "#2471a3", "strict": "#1e8449"}


def measure(renderer, clouds, cam, ref, covered, judge, inpaint, repeat=3):
    best = None
    for _ in range(repeat):
        idx, _, ms = render(renderer, clouds, cam, 2.0, [FILTERS["cartoon"]], "inpaint", inpaint)
        best = ms if best is None else min(best, ms)
    inside = int((covered & (idx != ref)).sum())
    added = ~covered & (idx >= 0) & (judge >= 0)
    return inside, int((added & (idx != judge)).sum()), best


def svg(path, series):
    """Two panels: wrong pixels (inside + added) and ms, against the radius."""
    width, height, pad = 720, 300, 50
    panel_w = (width - 3 * pad) / 2
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif" '
           'font-size="11">', f'<rect width="{width}" height="{height}" fill="white"/>']
    for p, (title, key) in enumerate((("wrong pixels (inside + added)", 0), ("inpainting ms", 1))):
        x0 = pad + p * (panel_w + pad)
        values = [v[key] for s in series.values() for v in s]
        top = max(values) * 1.1 or 1.0
        out.append(f'<text x="{x0}" y="{pad - 20}">{title}, against the radius (px)</text>')
        out.append(f'<line x1="{x0}" y1="{height - pad}" x2="{x0 + panel_w}" y2="{height - pad}" stroke="black"/>')
        out.append(f'<line x1="{x0}" y1="{pad}" x2="{x0}" y2="{height - pad}" stroke="black"/>')
        for i, r in enumerate(RADII):
            x = x0 + panel_w * i / (len(RADII) - 1)
            out.append(f'<text x="{x - 4}" y="{height - pad + 15}">{r}</text>')
        for frac in (0.0, 0.5, 1.0):
            y = height - pad - (height - 2 * pad) * frac
            out.append(f'<text x="{x0 - 45}" y="{y + 4}">{top * frac:,.0f}</text>')
        for method, points in series.items():
            coords = " ".join(f"{x0 + panel_w * i / (len(RADII) - 1):.1f},"
                              f"{height - pad - (height - 2 * pad) * v[key] / top:.1f}" for i, v in enumerate(points))
            out.append(f'<polyline points="{coords}" fill="none" stroke="{COLOURS[method]}" stroke-width="2"/>')
    for i, method in enumerate(series):
        out.append(f'<text x="{pad + 120 * i}" y="{height - 8}" fill="{COLOURS[method]}">{method}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    renderer = pointnpr.Renderer()
    name, clouds, world_from_camera, clip = next(scans())
    cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                      width=W, height=H)
    ref, _, _ = render(renderer, clouds, cam, 2.0, [], "depth_test", {})
    covered = ref >= 0
    judge = nearest_index(ref, covered)
    print(f"{name}, cartoon, sparse (2 px), {W}x{H}: wrong pixels inside / added, inpainting ms (best of 3)")
    print("| radius | " + " | ".join(METHODS) + " |")
    print("|---|" + "---|" * len(METHODS))
    series = {m: [] for m in METHODS}
    for radius in RADII:
        cells = []
        for method in METHODS:
            inside, added, ms = measure(renderer, clouds, cam, ref, covered, judge,
                                        {"method": method, "radius": radius})
            series[method].append((inside + added, ms))
            cells.append(f"{inside:,} / {added:,}, {ms:.0f} ms")
        print(f"| {radius} | " + " | ".join(cells) + " |", flush=True)
    print()
    print("Listing 1 (paper), radius 4, against its threshold:")
    print("| threshold | wrong inside / added | ms |")
    print("|---|---|---|")
    for threshold in THRESHOLDS:
        inside, added, ms = measure(renderer, clouds, cam, ref, covered, judge,
                                    {"method": "paper", "threshold": threshold})
        print(f"| {threshold:g} | {inside:,} / {added:,} | {ms:.0f} |", flush=True)
    if len(sys.argv) > 1:
        svg(sys.argv[1], series)
        print(f"\nchart: {sys.argv[1]}")


if __name__ == "__main__":
    main()
