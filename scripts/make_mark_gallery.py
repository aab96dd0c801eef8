"""Renders the gallery of the hatching mark into docs/images/marks/ (used by
docs/marks.md): every hatching preset on the lion scan and on the LiDAR HD
tile, and one picture per important parameter, each panel the same scene
with only that parameter changed (left to right, top to bottom in the
order listed in PICTURES).

    PYTHONPATH=build /usr/bin/python3 scripts/make_mark_gallery.py

Panels are 320x224 (the golden-image framing) or 212x224 close-ups;
pictures are at most 640 px wide, JPEG, quality 90.
"""
import os
import sys

import numpy as np

import pointnpr
from pointnpr import presets

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
OUT = os.path.join(ROOT, "docs", "images", "marks")
W, H = 320, 224

_clouds = {}


def cloud(scan):
    if scan not in _clouds:
        if scan == "tile":
            tile = pointnpr.read(os.path.join(ROOT, "data", "lidarhd_myria3d_870000_6618000_subset.las"))
            pos = np.asarray(tile.positions)
            _clouds[scan] = pointnpr.PointCloud(pos - (pos.min(0) + pos.max(0)) / 2,
                                                colors=np.asarray(tile.attributes["colors"]),
                                                classification=np.asarray(tile.attributes["classification"]))
        else:
            _clouds[scan] = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()
    return _clouds[scan]


# Framings: the golden images' (tests/python/test_golden.py), and close-ups
# of the lion's head and flank where stroke details show.
VIEWS = {
    "lion": ((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2), 35.0, (0.1, 100.0)),
    "tile": ((0.0, -70.0, 60.0), (0.0, 0.0, 0.0), 35.0, (0.5, 1000.0)),
    "lion_close": ((0.8, 0.3, 1.1), (-2.9, 3.9, -0.7), 35.0, (0.1, 100.0)),
}


def render(style, view, w=W, h=H):
    eye, target, lens, clip = VIEWS[view]
    camera = pointnpr.Camera.perspective(pointnpr.look_at(eye, target), lens=lens, clip_start=clip[0],
                                         clip_end=clip[1], width=w, height=h)
    scene = pointnpr.Scene()
    scene.add_segment("scan", style, [(cloud(view.split("_")[0]), np.eye(4))])
    result = renderer.render(scene, camera, w, h, background=(1, 1, 1, 1))
    return np.asarray(result.color)[..., :3], result.stats.get("strokes_drawn", 0)


def save(name, rows):
    """rows: lists of panels (top row first); pixels are bottom row first."""
    image = np.concatenate([np.concatenate(r, 1) for r in rows][::-1], 0)
    assert image.shape[1] <= 640, name
    path = os.path.join(OUT, name + ".jpg")
    pointnpr.save_image(path, np.ascontiguousarray(image, np.float32), srgb=True)
    print(f"{path}: {image.shape[1]}x{image.shape[0]}")


def hatching(base, **changes):
    return pointnpr.Style(mark=("hatching", dict(base, **changes)))


# The parameter pictures start from the Pencil preset's mark (no filters,
# so only the mark shows); (file, view, panel width, [panels' changes]).
PENCIL = presets.PRESETS["Pencil"]["mark"][1]
COLOURED = presets.PRESETS["Coloured crayons"]["mark"][1]
PICTURES = [
    ("cross_hatch", "lion", W, [[{"cross_hatch": 0.0}, {"cross_hatch": 1.0}]]),
    ("stroke_coverage", "lion", W, [[{"stroke_coverage": 0.75}, {"stroke_coverage": 5.0}]]),
    ("curvature_length", "lion_close", W, [[{"curvature_length": 0.0, "line_length": 20.0},
                                            {"curvature_length": 1.0, "line_length": 20.0}]]),
    ("placement", "tile", W, [[{"placement": "regular"},
                               {"placement": "irregular", "position_jitter": 0.8, "angle_jitter": 40.0}]]),
    # The paper's Fig. 4: without an offset the depth discs cut the strokes.
    ("depth_pass", "lion_close", 212, [[{"depth_pass": False}, {"depth_offset": 0.0}, {}]]),
    # Long strokes on the default cream paper, so the silhouette shows.
    ("clip_to_surface", "lion_close", W, [[{"clip_to_surface": c, "line_length": 40.0, "stroke_coverage": 1.0,
                                            "paper_color": (0.97, 0.96, 0.92, 1.0)} for c in (False, True)]]),
    ("coloring", "lion", 212, [[dict(COLOURED, coloring="constant", pencil_quantize=False),
                                dict(COLOURED, coloring="xtoon", pencil_quantize=False),
                                dict(COLOURED, coloring="point", pencil_quantize=False)]]),
    ("pencil_quantize", "lion_close", W, [[dict(COLOURED, pencil_quantize=False),
                                           dict(COLOURED, pencil_quantize=True, pencil_set="box_12")]]),
    ("stroke_texture", "lion_close", W, [[{"stroke_texture": t, "line_width": 3.0} for t in ("pencil", "crayon")],
                                         [{"stroke_texture": t, "line_width": 3.0} for t in ("ink", "soft")]]),
    ("light_direction", "lion", W, [[{"light_space": "world", "light_azimuth": -60.0},
                                     {"light_space": "world", "light_azimuth": 120.0}]]),
]


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, preset in presets.PRESETS.items():
        if preset["mark"][0] != "hatching":
            continue
        style = presets.style(name)
        panels = [render(style, scan)[0] for scan in ("lion", "tile")]
        save("preset_" + name.lower().replace(" ", "_"), [panels])
    for name, view, width, rows in PICTURES:
        out_rows = []
        for row in rows:
            panels = []
            for changes in row:
                image, strokes = render(hatching(PENCIL, **changes), view, width)
                panels.append(image)
                print(f"  {name} {changes if len(changes) < 4 else '...'}: {int(strokes)} strokes")
            out_rows.append(panels)
        save(name, out_rows)


if __name__ == "__main__":
    renderer = pointnpr.Renderer()
    sys.exit(main())
