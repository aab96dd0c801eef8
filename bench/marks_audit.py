"""The marks' look audit of issue 39: every mark preset (hatching, stipples,
feature strokes, brush splats) on six real scans of five kinds at 1280x720,
measured for what an art director sees first. The scans are the filters'
audit's (bench/look_audit.py: the lion, the LiDAR HD tile, the Kinect mug
frame, the LMS400 table, bun000) and a 10 % subsample of Igea (the sparse
case the brush's acceptance names).

Measures, per scan and preset (the preset whole: its mark and its filters):
  holes:  the points mark (3 px) closed by a disk of CLOSE_RADIUS px is the
          filled silhouette; holes = its share the preset leaves with alpha
          < 0.5. The brush's limit is HOLE_LIMIT (it is meant to cover the
          surface); for the ink marks paper showing is the look, so only
          reported.
  stray:  pixels the preset draws (alpha > STRAY_ALPHA) farther than
          STRAY_PX from the points' own coverage (each point a disc of twice
          the scan's median spacing, points beyond the frame's edge
          included: `coverage`), in per mille of the drawn pixels and as a
          count. Limit: none drawn.
  r:      ink against Lambert shading: the block correlation (16 px blocks
          fully covered) of the preset's ink (1 - luminance / paper, or
          luminance on dark paper) with the points mark's diffuse shading
          of a white scan under the preset's own light (its light_space,
          azimuth and elevation, defaults included; a stipple preset's
          highlight included: lambert_reference). Limit R_LIMIT for
          hatching, stipples and feature strokes. A light drawing (chalk on
          its board: LIGHT_DRAWINGS) is measured against the light instead.
  highlight (stipples with `specular`): ink on the lit side (N.L >= 0.5,
          N.H < 0.8 under the preset's light) minus ink where N.H >= 0.95,
          with the highlight and with the same preset's specular off; the
          highlight must add HIGHLIGHT_LIMIT (printed after the table).
  flicker (--orbit): a slow orbit (ORBIT_FRAMES frames, ORBIT_STEP degrees
          about the camera's up axis through the scan's centre) at half size;
          the mean reprojected frame-to-frame change over the frame's own
          detail (bench/filter_flicker.py's measure), over the points
          mark's (lit by diffuse shading on a colourless scan, whose flat
          grey has no detail). Limit FLICKER_LIMIT.

    PYTHONPATH=build python3 bench/marks_audit.py OUT_DIR [--orbit] [--scan=kinect ...] [--preset=Pencil ...]
        [--set='{"light_space": "camera"}']   (parameters laid over every preset: a trial)

Writes OUT_DIR/marks_<mark>.png (a contact sheet per mark, labelled with
oiiotool: rows = scans, columns = the points mark then the mark's presets;
1/4 scale; stray pixels magenta) and prints a markdown table.
"""
import json
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pointnpr  # noqa: E402
from pointnpr import presets  # noqa: E402

import filter_flicker  # noqa: E402
import look_audit as la  # noqa: E402

W, H = la.W, la.H
MARKS = ("hatching", "stipples", "feature_strokes", "brush_splats")
CLOSE_RADIUS = la.CLOSE_RADIUS
STRAY_PX, STRAY_ALPHA = 12, 0.05
COVER_MARGIN = 64  # px: beyond the largest mark's reach (a brush's 3x elongation)
HOLE_LIMIT, R_LIMIT, FLICKER_LIMIT = 1.0, 0.7, 1.1
HIGHLIGHT_LIMIT = 0.05  # ink: the highlight at least this much brighter against the lit side than without it


def SURFACE(spacing):
    """The points mark drawn as the scan's surface: discs twice its median
    spacing across, so a sparse scan's back points do not show through the
    gaps of its front (the Lambert reference is the front surface's)."""
    return {"size_mode": "world", "world_size": 2.0 * spacing}
BLOCK = 16
ORBIT_FRAMES, ORBIT_STEP = 6, 0.5
LIGHT_DRAWINGS = {"Chalk"}  # its X-Toon draws light strokes where lit (docs/marks.md)
LUMA = np.array([0.2126, 0.7152, 0.0722], np.float32)


def scans():
    yield from la.scans()
    scan = pointnpr.read(f"{la.SCANS_DIR}/igea.ply")
    pos = np.asarray(scan.positions, np.float64)[::10]
    cam, clip = la._frame(pos, (0.3, -1.0, 0.3))
    yield ("Igea 10 % (sparse photogrammetry)", pos, {}, cam, clip)


