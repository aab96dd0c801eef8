"""Stroke density on screen against camera distance, with and without the
continuous resolution queue (seed 001 section 6.3): a 2.4 x 1.8 m wall
sampled every 5 mm (173k points, 11 chunks) drawn by the feature_strokes
mark (dithering points as sprites) from 2 to 16 m, 640x480. Density =
strokes whose centre is in the image per 1000 covered pixels. Prints a markdown table and writes
docs/images/queue_density.svg.

    PYTHONPATH=build /usr/bin/python3 bench/queue_density.py
"""
import os

import numpy as np

import pointnpr

W, H = 640, 480
DISTANCES = [2.0, 2.8, 4.0, 5.7, 8.0, 11.3, 16.0]
STYLE = {"dither": 0.5, "dithering": "point_sprite", "queue_level": 0.05}


def wall():
    xs, ys = np.arange(-1.2, 1.2 + 1e-9, 0.005), np.arange(-0.9, 0.9 + 1e-9, 0.005)
    X, Y = np.meshgrid(xs, ys)
    return pointnpr.PointCloud(np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)]))


def density(renderer, cloud, distance, mode):
    m = np.eye(4)
    m[2, 3] = distance
    cam = pointnpr.Camera.perspective(m, lens=35.0, width=W, height=H)
    scene = pointnpr.Scene()
    scene.add_segment("wall", pointnpr.Style(mark=("feature_strokes", dict(STYLE, density_mode=mode))),
                      [(cloud, np.eye(4))])
    r = renderer.render(scene, cam, W, H, background=(1, 1, 1, 0), capture_marks=True)
    covered = (np.asarray(r.color)[..., 3] > 0).sum()
    # Strokes whose centre is in the image (a chunk partly outside the view
    # draws its queue share over all of it).
    c = np.asarray(r.marks["center"])
    focal = 35.0 / 36.0 * W
    x, y = W / 2 + focal * c[:, 0] / -c[:, 2], H / 2 + focal * c[:, 1] / -c[:, 2]
    n = int(((x >= 0) & (x < W) & (y >= 0) & (y < H)).sum())
    return 1000.0 * n / covered, n


def svg(rows, path):
    x0, y0, w, h = 60, 20, 420, 240
    lx = lambda d: x0 + w * (np.log2(d) - 1) / 3  # 2..16 m, log scale
    ymax = max(max(a, q) for _, a, q in rows) * 1.1
    ly = lambda v: y0 + h - h * v / ymax
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{x0 + w + 150}" height="{y0 + h + 50}" '
           'font-family="sans-serif" font-size="12">',
           f'<rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="none" stroke="#888"/>']
    for d in (2, 4, 8, 16):
        out.append(f'<text x="{lx(d):.1f}" y="{y0 + h + 16}" text-anchor="middle">{d}</text>')
    out.append(f'<text x="{x0 + w / 2}" y="{y0 + h + 36}" text-anchor="middle">camera distance (m)</text>')
    for v in np.linspace(0, ymax, 5)[1:]:
        out.append(f'<text x="{x0 - 6}" y="{ly(v) + 4:.1f}" text-anchor="end">{v:.0f}</text>')
    out.append(f'<text x="14" y="{y0 + h / 2}" transform="rotate(-90 14 {y0 + h / 2})" text-anchor="middle">'
               'strokes per 1000 px</text>')
    for col, colour, label in ((1, "#c03020", "all points"), (2, "#2050c0", "queue (constant on screen)")):
        pts = " ".join(f"{lx(r[0]):.1f},{ly(r[col]):.1f}" for r in rows)
        out.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"/>')
        for r in rows:
            out.append(f'<circle cx="{lx(r[0]):.1f}" cy="{ly(r[col]):.1f}" r="3" fill="{colour}"/>')
        yl = y0 + 20 * col
        out.append(f'<line x1="{x0 + w + 10}" y1="{yl}" x2="{x0 + w + 30}" y2="{yl}" stroke="{colour}" stroke-width="2"/>')
        out.append(f'<text x="{x0 + w + 34}" y="{yl + 4}">{label}</text>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def main():
    renderer = pointnpr.Renderer()
    cloud = wall()
    rows = []
    print(f"{cloud.num_points} points, {W}x{H}, feature_strokes {STYLE}")
    print("| distance (m) | all points: strokes / 1000 px (strokes) | queue: strokes / 1000 px (strokes) |")
    print("|---|---|---|")
    for d in DISTANCES:
        a, na = density(renderer, cloud, d, "all_points")
        q, nq = density(renderer, cloud, d, "constant_on_screen")
        rows.append((d, a, q))
        print(f"| {d:.1f} | {a:.0f} ({na}) | {q:.1f} ({nq}) |", flush=True)
    path = os.path.join(os.path.dirname(__file__), "..", "docs", "images", "queue_density.svg")
    svg(rows, path)
    print("wrote", os.path.normpath(path))


if __name__ == "__main__":
    main()
