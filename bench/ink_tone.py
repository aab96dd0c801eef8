"""Tone of the ink marks against Lambert shading (issue 39): each preset on
five scan kinds (the lion, the LiDAR HD tile, a Kinect frame, Igea and a
10 % subsample of it, the sparse colourless case) at 1280x720, and the
block correlation (16 px blocks fully covered by the points) of its ink
(1 - luminance / paper) with the points mark's Lambert shading under the
preset's light. Writes a contact sheet per preset (mark | Lambert, a scan a
row) and prints r per scan.

    PYTHONPATH=build python3 bench/ink_tone.py build OUTDIR Pencil,Blueprint ['{"light_space": "camera"}']"""
import os, sys, json, numpy as np
sys.path.insert(0, sys.argv[1])
import pointnpr
from pointnpr import presets
W, H = 1280, 720
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
S = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data", "scans")
extra = json.loads(sys.argv[4]) if len(sys.argv) > 4 else {}
def fit_cam(pos, eye_dir, up=(0, 0, 1)):
    c = (pos.min(0) + pos.max(0)) / 2; r = np.linalg.norm(pos.max(0) - pos.min(0)) / 2
    eye = c + np.asarray(eye_dir, float) / np.linalg.norm(eye_dir) * r * 2.2
    return pointnpr.Camera.perspective(pointnpr.look_at(tuple(eye), tuple(c), up=up), lens=35.0, clip_start=r * 0.01, clip_end=r * 20, width=W, height=H)
scans = []
d = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")); scans.append(("lion", d.to_cloud(), fit_cam(np.asarray(d.positions), (1, -0.7, 0.5))))
d = pointnpr.read(os.path.join(ROOT, "data", "lidarhd_myria3d_870000_6618000_subset.las")); p = np.asarray(d.positions, float); p -= p.mean(0)
scans.append(("aerial", pointnpr.PointCloud(p, colors=np.asarray(d.attributes["colors"])), fit_cam(p, (0, -1, 0.8))))
d = pointnpr.read(S + "/table_scene_mug_stereo_textured.pcd"); p = np.asarray(d.positions); ok = np.isfinite(p).all(1)
c = d.to_cloud(); pm = p[ok]
scans.append(("kinect", c, pointnpr.Camera.perspective(pointnpr.look_at((0, 0, 0), tuple(np.median(pm, 0)), up=(0, -1, 0)), lens=35, clip_start=0.05, clip_end=50, width=W, height=H)))
d = pointnpr.read(S + "/igea.ply"); p = np.asarray(d.positions, float)
scans.append(("igea", pointnpr.PointCloud(p), fit_cam(p, (0.3, -1, 0.3))))
d = pointnpr.read(S + "/igea.ply"); p = np.asarray(d.positions, float)[::10]
scans.append(("igea_10pc", pointnpr.PointCloud(p), fit_cam(p, (0.3, -1, 0.3))))
r = pointnpr.Renderer()
names = sys.argv[3].split(",")
os.makedirs(sys.argv[2], exist_ok=True)
for n in names:
    st = presets.PRESETS[n]; mark, params = st["mark"][0], dict(st["mark"][1]); params.update(extra)
    light = {k: params[k] for k in ("light_space", "light_azimuth", "light_elevation") if k in params}
    light.setdefault("light_space", "world")
    rows = []
    for sname, cloud, cam in scans:
        sc = pointnpr.Scene(); sc.add_segment("s", pointnpr.Style(mark=(mark, params)), [(cloud, np.eye(4))])
        img = np.asarray(r.render(sc, cam, W, H, background=(1, 1, 1, 0)).color)
        lam = pointnpr.Scene(); lam.add_segment("s", pointnpr.Style(mark=("points", {"shading": "diffuse", "shading_strength": 1.0,
            "color_source": "constant", "color": (1, 1, 1, 1), "point_size": 3.0 if sname != "igea_10pc" else 9.0, **light})), [(cloud, np.eye(4))])
        L = np.asarray(r.render(lam, cam, W, H, background=(1, 1, 1, 0)).color)
        paper = np.asarray(params.get("paper_color", (0.97, 0.96, 0.92, 1.0))[:3])
        lum = img[..., :3] @ [0.2126, 0.7152, 0.0722]
        ink = np.clip(1 - lum / max(paper @ [0.2126, 0.7152, 0.0722], 1e-3), 0, 1) if sum(paper) > 1.5 else np.clip(lum / 1.0, 0, 1)
        cov = (L[..., 3] > 0.5)
        B = 16; hb, wb = H // B, W // B
        def blocks(a): return a[:hb * B, :wb * B].reshape(hb, B, wb, B).mean((1, 3))
        cb = blocks(cov.astype(float)); ib = blocks(ink * cov); lb = blocks((1 - L[..., 0]) * cov)
        m = cb > 0.9
        rr = float(np.corrcoef(ib[m], lb[m])[0, 1]) if m.sum() > 10 else float("nan")
        print(f"{n:18s} {sname:11s} r={rr:+.2f} blocks={int(m.sum())}", flush=True)
        rows.append(np.concatenate([img[..., :3] * img[..., 3:] + (1 - img[..., 3:]), np.repeat(L[..., :1], 3, 2) * L[..., 3:] + (1 - L[..., 3:])], 1))
    pointnpr.save_image(os.path.join(sys.argv[2], n.replace(" ", "_").lower() + ".png"),
                        np.ascontiguousarray(np.concatenate(rows, 0)[::2, ::2]), srgb=True)