def light_of(mark, params):
    """The preset's light with the mark's defaults filled in."""
    defaults = {p["name"]: p["default"] for p in pointnpr.schema(mark, "mark")["params"]}
    return {k: params.get(k, defaults[k]) for k in ("light_space", "light_azimuth", "light_elevation")
            if k in defaults}


def highlight_of(mark, params):
    """A stipple preset's highlight (specular_share, tau), or None."""
    if mark != "stipples" or not params.get("specular"):
        return None
    defaults = {p["name"]: p["default"] for p in pointnpr.schema(mark, "mark")["params"]}
    return (params.get("specular_share", defaults["specular_share"]), params.get("tau", defaults["tau"]))


def ink_of(img, mark, params):
    """Ink per pixel in [0, 1]: how far the drawing is from its paper."""
    defaults = {p["name"]: p["default"] for p in pointnpr.schema(mark, "mark")["params"]}
    paper = np.asarray(params.get("paper_color", defaults.get("paper_color", (1.0, 1.0, 1.0, 1.0)))[:3], np.float32)
    a = img[..., 3:4]
    rgb = img[..., :3] * a + paper * (1.0 - a)  # composited over its own paper
    lum, paper_lum = rgb @ LUMA, max(float(paper @ LUMA), 1e-3)
    return np.clip(1.0 - lum / paper_lum, 0, 1) if paper_lum > 0.5 else np.clip(lum, 0, 1)


def blocks(a):
    hb, wb = H // BLOCK, W // BLOCK
    return a[:hb * BLOCK, :wb * BLOCK].reshape(hb, BLOCK, wb, BLOCK).mean((1, 3))


def colour_led(mark, params):
    """Whether the preset's strokes take the scan's own colours (hatching's
    `coloring` `point`): its tone is then the coloured surface's under the
    light, Lambert's albedo x N.L, not a white surface's."""
    return mark == "hatching" and params.get("coloring") == "point"


def tone_r(ink, lambert, filled, albedo=None):
    """Blocks fully inside the filled silhouette; the shading is averaged over
    the pixels its points cover (a sparse scan's 3 px points leave gaps).
    With `albedo` (the scan's colours drawn as the same surface, linear) the
    reference is the shaded colour's luminance."""
    if albedo is not None:
        lambert = lambert.copy()
        lambert[..., 0] *= albedo[..., :3] @ LUMA
    covered = filled & (lambert[..., 3] >= 0.5)
    full = blocks(filled.astype(np.float32)) > 0.9
    lit = blocks(covered.astype(np.float32))
    full &= lit > 0
    if full.sum() < 10:
        return float("nan")
    ib = blocks(ink * filled) / np.maximum(blocks(filled.astype(np.float32)), 1e-6)
    lb = blocks((1.0 - lambert[..., 0]) * covered) / np.maximum(lit, 1e-6)
    return float(np.corrcoef(ib[full], lb[full])[0, 1])


def orbit(world_from_camera, pivot, k):
    """The camera turned by k * ORBIT_STEP degrees about its own up axis
    through `pivot`."""
    m = np.asarray(world_from_camera, np.float64)
    up = m[:3, 1] / np.linalg.norm(m[:3, 1])
    a = np.radians(ORBIT_STEP * k)
    kx = np.array([[0, -up[2], up[1]], [up[2], 0, -up[0]], [-up[1], up[0], 0]])
    rot = np.eye(3) + np.sin(a) * kx + (1 - np.cos(a)) * kx @ kx
    out = m.copy()
    out[:3, :3] = rot @ m[:3, :3]
    out[:3, 3] = pivot + rot @ (m[:3, 3] - pivot)
    return out


def flicker(renderer, cloud, centre, mark, filters, world_from_camera, clip):
    """Reprojected frame-to-frame change over spatial detail (filter_flicker's
    measure) on a slow orbit at half size."""
    w, h = W // 2, H // 2
    filter_flicker.W, filter_flicker.H, filter_flicker.LENS = w, h, 35.0
    m = np.asarray(world_from_camera, np.float64)
    pivot = m[:3, 3] - m[:3, 2] * np.linalg.norm(m[:3, 3] - centre)  # the point the camera looks at
    cams = [orbit(m, pivot, k) for k in range(ORBIT_FRAMES)]
    scene = pointnpr.Scene()
    shift = np.eye(4)
    shift[:3, 3] = centre
    scene.add_segment("scan", pointnpr.Style(mark=mark, filters=filters), [(cloud, shift)])
    frames = [renderer.render(scene, pointnpr.Camera.perspective(c, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                                                 width=w, height=h), w, h) for c in cams]
    mads = [filter_flicker.reprojected_mad(frames[k], frames[k + 1], cams[k], cams[k + 1])[0]
            for k in range(ORBIT_FRAMES - 1)]
    detail = float(np.mean([filter_flicker.spatial_mad(f) for f in frames[1:]]))
    return float(np.mean(mads)) / detail if detail > 0 else float("nan")


