"""Temporal stability of each filter (issue 5): renders a 30-frame camera
orbit of the lion scan and reports the mean absolute difference between
consecutive frames after reprojecting frame k+1 into frame k with the known
cameras and the rendered depth (pixels covered in both, not disoccluded:
reprojected depth within 1 %; the previous frame is sampled bilinearly).
Colours are the renderer's scene-linear
premultiplied output. The unfiltered render is the baseline: a filter's
excess over it is flicker the filter introduces.

    PYTHONPATH=build /usr/bin/python3 bench/filter_flicker.py [style ...]

With style names (e.g. `pencil_hatching "preset Toon"`), only those are rendered
(the plain baseline always is).
"""
import sys

import numpy as np

import pointnpr
from pointnpr import presets

W, H, FRAMES, STEP_DEG, LENS, SENSOR = 320, 224, 30, 1.0, 35.0, 36.0
CENTRE = np.array([-2.9, 3.9, -1.2])


def orbit_camera(k):
    a = np.radians(-45.0 + STEP_DEG * k)
    return pointnpr.look_at(CENTRE + np.array([7.8 * np.cos(a), 7.8 * np.sin(a), 2.7]), CENTRE)


def reprojected_mad(prev, cur, m_prev, m_cur):
    """Mean |cur - prev(reprojected)| over pixels valid in both frames."""
    focal = LENS / SENSOR * W  # sensor fit AUTO, landscape: horizontal
    j, i = np.mgrid[0:H, 0:W]
    d = cur.depth
    valid = (cur.color[..., 3] > 0) & (d < 1e9)
    x = (i + 0.5 - W / 2) / focal * d
    y = (j + 0.5 - H / 2) / focal * d
    pts = np.stack([x, y, -d, np.ones_like(d)], -1)[valid]
    world = pts @ m_cur.T
    cam = world @ np.linalg.inv(m_prev).T
    dp = -cam[:, 2]
    # Bilinear lookup of the previous frame at the reprojected position (a
    # nearest-pixel lookup would charge every thin, well anchored line for
    # resampling error); all four taps must see the same surface.
    fx = cam[:, 0] / np.maximum(dp, 1e-9) * focal + W / 2 - 0.5
    fy = cam[:, 1] / np.maximum(dp, 1e-9) * focal + H / 2 - 0.5
    u, v = np.floor(fx).astype(int), np.floor(fy).astype(int)
    inside = (u >= 0) & (u + 1 < W) & (v >= 0) & (v + 1 < H) & (dp > 0)
    u, v, dp, tx, ty = u[inside], v[inside], dp[inside], (fx - np.floor(fx))[inside], (fy - np.floor(fy))[inside]
    cur_px = cur.color[valid][inside]
    ok = np.ones(len(u), bool)
    sample = np.zeros_like(cur_px)
    for du, dv, w in ((0, 0, (1 - tx) * (1 - ty)), (1, 0, tx * (1 - ty)), (0, 1, (1 - tx) * ty), (1, 1, tx * ty)):
        ok &= (prev.color[v + dv, u + du, 3] > 0) & (np.abs(prev.depth[v + dv, u + du] - dp) < 0.01 * dp)
        sample += w[:, None] * prev.color[v + dv, u + du]
    return float(np.abs(cur_px[ok] - sample[ok]).mean()), int(ok.sum())


def spatial_mad(frame):
    """Mean |difference| between neighbouring covered pixels: the frame's
    own detail. A pattern fixed to the surface changes between frames in
    proportion to it (resampling, depth noise), so temporal / spatial is the
    flicker per unit of detail, comparable between smooth and busy styles."""
    c, a = frame.color, frame.color[..., 3] > 0
    dx = np.abs(c[:, 1:] - c[:, :-1])[a[:, 1:] & a[:, :-1]]
    dy = np.abs(c[1:] - c[:-1])[a[1:] & a[:-1]]
    return float(np.concatenate([dx, dy]).mean())


def main():
    renderer = pointnpr.Renderer()
    lion = pointnpr.read("data/lion_takanawa.ply").to_cloud()
    styles = {"plain": pointnpr.Style(rasterize={"point_size": 2.0})}
    for f in ["posterize", "color_grade", "blur", "xdog", "kuwahara", "watercolor", "edge_enhance",
              "pencil_hatching", "cartoon", "warp"]:
        styles[f] = pointnpr.Style(rasterize={"point_size": 2.0}, filters=[f])
    styles["mark hatching"] = pointnpr.Style(mark="hatching")
    styles["pencil_hatching (screen space)"] = pointnpr.Style(rasterize={"point_size": 2.0},
                                                              filters=[("pencil_hatching", {"space": "screen"})])
    for name in presets.PRESETS:
        if name != "Urban map":  # needs classification; the lion has none
            styles["preset " + name] = presets.style(name)
    only = set(sys.argv[1:])
    if only:
        unknown = only - set(styles)
        if unknown:
            sys.exit(f"unknown styles {sorted(unknown)}; known: {sorted(styles)}")
        styles = {k: v for k, v in styles.items() if k == "plain" or k in only}
    cams = [orbit_camera(k) for k in range(FRAMES)]
    base = base_rel = None
    print("| style | temporal MAD (x1000) | vs. plain | temporal / spatial MAD | vs. plain |")
    print("|---|---|---|---|---|")
    for name, style in styles.items():
        scene = pointnpr.Scene()
        scene.add_segment("lion", style, [(lion, np.eye(4))])
        frames = [renderer.render(scene, pointnpr.Camera.perspective(m, lens=LENS, clip_start=0.1, clip_end=100.0,
                                                                     width=W, height=H), W, H)
                  for m in cams]
        mads = [reprojected_mad(frames[k], frames[k + 1], cams[k], cams[k + 1])[0] for k in range(FRAMES - 1)]
        mad = float(np.mean(mads))
        rel = mad / float(np.mean([spatial_mad(f) for f in frames[1:]]))
        base = mad if base is None else base
        base_rel = rel if base_rel is None else base_rel
        print(f"| {name} | {1000 * mad:.1f} | {mad / base:.2f}x | {rel:.3f} | {rel / base_rel:.2f}x |", flush=True)


if __name__ == "__main__":
    main()
