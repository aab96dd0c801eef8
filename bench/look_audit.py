"""The look audit of issue 40: every filter preset on five kinds of real scan
at 1280x720, measured for what an art director sees first.

Scans: the lion (photogrammetry statue), the LiDAR HD tile (aerial, RGB),
Autzen (aerial, RGB, PDAL's sample, sparser), the PCL mug scene (Kinect RGB-D frame), the PCL LMS400 table scene
(terrestrial laser, intensity only) and Stanford's bun000 (one sparse
colourless Cyberware range image). Presets: Toon, Ink outlines,
Watercolor, Oil paint, Posterize, Urban map (its own mark colours by
classification; scans without classes fall back to the points' colour),
and the edge_enhance filter alone (eye-dome lighting and depth lines).

Measures, per scan and preset:
  (a) holes: the points mark alone (the preset's own mark, no filters) is
      rendered; its silhouette (alpha >= 0.5) closed morphologically by a
      disk of radius CLOSE_RADIUS px is the *filled silhouette*. Holes = the
      share of the filled silhouette the preset leaves with alpha < 0.5
      (background). Threshold 0.5 %. Reported with it: the part of those
      holes within 2 CLOSE_RADIUS of covered pixels whose depths differ by
      more than jump() (4.4 % at 1280 px, one surface's steepest change over the disk)
      of the nearest, i.e. where the closing bridged
      two surfaces (an occlusion shadow, a gap between leaves), which a
      depth-aware fill must leave open; "elsewhere" is the rest, the holes
      such a fill may close (judged against the same 0.5 %).
      Holes at the scan's spacing: the same share, of the silhouette closed
      instead by each point's own spacing (its mean distance to its 8
      nearest, the renderer's ScanSampling) in px at its depth
      (spacing_filled): a gap between neighbouring samples wherever the
      scan is, however sparse (up to OWN_CLOSE_MAX px), and not an opening
      wider than them (foliage's gaps and the notches of their borders,
      which the fixed CLOSE_RADIUS counts on a dense scan). Judged against
      the same 0.5 %; printed with the part of it at depth jumps (as above:
      a laser's mixed returns strewn between an edge and what lies behind
      it are no surface to close).
  (b) lines on planes: points whose surface variation (PCA of k = 64
      neighbours, lambda0 / sum) is below PLANAR_VARIATION are planar; the
      flag is rendered as the points' colour (same mark), made the majority
      over a 9x9 box of covered pixels (a noisy Kinect wall has scattered
      non-planar points), kept within the filled silhouette (the gaps
      between an aerial tile's scan lines belong to their plane) and eroded by ERODE_PLANAR px so that true
      silhouettes and creases at a plane's border do not count: the planar
      region. The preset is rendered
      with every point one constant grey (so colour texture draws no lines;
      only gaps and depth can) over white; a line pixel is one darker than
      the grey closing of its 5x5 neighbourhood by more than LINE_CONTRAST
      (a black top-hat: dark features under 5 px wide: dashes, pinholes'
      rims, EDL noise). Lines = the share of the planar region that is line
      pixels. Threshold 1 %. On the aerial tile the planes are roofs and
      ground, so scan-line dashes show here; on the Kinect frame the walls
      and the table.

    PYTHONPATH=build /usr/bin/python3 bench/look_audit.py [out_dir] [--quick] [--tiles]
        [--scan=lion ...] [--preset="Oil paint" ...]

Writes out_dir/look_audit.png (contact sheet: rows = scans, columns = the
points mark then the presets; 1/4 scale), out_dir/look_audit_marked.png
(the same with hole pixels red, dark red at depth jumps, magenta where only the
scan's spacing counts them, and line pixels blue) and prints a markdown
table. `--quick` renders at 640x360; `--tiles` also writes every render and
its marked copy at full size; `--scan=`/`--preset=` pick some (by name).
"""
import os
import sys

import numpy as np

import pointnpr
from pointnpr import presets

W, H = 1280, 720
PRESETS = ["Toon", "Ink outlines", "Flow ink", "Watercolor", "Oil paint", "Flow oil paint", "Posterize", "Urban map",
           "edge_enhance"]
# Not a preset: the depth cues alone (eye-dome lighting and depth lines, defaults), which the issue saw draw line
# noise on flat Kinect walls.
EXTRA = {"edge_enhance": {"mark": ("points", {"point_size": 3.0}), "filters": [("edge_enhance", {})]},
         # Eye-dome lighting alone at Urban map's strength (asked for by name: --preset="EDL 1").
         "EDL 1": {"mark": ("points", {"point_size": 3.0}),
                   "filters": [("edge_enhance", {"edl_strength": 1.0, "outline_width": 0})]}}
