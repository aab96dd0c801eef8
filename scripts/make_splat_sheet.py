"""Renders the contact sheet of a splat capture under every mark and filter
(docs/images/splats_contact_sheet.jpg, used by docs/marks.md): PLAYBOT
(tests/data/io/gaussians/playbot_lod3.spz, 31,000 splats) drawn by the
gaussians mark, then under every filter (each alone, on the gaussians
mark's render with min_coverage 0.2), then by every other point mark (its defaults) on the same
splats. Panels 200x150, the test camera of tests/python/test_marks_gaussians.py,
a white background, each labelled in docs/marks.md in this order.

    PYTHONPATH=build:tests/python /usr/bin/python3 scripts/make_splat_sheet.py
"""
import os

import numpy as np

import pointnpr
from gaussian_reference import perspective, view_matrix

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
W, H, COLUMNS = 200, 150, 5


def main():
    d = pointnpr.read(os.path.join(ROOT, "tests", "data", "io", "gaussians", "playbot_lod3.spz"))
    c = d.positions.mean(0)
    cam = pointnpr.Camera.from_matrices(view_matrix(c + np.array([1.6, 0.5, -2.0]), c, up=(0, 1, 0)),
                                        perspective(1.6, 1.6 * W / H, 0.1, 100.0))
    cloud = d.to_cloud()
    filters = [s["id"] for s in pointnpr.schemas() if s["kind"] == "filter"]
    marks = [s["id"] for s in pointnpr.schemas() if s["kind"] == "mark" and s["id"] not in ("gaussians", "mesh_surface")]
    styles = [("gaussians", pointnpr.Style(mark=("gaussians", {})))]
    # The filters take the render without its faint haze (min_coverage), which
    # those that see any coverage as surface (cartoon, watercolor) paint over.
    styles += [(f, pointnpr.Style(mark=("gaussians", {"min_coverage": 0.2}), filters=[(f, {})])) for f in filters]
    styles += [(m, pointnpr.Style(mark=(m, {}))) for m in marks]
    renderer = pointnpr.Renderer()
    panels = []
    for name, style in styles:
        scene = pointnpr.Scene()
        scene.add_segment("s", style, [(cloud, np.eye(4))])
        r = renderer.render(scene, cam, W, H, background=(1, 1, 1, 1))
        panels.append(np.asarray(r.color)[..., :3])
        print(name)
    while len(panels) % COLUMNS:
        panels.append(np.ones((H, W, 3), np.float32))
    rows = [np.concatenate(panels[i:i + COLUMNS], axis=1) for i in range(0, len(panels), COLUMNS)]
    image = np.concatenate(rows[::-1], axis=0)  # bottom row first: the first panels on top
    path = os.path.join(ROOT, "docs", "images", "splats_contact_sheet.jpg")
    pointnpr.save_image(path, np.ascontiguousarray(image, np.float32), srgb=True)
    print(path, [name for name, _ in styles])


if __name__ == "__main__":
    main()