def light_world(light, world_from_camera):
    """Toward the light in world axes (render/mark.cpp's view_light_direction)."""
    a, e = np.radians(light.get("light_azimuth", 135.0)), np.radians(light.get("light_elevation", 45.0))
    if light.get("light_space") == "camera":  # elevation away from the view axis, azimuth around it
        return np.asarray(world_from_camera)[:3, :3] @ np.array([np.sin(e) * np.cos(a), np.sin(e) * np.sin(a),
                                                                  np.cos(e)])
    return np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])


def grey_cloud(pos, grey):
    """The scan with `grey` (linear, per point) as its colour."""
    srgb = la.srgb_encode(grey).astype(np.float32)  # so the linear render reads `grey`
    return la._cloud(pos, {}, colors=np.repeat(srgb[:, None], 3, axis=1))[0]


def n_dot_h(pos, normals, light, world_from_camera):
    to_eye = np.asarray(world_from_camera)[:3, 3] - pos
    to_eye /= np.linalg.norm(to_eye, axis=1)[:, None]
    half = light_world(light, world_from_camera) + to_eye
    return np.clip(np.sum(normals * half, axis=1) / np.linalg.norm(half, axis=1), 0.0, 1.0)


def lambert_reference(pos, centre, normals, light, world_from_camera, highlight=None):
    """A white scan lit by the preset's light as a surface seen from the
    camera: each point's normal turned toward the camera (the side it shows
    it), max(N.L, 0) as its grey. A surface turned away from a light behind
    it is dark (|N.L|, the points mark's two-sided shading, lit it). With
    `highlight` (specular_share, tau: a stipple preset's highlight), the
    diffuse term gives up that share to clamp(1 - (1 - N.H) / tau, 0, 1),
    the highlight the preset draws (marks.md, the stipples' specular)."""
    shade = np.clip(normals @ light_world(light, world_from_camera), 0.0, 1.0)
    if highlight is not None:
        share, tau = highlight
        spec = np.clip(1.0 - (1.0 - n_dot_h(pos, normals, light, world_from_camera)) / tau, 0.0, 1.0)
        shade = np.clip((1.0 - share) * shade + spec, 0.0, 1.0)
    return grey_cloud(pos, shade)


def half_way_reference(pos, centre, normals, light, world_from_camera):
    """N.H per point (H half-way between the preset's light and the eye), as
    a grey the points mark draws: where a highlight belongs."""
    return grey_cloud(pos, n_dot_h(pos, normals, light, world_from_camera))


def highlight(ink, lambert, half, filled):
    """Ink where the highlight belongs (N.H >= 0.95) and on the rest of the
    lit side (N.L >= 0.5, N.H < 0.8): (lit - high), how much brighter the
    highlight is than the light around it."""
    covered = filled & (half[..., 3] >= 0.5)
    high, lit = covered & (half[..., 0] >= 0.95), covered & (lambert[..., 0] >= 0.5) & (half[..., 0] < 0.8)
    if high.sum() < 100 or lit.sum() < 100:
        return float("nan")
    return float(ink[lit].mean() - ink[high].mean())


def median_spacing(pos, centre):
    """The scan's median spacing: the mean distance to 8 neighbours."""
    r, _eps = pointnpr.local_resolution(np.asarray(pos - centre, np.float64), 8)
    return float(np.median(r))


