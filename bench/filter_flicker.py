"""Temporal stability of each filter (issue 5): renders a 30-frame camera
orbit of the lion scan and reports the mean absolute difference between
consecutive frames after reprojecting frame k+1 into frame k with the known
cameras and the rendered depth (pixels covered in both, not disoccluded:
reprojected depth within 1 %). Colours are the renderer's scene-linear
premultiplied output. The unfiltered render is the baseline: a filter's
excess over it is flicker the filter introduces.

    PYTHONPATH=build python3 bench/filter_flicker.py
"""
import numpy as np

import pointnpr
from pointnpr import presets

W, H, FRAMES, STEP_DEG, LENS, SENSOR = 320, 224, 30, 1.0, 35.0, 36.0
CENTRE = np.array([-2.9, 3.9, -1.2])


def orbit_camera(k):
    a = np.radians(-45.0 + STEP_DEG * k)
    eye = CENTRE + np.array([7.8 * np.cos(a), 7.8 * np.sin(a), 2.7])
    f = CENTRE - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, [0.0, 0.0, 1.0])
    s /= np.linalg.norm(s)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = s, np.cross(s, f), -f, eye
    return m


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
    u = np.floor(cam[:, 0] / dp * focal + W / 2).astype(int)
    v = np.floor(cam[:, 1] / dp * focal + H / 2).astype(int)
    inside = (u >= 0) & (u < W) & (v >= 0) & (v < H) & (dp > 0)
    u, v, dp = u[inside], v[inside], dp[inside]
    cur_px = cur.color[valid][inside]
    ok = (prev.color[v, u, 3] > 0) & (np.abs(prev.depth[v, u] - dp) < 0.01 * dp)
    return float(np.abs(cur_px[ok] - prev.color[v, u][ok]).mean()), int(ok.sum())


def main():
    renderer = pointnpr.Renderer()
    lion = pointnpr.read("data/lion_takanawa.ply").to_cloud()
    styles = {"plain": pointnpr.Style(rasterize={"point_size": 2.0})}
    for f in ["posterize", "color_grade", "blur", "xdog", "kuwahara", "watercolor", "edge_enhance", "hatching",
              "cartoon", "warp"]:
        styles[f] = pointnpr.Style(rasterize={"point_size": 2.0}, filters=[f])
    for name in presets.PRESETS:
        if name != "Urban map":  # needs classification; the lion has none
            styles["preset " + name] = presets.style(name)
    cams = [orbit_camera(k) for k in range(FRAMES)]
    base = None
    print(f"| style | mean abs. difference (x1000) | vs. plain |")
    print(f"|---|---|---|")
    for name, style in styles.items():
        scene = pointnpr.Scene()
        scene.add_segment("lion", style, [(lion, np.eye(4))])
        frames = [renderer.render(scene, pointnpr.Camera.perspective(m, lens=LENS, clip_start=0.1, clip_end=100.0,
                                                                     width=W, height=H), W, H)
                  for m in cams]
        mads = [reprojected_mad(frames[k], frames[k + 1], cams[k], cams[k + 1])[0] for k in range(FRAMES - 1)]
        mad = float(np.mean(mads))
        base = mad if base is None else base
        print(f"| {name} | {1000 * mad:.1f} | {mad / base:.2f}x |", flush=True)


if __name__ == "__main__":
    main()