CLOSE_RADIUS = 5          # px at 1280x720: closes gaps between splats, not a statue's legs
PLANAR_K, PLANAR_VARIATION = 64, 0.02  # surface variation of 64 neighbours below this: a plane (1/3: isotropic)
PLANAR_MAJORITY = 4       # px: the planar flag is the majority of the covered pixels within this box radius
ERODE_PLANAR = 4          # px kept away from a planar region's border
LINE_CONTRAST = 0.15      # display-sRGB luminance step that makes a line pixel (EDL's contour noise on a Kinect wall
                          # is 0.1 to 0.2; the oil pass's impasto streaks mostly stay under it)
HOLE_LIMIT, LINE_LIMIT = 0.5, 1.0  # percent
SPACING_K = 8             # neighbours of a point's spacing (the renderer's ScanSampling)
OWN_CLOSE_MAX = 16        # px: the widest closing by the scan's spacing (a lone return's gap at most 32 px)
# A hole at a jump between surfaces: the covered pixels within 2 CLOSE_RADIUS of it (the widest gap the closing
# bridges, so both of its sides) include depths farther apart than one surface turned 70 degrees from the view (the
# gap fill's kSteepestSurfaceSlope, tan 70) changes over the disk's diameter: 4 CLOSE_RADIUS px times the pixel's
# footprint (depth x 36 mm / 35 mm / W, the audit's camera) x tan 70, relative to the depth (4.4 %). A fixed 5 % within
# CLOSE_RADIUS counted a bridge's occlusion gap on an aerial tile seen from hundreds of metres, and the middle of a
# stereo camera's 10 px occlusion gap, as one surface's holes.
GRAZING = 2.75
JUMP_RADIUS = 2 * CLOSE_RADIUS
SCANS_DIR = "/work/shared/data/scans"


def jump():
    """The relative depth step of a jump (above) at the current output width
    (--quick halves the width, so a pixel spans twice as much)."""
    return 2 * JUMP_RADIUS * (36.0 / 35.0 / W) * GRAZING


def _local(path, **keep):
    scan = pointnpr.read(path)
    pos = np.asarray(scan.positions, np.float64)
    attrs = {k: np.asarray(scan.attributes[a]) for k, a in keep.items() if a in scan.attributes}
    return pos, attrs


def _frame(pos, direction, up=(0.0, 0.0, 1.0), margin=1.05, eye=None):
    """A camera looking at the points' bounding box from `direction` (or
    from `eye`), far enough for the bounding sphere to fit vertically."""
    lo, hi = np.percentile(pos, 0.5, axis=0), np.percentile(pos, 99.5, axis=0)
    centre = (lo + hi) / 2
    if eye is None:
        d = np.asarray(direction, float)
        d /= np.linalg.norm(d)
        radius = np.linalg.norm(hi - lo) / 2
        half_v = np.arctan(18.0 * H / W / 35.0)
        eye = centre + d * radius / np.tan(half_v) * margin
    dist = np.linalg.norm(np.asarray(eye) - centre)
    return pointnpr.look_at(tuple(eye), tuple(centre), up=up), (dist / 100.0, dist * 10.0)


def scans():
    """(name, positions, attributes, world_from_camera, clip)"""
    pos, at = _local("data/lion_takanawa.ply", colors="colors")
    yield ("lion (photogrammetry)", pos, at,
           pointnpr.look_at((2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)), (0.1, 100.0))
    pos, at = _local("data/lidarhd_myria3d_870000_6618000_subset.las", colors="colors",
                     classification="classification")
    pos -= (pos.min(0) + pos.max(0)) / 2
    yield ("LiDAR HD tile (aerial)", pos, at, pointnpr.look_at((0.0, -70.0, 60.0), (0.0, 0.0, 0.0)), (0.5, 1000.0))
    # A second aerial tile, sparser (about 2.4 ft between neighbours) and from another scanner.
    pos, at = _local(f"{SCANS_DIR}/autzen_trim.las", colors="colors", classification="classification")
    pos -= (pos.min(0) + pos.max(0)) / 2
    cam, clip = _frame(pos, (0.0, -1.0, 0.8), margin=0.6)  # the long tile fills the width
    yield ("Autzen (aerial)", pos, at, cam, clip)
    pos, at = _local(f"{SCANS_DIR}/table_scene_mug_stereo_textured.pcd", colors="colors")
    # The sensor's own view (PCL: +z forward, +y down).
    cam, clip = _frame(pos, None, up=(0.0, -1.0, 0.0), eye=(0.0, 0.0, 0.0))
    yield ("Kinect mug (RGB-D)", pos, at, cam, clip)
    pos, at = _local(f"{SCANS_DIR}/table_scene_lms400.pcd", intensity="intensity")
    cam, clip = _frame(pos, None, up=(0.0, 0.0, 1.0), eye=(0.0, 0.0, 0.0))
    yield ("LMS400 table (terrestrial laser)", pos, at, cam, clip)
    pos, at = _local(f"{SCANS_DIR}/stanford_bunny/bun000.ply")
    cam, clip = _frame(pos, (0.0, 0.0, 1.0), up=(0.0, 1.0, 0.0))
    yield ("bun000 (sparse range scan)", pos, at, cam, clip)