def coverage(renderer, cloud, spacing, centre, world_from_camera, clip, reach=0):
    """The points' own coverage grown by `reach` px: each point a disc as
    wide as twice the scan's median spacing (its typical neighbourhood, so
    a sparse surface near the camera closes and an isolated point stays
    small), drawn on a frame COVER_MARGIN px larger on every side with the
    same pixel scale, grown there (points just outside the picture reach
    into it), then cropped."""
    w, h = W + 2 * COVER_MARGIN, H + 2 * COVER_MARGIN
    wide = pointnpr.Camera.perspective(world_from_camera, lens=35.0 * W / w, clip_start=clip[0], clip_end=clip[1],
                                       width=w, height=h)
    scene = pointnpr.Scene()
    shift = np.eye(4)
    shift[:3, 3] = centre
    discs = {"size_mode": "world", "world_size": 2.0 * spacing}
    scene.add_segment("scan", pointnpr.Style(mark=("points", discs)), [(cloud, shift)])
    covered = np.asarray(renderer.render(scene, wide, w, h).color)[..., 3] > 0
    if reach:
        covered = la.dilate(covered, reach)
    return covered[COVER_MARGIN:COVER_MARGIN + H, COVER_MARGIN:COVER_MARGIN + W]


def audit_scan(renderer, name, pos, attrs, world_from_camera, clip, preset_names, with_orbit, overlay):
    cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                      width=W, height=H)
    cloud, centre = la._cloud(pos, attrs)
    eye = np.asarray(world_from_camera)[:3, 3]
    normals = pointnpr.estimate_normals(np.asarray(pos - centre, np.float64), 16, orient_toward=eye - centre)
    base = la._render(renderer, cloud, centre, ("points", {"point_size": 3.0}), [], cam)
    filled = la.erode(la.dilate(base[..., 3] >= 0.5, CLOSE_RADIUS), CLOSE_RADIUS)
    spacing = median_spacing(pos, centre)
    near = coverage(renderer, cloud, spacing, centre, world_from_camera, clip, STRAY_PX)
    # The baseline of a colourless scan is its lit shape (flat grey has no detail to compare with).
    lit = {} if attrs else {"shading": "diffuse"}
    base_flicker = flicker(renderer, cloud, centre, ("points", {**SURFACE(spacing), **lit}), [], world_from_camera,
                           clip) if with_orbit else None
    albedo = la._render(renderer, cloud, centre, ("points", SURFACE(spacing)), [], cam)
    rows, tiles = [], {m: [base] for m in MARKS}
    for preset in preset_names:
        spec = presets.PRESETS[preset]
        mark, params = spec["mark"][0], dict(spec["mark"][1])
        known = {p["name"] for p in pointnpr.schema(mark, "mark")["params"]}
        params.update({k: v for k, v in overlay.items() if k in known})
        img = la._render(renderer, cloud, centre, (mark, params), spec["filters"], cam)
        drawn = img[..., 3] > STRAY_ALPHA
        stray = drawn & ~near
        holes = filled & (img[..., 3] < 0.5)
        lit_scan = lambert_reference(pos, centre, normals, light_of(mark, params), world_from_camera,
                                     highlight_of(mark, params))
        lambert = la._render(renderer, lit_scan, centre, ("points", {"color_source": "rgb", **SURFACE(spacing)}), [],
                             cam)
        r = tone_r(ink_of(img, mark, params), lambert, filled, albedo if colour_led(mark, params) else None)
        r = -r if preset in LIGHT_DRAWINGS else r
        shine = None
        if mark == "stipples" and params.get("specular"):
            half = la._render(renderer, half_way_reference(pos, centre, normals, light_of(mark, params),
                                                           world_from_camera), centre,
                              ("points", {"color_source": "rgb", **SURFACE(spacing)}), [], cam)
            matte = la._render(renderer, cloud, centre, (mark, dict(params, specular=False)), spec["filters"], cam)
            diffuse = la._render(renderer, lambert_reference(pos, centre, normals, light_of(mark, params),
                                                             world_from_camera), centre,
                                 ("points", {"color_source": "rgb", **SURFACE(spacing)}), [], cam)
            shine = (highlight(ink_of(img, mark, params), diffuse, half, filled),
                     highlight(ink_of(matte, mark, params), diffuse, half, filled))
        fl = (flicker(renderer, cloud, centre, (mark, params), spec["filters"], world_from_camera, clip) / base_flicker
              if with_orbit else float("nan"))
        rows.append(dict(scan=name, preset=preset, mark=mark, holes=100.0 * holes.sum() / max(filled.sum(), 1),
                         stray=int(stray.sum()), stray_pm=1000.0 * stray.sum() / max(drawn.sum(), 1), r=r,
                         flicker=fl, highlight=shine))
        mk = img.copy()
        mk[stray] = (1.0, 0.0, 1.0, 1.0)
        tiles[mark].append(mk)
    return rows, tiles


