"""Renders the filter gallery of docs/filters.md: the lion scan with every
filter (default parameters) and every preset, plus the "Urban map" preset
on the LiDAR HD tile (it colours by classification, which the lion lacks).
One contact sheet, 4 columns, in the order of ORDER below.

    PYTHONPATH=build python3 bench/filter_gallery.py docs/filter_gallery.jpg
"""
import sys

import numpy as np

import pointnpr
from pointnpr import presets

W, H = 320, 224
ORDER = ["plain", "posterize", "color_grade", "blur", "xdog", "kuwahara", "flow_oil", "watercolor", "edge_enhance",
         "pencil_hatching", "cartoon", "warp", "fill_holes", "Toon", "Ink outlines", "Flow ink", "Watercolor",
         "Oil paint", "Flow oil paint", "Posterize", "Urban map"]


def render(renderer, cloud, style, camera):
    scene = pointnpr.Scene()
    scene.add_segment("cloud", style, [(cloud, np.eye(4))])
    return renderer.render(scene, camera, W, H, background=(1, 1, 1, 1)).color[..., :3]


def main(out):
    renderer = pointnpr.Renderer()
    lion = pointnpr.read("data/lion_takanawa.ply").to_cloud()
    lion_cam = pointnpr.Camera.perspective(pointnpr.look_at((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)), lens=35.0,
                                           clip_start=0.1, clip_end=100.0, width=W, height=H)
    tile = pointnpr.read("data/lidarhd_myria3d_870000_6618000_subset.las")
    pos = np.asarray(tile.positions)
    centre = (pos.min(0) + pos.max(0)) / 2
    local = pointnpr.PointCloud(pos - centre, colors=np.asarray(tile.attributes["colors"]),
                                classification=np.asarray(tile.attributes["classification"]))
    tile_cam = pointnpr.Camera.perspective(pointnpr.look_at((0.0, -70.0, 60.0), (0.0, 0.0, 0.0)), lens=35.0,
                                           clip_start=0.5, clip_end=1000.0, width=W, height=H)
    images = []
    for name in ORDER:
        if name == "Urban map":
            images.append(render(renderer, local, presets.style(name), tile_cam))
        elif name in presets.PRESETS:
            images.append(render(renderer, lion, presets.style(name), lion_cam))
        else:
            filters = [] if name == "plain" else [name]
            images.append(render(renderer, lion, pointnpr.Style(rasterize={"point_size": 2.0}, filters=filters),
                                 lion_cam))
    cols = 4
    rows = (len(images) + cols - 1) // cols
    sheet = np.ones((rows * (H + 4), cols * (W + 4), 3), np.float32)
    for i, img in enumerate(images):
        r, c = rows - 1 - i // cols, i % cols  # bottom row first
        sheet[r * (H + 4) + 2:r * (H + 4) + 2 + H, c * (W + 4) + 2:c * (W + 4) + 2 + W] = img
    pointnpr.save_image(out, np.ascontiguousarray(sheet))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "filter_gallery.jpg")