def _cloud(pos, attrs, colors=None):
    centre = (pos.min(0) + pos.max(0)) / 2  # float32 positions stay precise near the origin
    kw = dict(attrs)
    if colors is not None:
        kw = {"colors": colors}
    return pointnpr.PointCloud((pos - centre).astype(np.float32), **kw), centre


def srgb_encode(linear):
    """Display sRGB of linear values: what a point colour must be for the
    linear render to read `linear` (point colours are display sRGB)."""
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)


def spacing_filled(renderer, spacing_cloud, scale, centre, mark, cam, base, base_depth):
    """The silhouette closed by the scan's own spacing: the covered pixels
    of the points whose spacing (mean distance to their SPACING_K nearest,
    as the renderer measures it, here not capped by the neighbours' but at
    4x the scan's median) spans at least k px at their depth,
    closed by a disk of radius k, for every k up to OWN_CLOSE_MAX. So a gap
    is one between neighbouring samples wherever the scan is, and a gap
    wider than the samples' spacing (foliage's openings and the notches of
    their borders, a street between roofs) is not a hole."""
    plain = dict(mark[1], color_source="rgb")
    sp = _render(renderer, spacing_cloud, centre, (mark[0], plain), [], cam)
    cov = base[..., 3] >= 0.5
    pixel = np.where(cov, base_depth, np.inf) * (36.0 / 35.0 / W)
    encoded = srgb_encode(np.clip(sp[..., 0], 0.0, 1.0))  # the renderer reads colours as sRGB: encode back
    radius_px = np.where(cov, encoded * scale / pixel, 0.0)
    out = cov.copy()
    for k in range(1, OWN_CLOSE_MAX + 1):
        seeds = cov & (radius_px >= k)
        if seeds.any():
            out |= erode(dilate(seeds, k), k)
    return out


def _render(renderer, cloud, centre, mark, filters, cam, depth=False):
    scene = pointnpr.Scene()
    m = np.eye(4)
    m[:3, 3] = centre
    scene.add_segment("scan", pointnpr.Style(mark=mark, filters=filters), [(cloud, m)])
    r = renderer.render(scene, cam, W, H)
    color = np.asarray(r.color, np.float32)
    return (color, np.asarray(r.depth, np.float32)) if depth else color


def depth_jumps(color, depth, r):
    """Pixels within `r` of covered pixels whose depths differ by more than
    jump() (relative to the nearest): where a hole may lie between two
    surfaces, which a depth-aware fill must not bridge."""
    cov = color[..., 3] >= 0.5
    near = np.where(cov, depth, np.inf)
    far = np.where(cov, depth, 0.0)
    pad_n, pad_f = np.pad(near, r, constant_values=np.inf), np.pad(far, r)
    lo, hi = pad_n.copy(), pad_f.copy()
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            if dx * dx + dy * dy <= r * r:
                lo = np.minimum(lo, np.roll(np.roll(pad_n, dy, 0), dx, 1))
                hi = np.maximum(hi, np.roll(np.roll(pad_f, dy, 0), dx, 1))
    lo, hi = lo[r:-r, r:-r], hi[r:-r, r:-r]
    return np.isfinite(lo) & (hi > lo * (1.0 + jump()))


def _shift_reduce(mask, radius, op):
    """Morphology by a disk of `radius` px (np.roll; image borders padded)."""
    pad = np.pad(mask, radius, constant_values=op is np.logical_and)
    out = pad.copy()
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            if dx * dx + dy * dy <= radius * radius:
                out = op(out, np.roll(np.roll(pad, dy, 0), dx, 1))
    return out[radius:-radius, radius:-radius]


def dilate(mask, r):
    return _shift_reduce(mask, r, np.logical_or)


def erode(mask, r):
    return _shift_reduce(mask, r, np.logical_and)