def label_sheet(path, scan_names, column_names, scale=4):
    """Names each tile of a contact sheet (la.sheet's layout): the column's
    style at its top, the scan in the first column."""
    w, h = W // scale + 4, H // scale + 4
    found = subprocess.run(["fc-match", "-f", "%{file}", "sans"], capture_output=True, text=True)
    font = found.stdout.strip() if found.returncode == 0 else ""
    if not font:
        print(f"(no font found by fc-match: {path} left unlabelled)")
        return
    args = ["oiiotool", path]
    for r, scan in enumerate(scan_names):
        for c, column in enumerate(column_names):
            text = f"{scan}: {column}" if c == 0 else column
            args += [f"--text:x={c * w + 6}:y={r * h + 16}:size=13:color=0.8,0.1,0.1:font={font}", text]
    subprocess.run(args + ["-o", path], check=True)


def verdict(row):
    bad = []
    if row["mark"] == "brush_splats" and row["holes"] > HOLE_LIMIT:
        bad.append("holes")
    if row["stray"] > 0:
        bad.append("stray")
    if row["mark"] != "brush_splats" and not row["r"] >= R_LIMIT:
        bad.append("r")
    if row["flicker"] == row["flicker"] and row["flicker"] > FLICKER_LIMIT:
        bad.append("flicker")
    if row["highlight"] is not None and not row["highlight"][0] - row["highlight"][1] >= HIGHLIGHT_LIMIT:
        bad.append("highlight")
    return bad


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    out_dir = args[0] if args else "."
    only = [a.split("=", 1)[1] for a in sys.argv if a.startswith("--scan=")]
    picked = [a.split("=", 1)[1] for a in sys.argv if a.startswith("--preset=")]
    names = [n for n, s in presets.PRESETS.items() if s["mark"][0] in MARKS and (not picked or n in picked)]
    with_orbit = "--orbit" in sys.argv
    overlay = {}
    for a in sys.argv:
        if a.startswith("--set="):
            overlay.update(json.loads(a.split("=", 1)[1]))
    os.makedirs(out_dir, exist_ok=True)
    renderer = pointnpr.Renderer()
    print(f"{W}x{H}; holes: % of the filled silhouette (closing r={CLOSE_RADIUS} px) with alpha < 0.5 (brush limit "
          f"{HOLE_LIMIT} %); stray: pixels drawn > {STRAY_PX} px from the points (limit 0); r: ink vs Lambert, "
          f"{BLOCK} px blocks (limit {R_LIMIT}); flicker: vs the points mark (limit {FLICKER_LIMIT}x)")
    print("| scan | preset | holes % | stray px (‰ of drawn) | ink vs Lambert r | flicker vs points | over |")
    print("|---|---|---|---|---|---|---|")
    sheets, fails, sheet_scans, highlights = {m: [] for m in MARKS}, 0, [], []
    for name, pos, attrs, cam, clip in scans():
        if only and not any(o.lower() in name.lower() for o in only):
            continue
        rows, tiles = audit_scan(renderer, name, pos, attrs, cam, clip, names, with_orbit, overlay)
        highlights += [row for row in rows if row["highlight"] is not None]
        for row in rows:
            bad = verdict(row)
            fails += len(bad)
            print(f"| {row['scan']} | {row['preset']} | {row['holes']:.2f} | {row['stray']} ({row['stray_pm']:.2f}) | "
                  f"{row['r']:+.2f} | {row['flicker']:.2f} | {', '.join(bad)} |", flush=True)
        for mark, t in tiles.items():
            if len(t) > 1:
                sheets[mark].append(t)
        sheet_scans.append(name)
    for mark, rows_of_tiles in sheets.items():
        if rows_of_tiles:
            path = os.path.join(out_dir, f"marks_{mark}.png")
            pointnpr.save_image(path, la.sheet(rows_of_tiles))
            label_sheet(path, sheet_scans, ["points (3 px)"] + [n for n in names if presets.PRESETS[n]["mark"][0] == mark])
    print(f"{fails} measures over their limit")
    print("\nHighlights (stipples with specular): ink on the lit side (N.L >= 0.5, N.H < 0.8) minus ink where "
          "N.H >= 0.95, with the highlight and without it (the same preset, specular off)")
    for row in highlights:
        print(f"| {row['scan']} | {row['preset']} | {row['highlight'][0]:+.3f} | {row['highlight'][1]:+.3f} |")


if __name__ == "__main__":
    main()
