"""Does depth inpainting make compositing worse? (issue 18; seed 000 Fig. 12
measured on real scans.)

Protocol, per scan split into two segments, per filter and splat size:
  reference = each segment with its splats unfiltered, composited by the
  depth test; its covered pixels and front-segment index are the truth.
  Each compositing mode renders the segments filtered and counts
    - inside: pixels inside the reference's coverage whose front segment
      differs from the reference's;
    - added: pixels the filters added beyond the reference's coverage whose
      segment differs from that of the nearest reference-covered pixel
      (within 8 px; farther ones are not judged).

    PYTHONPATH=build /usr/bin/python3 bench/inpaint_compositing.py [--quick]

Prints one markdown table row per case; `--quick` runs one scan.
"""
import sys
import time

import numpy as np

import pointnpr

W, H = 1280, 720
FILTERS = {
    "cartoon": ("cartoon", {"outline_width": 3}),
    "xdog": ("xdog", {"thickness": 2.0}),
    "oil": ("kuwahara", {"radius": 5.0}),
}
SPLATS = {"dense": 6.0, "sparse": 2.0}
MODES = [("layering", {}), ("depth_test", {}), ("inpaint", {"method": "paper"}), ("inpaint", {"method": "surface"}),
         ("inpaint", {"method": "strict"})]


def _split(positions, mask, colors, **extra):
    pos = np.asarray(positions, float)
    centre = (pos.min(0) + pos.max(0)) / 2
    out = []
    for m in (mask, ~mask):
        kw = {k: np.asarray(v)[m] for k, v in extra.items()}
        out.append(pointnpr.PointCloud(pos[m] - centre, colors=None if colors is None else np.asarray(colors)[m],
                                       **kw))
    return out


def scans():
    """(name, [cloud A, cloud B], world_from_camera, clip)"""
    tile = pointnpr.read("data/lidarhd_myria3d_870000_6618000_subset.las")
    cls = np.asarray(tile.attributes["classification"])
    yield ("LiDAR HD tile (aerial; buildings vs rest)",
           _split(tile.positions, cls == 6, tile.attributes["colors"]),
           pointnpr.look_at((0.0, -70.0, 60.0), (0.0, 0.0, 0.0)), (0.5, 1000.0))
    lion = pointnpr.read("data/lion_takanawa.ply")
    z = np.asarray(lion.positions)[:, 2]
    yield ("lion (photogrammetry; statue vs plinth)",
           _split(lion.positions, z > np.percentile(z, 45), lion.attributes["colors"]),
           pointnpr.look_at((4.6, -4.6, 2.6), (0.0, 0.0, 0.0)), (0.1, 100.0))
    warsaw = pointnpr.read("tests/data/io/warsaw_small.las")
    cls = np.asarray(warsaw.attributes["classification"])
    pos = np.asarray(warsaw.positions)
    extent = np.ptp(pos, axis=0)
    yield ("Warsaw (aerial; vegetation vs rest)",
           _split(warsaw.positions, np.isin(cls, (3, 4, 5)), warsaw.attributes["colors"]),
           pointnpr.look_at((0.0, -0.9 * extent[1], 0.8 * extent[1]), (0.0, 0.0, 0.0)), (0.5, 5000.0))
    mug = pointnpr.read("tests/data/io/mug_crop.pcd")
    pos = np.asarray(mug.positions)
    depth = pos[:, 2]
    yield ("Kinect mug (depth camera; near vs far)",
           _split(mug.positions, depth < np.percentile(depth, 40), mug.attributes["colors"]),
           # The camera of the frame (PCL: +z forward, +y down), recentred like the points.
           pointnpr.look_at((0.0, 0.0, -0.5), (0.0, 0.0, 0.0), up=(0.0, -1.0, 0.0)), (0.01, 100.0))


def render(renderer, clouds, cam, splat, filters, mode, inpaint):
    scene = pointnpr.Scene()
    for k, c in enumerate(clouds):
        style = pointnpr.Style(mark=("points", {"point_size": splat}), filters=filters, inpaint=inpaint or None)
        scene.add_segment("AB"[k], style, [c])
    t0 = time.perf_counter()
    r = renderer.render(scene, cam, W, H, composite={"mode": mode}, stage_timings=True)
    return np.asarray(r.segment_index).copy(), (time.perf_counter() - t0) * 1000, r.stats.get("inpaint_ms", 0.0)


def nearest_index(index, covered, reach=8):
    """Segment index of the nearest covered pixel (by 8-neighbour dilation
    rounds), -1 beyond `reach` pixels."""
    out = np.where(covered, index, -1)
    for _ in range(reach):
        grown = out.copy()
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                shifted = np.roll(np.roll(out, dy, 0), dx, 1)
                grown = np.where((grown < 0) & (shifted >= 0), shifted, grown)
        out = grown
    return out


def main():
    quick = "--quick" in sys.argv
    renderer = pointnpr.Renderer()
    print(f"{W}x{H}; wrong front-segment pixels inside the reference's coverage / among the pixels the filters "
          "added (judged against the nearest covered pixel)")
    print("| scan | filter | splats | layering | depth test | inpaint (paper) | inpaint (surface) | "
          "inpaint (strict) | inpaint ms paper / surface / strict |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, clouds, world_from_camera, clip in scans():
        cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                          width=W, height=H)
        for splat_name, splat in SPLATS.items():
            ref, _, _ = render(renderer, clouds, cam, splat, [], "depth_test", {})
            covered = ref >= 0
            judge = nearest_index(ref, covered)
            for filter_name, step in FILTERS.items():
                cells, times = [], []
                for mode, inpaint in MODES:
                    idx, _, inpaint_ms = render(renderer, clouds, cam, splat, [step], mode, inpaint)
                    inside = int((covered & (idx != ref)).sum())
                    added = ~covered & (idx >= 0) & (judge >= 0)
                    cells.append(f"{inside:,} / {int((added & (idx != judge)).sum()):,}")
                    if mode == "inpaint":
                        times.append(inpaint_ms)
                print(f"| {name} | {filter_name} | {splat_name} ({splat:g} px) | " + " | ".join(cells) +
                      " | " + " / ".join(f"{t:.0f}" for t in times) + " |", flush=True)
        if quick:
            break


if __name__ == "__main__":
    main()