def _grey_filter(img, r, op):
    pad = np.pad(img, r, mode="edge")
    out = pad.copy()
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            out = op(out, np.roll(np.roll(pad, dy, 0), dx, 1))
    return out[r:-r, r:-r]


def box_mean(img, r):
    c = np.pad(img, r).cumsum(0).cumsum(1)
    c = np.pad(c, ((1, 0), (1, 0)))
    n = 2 * r + 1
    return (c[n:, n:] - c[:-n, n:] - c[n:, :-n] + c[:-n, :-n]) / (n * n)


def line_pixels(rgba):
    """Dark features under 5 px wide: black top-hat of the luminance over white."""
    a = rgba[..., 3:4]
    rgb = rgba[..., :3] * a + (1.0 - a)
    lum = rgb @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    closing = _grey_filter(_grey_filter(lum, 2, np.maximum), 2, np.minimum)
    return closing - lum > LINE_CONTRAST


def audit_scan(renderer, name, pos, attrs, world_from_camera, clip, preset_names, tiles_dir=None):
    cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                      width=W, height=H)
    cloud, centre = _cloud(pos, attrs)
    variation = pointnpr.curvature((pos - centre).astype(np.float32), k=PLANAR_K)
    planar = (variation < PLANAR_VARIATION).astype(np.float32)
    planar_cloud, _ = _cloud(pos, {}, colors=np.repeat(planar[:, None], 3, 1))
    grey_cloud, _ = _cloud(pos, {}, colors=np.full((len(pos), 3), 0.6, np.float32))
    spacing = np.asarray(pointnpr.local_resolution((pos - centre).astype(np.float32), k=SPACING_K)[0], np.float32)
    spacing_scale = 4.0 * float(np.median(spacing))  # colours hold spacing / scale, up to 4x the median
    spacing_cloud, _ = _cloud(pos, {}, colors=np.repeat(np.clip(spacing / spacing_scale, 0, 1)[:, None], 3, 1))
    rows, tiles, marked = [], [], []
    base_mark = None
    for preset in preset_names:
        spec = EXTRA.get(preset) or presets.PRESETS[preset]
        mark = (spec["mark"][0], dict(spec["mark"][1]))
        if mark != base_mark:  # the filled silhouette and planar region of this mark
            base_mark = mark
            base, base_depth = _render(renderer, cloud, centre, mark, [], cam, depth=True)
            filled = erode(dilate(base[..., 3] >= 0.5, CLOSE_RADIUS), CLOSE_RADIUS)
            jumps = depth_jumps(base, base_depth, JUMP_RADIUS)
            plain = dict(mark[1], color_source="rgb")
            pl = _render(renderer, planar_cloud, centre, (mark[0], plain), [], cam)
            cov = (pl[..., 3] >= 0.5).astype(np.float32)
            flag = box_mean(cov * pl[..., 0], PLANAR_MAJORITY) / np.maximum(box_mean(cov, PLANAR_MAJORITY), 1e-6)
            region = erode(filled & (flag > 0.5), ERODE_PLANAR)
            if not tiles:
                tiles.append(base)
                marked.append(base)
            own = spacing_filled(renderer, spacing_cloud, spacing_scale, centre, mark, cam, base, base_depth)
        img = _render(renderer, cloud, centre, mark, spec["filters"], cam)
        holes = filled & (img[..., 3] < 0.5)
        own_holes = own & (img[..., 3] < 0.5)
        own_pct = 100.0 * own_holes.sum() / max(own.sum(), 1)
        own_jump_pct = 100.0 * (own_holes & jumps).sum() / max(own.sum(), 1)
        grey = _render(renderer, grey_cloud, centre, (mark[0], dict(mark[1], color_source="rgb")), spec["filters"],
                       cam)
        lines = region & line_pixels(grey)
        hole_pct = 100.0 * holes.sum() / max(filled.sum(), 1)
        line_pct = 100.0 * lines.sum() / max(region.sum(), 1)
        jump_pct = 100.0 * (holes & jumps).sum() / max(filled.sum(), 1)
        rows.append((name, preset, hole_pct, jump_pct, own_pct, own_jump_pct, line_pct, int(filled.sum()),
                     int(region.sum())))
        tiles.append(img)
        mk = img.copy()
        mk[own_holes & ~holes] = (1.0, 0.0, 1.0, 1.0)  # a hole at the scan's spacing only: magenta
        mk[holes] = (1.0, 0.0, 0.0, 1.0)
        mk[holes & jumps] = (0.45, 0.0, 0.0, 1.0)  # at a depth jump: dark red
        mk[lines] = (0.0, 0.3, 1.0, 1.0)
        mk[..., :3] = np.where(region[..., None] & ~(holes | lines)[..., None], mk[..., :3] * 0.85 + 0.15 *
                               np.array([0.0, 1.0, 0.0], np.float32), mk[..., :3])
        marked.append(mk)
        if tiles_dir:
            stem = f"{name.split()[0]}_{preset.replace(' ', '_')}"
            pointnpr.save_image(os.path.join(tiles_dir, stem + ".png"), np.ascontiguousarray(img))
            pointnpr.save_image(os.path.join(tiles_dir, stem + "_marked.png"), np.ascontiguousarray(mk))
    return rows, tiles, marked


def sheet(rows_of_tiles, scale=4):
    h, w = H // scale, W // scale
    n_cols = max(len(r) for r in rows_of_tiles)
    out = np.ones((len(rows_of_tiles) * (h + 4), n_cols * (w + 4), 3), np.float32)
    for r, tiles in enumerate(rows_of_tiles):
        for c, img in enumerate(tiles):
            a = img[..., 3:4]
            rgb = img[..., :3] * a + (1.0 - a)
            small = rgb[:h * scale, :w * scale].reshape(h, scale, w, scale, 3).mean((1, 3))
            rr = len(rows_of_tiles) - 1 - r  # save_image writes bottom row first
            out[rr * (h + 4) + 2:rr * (h + 4) + 2 + h, c * (w + 4) + 2:c * (w + 4) + 2 + w] = small
    return np.ascontiguousarray(out)


def main():
    global W, H
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    out_dir = args[0] if args else "."
    if "--quick" in sys.argv:
        W, H = 640, 360
    only = [a.split("=", 1)[1] for a in sys.argv if a.startswith("--scan=")]
    presets_run = [a.split("=", 1)[1] for a in sys.argv if a.startswith("--preset=")] or PRESETS
    os.makedirs(out_dir, exist_ok=True)
    renderer = pointnpr.Renderer()
    print(f"{W}x{H}; holes: % of the filled silhouette (closing r={CLOSE_RADIUS} px) left with alpha < 0.5 "
          f"(limit {HOLE_LIMIT} %); lines: % of the planar region (variation < {PLANAR_VARIATION}, eroded "
          f"{ERODE_PLANAR} px) darker than its 5x5 closing by > {LINE_CONTRAST} on constant-grey input "
          f"(limit {LINE_LIMIT} %)")
    print("| scan | preset | holes % | of which at depth jumps % | elsewhere % | holes at the scan's spacing % | "
          "lines on planes % | filled px | planar px |")
    print("|---|---|---|---|---|---|---|---|---|")
    all_tiles, all_marked, fails, fails_elsewhere, fails_own = [], [], 0, 0, 0
    for name, pos, attrs, cam, clip in scans():
        if only and not any(o.lower() in name.lower() for o in only):
            continue
        rows, tiles, marked = audit_scan(renderer, name, pos, attrs, cam, clip, presets_run,
                                         out_dir if "--tiles" in sys.argv else None)
        for scan, preset, hole_pct, jump_pct, own_pct, own_jump_pct, line_pct, nf, npl in rows:
            flag_h = "" if hole_pct <= HOLE_LIMIT else " ✗"
            flag_l = "" if line_pct <= LINE_LIMIT else " ✗"
            # The holes a depth-aware fill may close: those not between two surfaces.
            flag_e = "" if hole_pct - jump_pct <= HOLE_LIMIT else " ✗"
            flag_o = "" if own_pct <= HOLE_LIMIT else " ✗"
            fails += bool(flag_h) + bool(flag_l)
            fails_elsewhere += bool(flag_e) + bool(flag_l)
            fails_own += bool(flag_o) + bool(flag_l)
            print(f"| {scan} | {preset} | {hole_pct:.2f}{flag_h} | {jump_pct:.2f} | "
                  f"{hole_pct - jump_pct:.2f}{flag_e} | {own_pct:.2f}{flag_o} ({own_jump_pct:.2f} at jumps) | "
                  f"{line_pct:.2f}{flag_l} | {nf:,} | "
                  f"{npl:,} |", flush=True)
        all_tiles.append(tiles)
        all_marked.append(marked)
    pointnpr.save_image(os.path.join(out_dir, "look_audit.png"), sheet(all_tiles))
    pointnpr.save_image(os.path.join(out_dir, "look_audit_marked.png"), sheet(all_marked))
    print(f"{fails} measures over their limit ({fails_elsewhere} with the holes at depth jumps left out, "
          f"{fails_own} with the holes at the scan's spacing)")


if __name__ == "__main__":
    main()
