"""Speed against error (issue 14): for each knob that trades quality for
time, the image error against the full-quality render of the same frame and
the time it costs, measured in one run on this machine.

    PYTHONPATH=build:bench /usr/bin/python3 bench/speed_vs_error.py [--out docs/images] [--quick]

Studies (each a table on stdout and a plot, speed_vs_error_<study>.png):
  budget      the frame's point budget (level of detail), aerial 3M points
  viewport    the viewport's reduced resolution, upscaled as it is drawn
  rasterizer  the points mark's rasterizers against each other
  filters     cartoon smoothing iterations, Kuwahara radius
  normals     k of the normal estimation: angular error against ms
  packing     the 8-bit normal packing: angle and Lambert shading error
  inpaint     the inpainting radius: wrong-segment pixels against ms (Fig. 12)

Image error: mean CIE76 delta E (CIELAB, D65) of the display sRGB images
composited over white, and the percentage of pixels where a channel differs
by more than 2/255. Times: CPU ms per frame (the process's, every thread),
best of REPEATS frames after a warm-up frame; normal estimation: wall ms.
"""
import os
import sys
import time

import numpy as np

import pointnpr

QUICK = "--quick" in sys.argv
REPEATS = 2 if QUICK else 3
OUT = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else None
W, H = 1920, 1080


# -- image error --------------------------------------------------------------

def display_srgb(result):
    """The frame over white, as display sRGB in [0, 1] (H, W, 3)."""
    c = np.asarray(result.color, np.float64)
    rgb = c[..., :3] + (1.0 - c[..., 3:4])  # premultiplied over white
    rgb = np.clip(rgb, 0.0, 1.0)
    return np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * rgb ** (1 / 2.4) - 0.055)


def lab(srgb):
    lin = np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)
    m = np.array([[0.4124564, 0.3575761, 0.1804375], [0.2126729, 0.7151522, 0.0721750],
                  [0.0193339, 0.1191920, 0.9503041]])
    xyz = lin @ m.T / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.stack([116 * f[..., 1] - 16, 500 * (f[..., 0] - f[..., 1]), 200 * (f[..., 1] - f[..., 2])], -1)


def image_error(img, ref):
    """(mean delta E, % of pixels with a channel off by more than 2/255)."""
    de = np.linalg.norm(lab(img) - lab(ref), axis=-1).mean()
    off = (np.abs(np.round(img * 255) - np.round(ref * 255)) > 2).any(-1).mean() * 100.0
    return float(de), float(off)


def timed(render):
    """(best CPU ms of the frame, last result) after a warm-up frame. CPU
    time of the process, all threads (llvmpipe's included): steadier than
    wall time on a machine shared with other work, and on two cores about
    twice the wall time of an idle machine."""
    render()
    best, result = None, None
    for _ in range(REPEATS):
        t0 = time.process_time()
        result = render()
        ms = (time.process_time() - t0) * 1e3
        best = ms if best is None else min(best, ms)
    return best, result


# -- plots ---------------------------------------------------------------------

def plot(study, title, series, xlabel="CPU ms per frame", ylabel="mean delta E (CIELAB)", labels=None):
    """series: name -> list of (x, y); labels: name -> list of point labels."""
    if OUT is None:
        return
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    for name, points in series.items():
        xs, ys = zip(*points)
        ax.plot(xs, ys, "o-", label=name)
        for (x, y), text in zip(points, (labels or {}).get(name, [])):
            ax.annotate(text, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    if len(series) > 1:
        ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(OUT, f"speed_vs_error_{study}.png")
    fig.savefig(path)
    plt.close(fig)
    print(f"plot: {path}\n")


def table(header, rows):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(r) + " |")
    print(flush=True)


# -- scenes --------------------------------------------------------------------

def aerial():
    """The 3M-point aerial scene of bench/bench_marks.py (--aerial)."""
    import bench_marks
    argv = sys.argv
    sys.argv = [argv[0], "--aerial"]
    try:
        name, cloud, cam = bench_marks.clouds()[-1]
    finally:
        sys.argv = argv
    return name, cloud, cam


def lion():
    import bench_marks
    return bench_marks.clouds()[0]


def one_segment(cloud, mark=("points", {}), filters=()):
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=mark, filters=list(filters)), [cloud])
    return scene


# -- studies -------------------------------------------------------------------

def study_budget(renderer):
    name, cloud, cam = aerial()
    print(f"## Point budget: {name}, points mark (2 px), {W}x{H}\n")
    scene = one_segment(cloud)
    full_ms, full = timed(lambda: renderer.render(scene, cam, W, H))
    ref = display_srgb(full)
    rows, points, labels = [], [], []
    budgets = [100_000, 300_000, 1_000_000, 2_000_000] if QUICK else \
        [100_000, 250_000, 500_000, 1_000_000, 1_500_000, 2_000_000, 2_500_000]
    for budget in budgets:
        ms, r = timed(lambda: renderer.render(scene, cam, W, H, point_budget=budget))
        de, off = image_error(display_srgb(r), ref)
        drawn = r.stats["point_budget_points"]
        rows.append([f"{budget:,}", f"{drawn / cloud.num_points:.0%}", f"{ms:.0f}", f"{de:.2f}", f"{off:.1f}"])
        points.append((ms, de))
        labels.append(f"{budget / 1e6:g}M")
    rows.append([f"all ({cloud.num_points:,})", "100%", f"{full_ms:.0f}", "0", "0"])
    points.append((full_ms, 0.0))
    labels.append("all")
    table(["budget", "points drawn", "CPU ms", "mean dE", "% px > 2/255"], rows)
    plot("budget", f"Point budget, {name}, {W}x{H}", {"point budget": points}, labels={"point budget": labels})


def upscale(small, factor, w, h):
    """Bilinear upscaling to w x h, as a texture drawn at the region's size."""
    sh, sw = small.shape[:2]
    ys = np.clip((np.arange(h) + 0.5) / factor - 0.5, 0, sh - 1)
    xs = np.clip((np.arange(w) + 0.5) / factor - 0.5, 0, sw - 1)
    y0, x0 = np.floor(ys).astype(int), np.floor(xs).astype(int)
    y1, x1 = np.minimum(y0 + 1, sh - 1), np.minimum(x0 + 1, sw - 1)
    fy, fx = (ys - y0)[:, None, None], (xs - x0)[None, :, None]
    top = small[y0][:, x0] * (1 - fx) + small[y0][:, x1] * fx
    bottom = small[y1][:, x0] * (1 - fx) + small[y1][:, x1] * fx
    return top * (1 - fy) + bottom * fy


def study_viewport(renderer):
    name, cloud, cam_full = lion()
    print(f"## Viewport resolution: {name}, cartoon, {W}x{H} region\n")
    scene = one_segment(cloud, ("points", {"point_size": 3}), [("cartoon", {})])
    rows, series, labels = [], {"cartoon": []}, {"cartoon": []}
    full_ms, full = timed(lambda: renderer.render(scene, cam_full, W, H))
    ref = display_srgb(full)
    import bench_marks
    for factor in (2, 3, 4, 6, 8):
        w, h = W // factor, H // factor
        cam = pointnpr.Camera.perspective(pointnpr.look_at(bench_marks.EYE, bench_marks.TARGET), lens=35.0,
                                          clip_start=0.1, clip_end=100.0, width=w, height=h)
        ms, r = timed(lambda: renderer.render(scene, cam, w, h))
        img = upscale(display_srgb(r), W / w, W, H)
        de, off = image_error(img, ref)
        rows.append([f"1/{factor}", f"{w}x{h}", f"{ms:.0f}", f"{de:.2f}", f"{off:.1f}"])
        series["cartoon"].append((ms, de))
        labels["cartoon"].append(f"1/{factor}")
    rows.append(["1", f"{W}x{H}", f"{full_ms:.0f}", "0", "0"])
    series["cartoon"].append((full_ms, 0.0))
    labels["cartoon"].append("1")
    table(["resolution", "rendered", "CPU ms", "mean dE", "% px > 2/255"], rows)
    plot("viewport", f"Viewport resolution, {name}, cartoon, upscaled to {W}x{H}", series, labels=labels)


def study_rasterizer(renderer):
    rasterizers = [p for p in next(s for s in pointnpr.schemas() if s["id"] == "points")["params"]
                   if p["name"] == "rasterizer"][0]["items"]
    rows, series, labels = [], {}, {}
    for name, cloud, cam in (lion(), aerial()):
        print(f"## Rasterizers: {name}, points mark, {W}x{H}\n")
        results = {}
        for size in (1.0, 2.0, 3.0):
            for rast in rasterizers:
                scene = one_segment(cloud, ("points", {"rasterizer": rast, "point_size": size}))
                results[(rast, size)] = timed(lambda: renderer.render(scene, cam, W, H))
            ref = display_srgb(results[("compute", size)][1])
            for rast in rasterizers:
                ms, r = results[(rast, size)]
                de, off = image_error(display_srgb(r), ref)
                rows.append([name, f"{size:g}", rast, f"{ms:.0f}", f"{cloud.num_points / ms / 1e3:.1f}",
                             f"{de:.3f}", f"{off:.2f}"])
                if rast != "auto":  # the plot: auto is native here, or compute on a GPU
                    series.setdefault(f"{rast}, {name}", []).append((ms, de))
                    labels.setdefault(f"{rast}, {name}", []).append(f"{size:g}px")
    table(["cloud", "px", "rasterizer", "frame CPU ms", "M points per CPU s", "mean dE vs compute",
           "% px > 2/255"], rows)
    plot("rasterizer", f"Rasterizers against compute, {W}x{H}", series, labels=labels)


def study_filters(renderer):
    name, cloud, cam = lion()
    print(f"## Filters: {name}, points (3 px), {W}x{H}\n")
    cases = {
        "cartoon smoothing": ("cartoon", "smoothing", [0, 1, 2, 3], 4),
        "kuwahara radius": ("kuwahara", "radius", [2.0, 3.0, 4.0, 6.0, 8.0], 10.0),
    }
    rows, series, labels = [], {}, {}
    for label, (fid, param, values, best) in cases.items():
        def render(v):
            scene = one_segment(cloud, ("points", {"point_size": 3}), [(fid, {param: v})])
            return timed(lambda: renderer.render(scene, cam, W, H))
        ref_ms, ref_r = render(best)
        ref = display_srgb(ref_r)
        for v in values:
            ms, r = render(v)
            de, off = image_error(display_srgb(r), ref)
            rows.append([fid, f"{param} = {v:g}", f"{ms:.0f}", f"{de:.2f}", f"{off:.1f}"])
            series.setdefault(label, []).append((ms, de))
            labels.setdefault(label, []).append(f"{v:g}")
        rows.append([fid, f"{param} = {best:g} (reference)", f"{ref_ms:.0f}", "0", "0"])
        series[label].append((ref_ms, 0.0))
        labels[label].append(f"{best:g}")
    table(["filter", "setting", "CPU ms", "mean dE", "% px > 2/255"], rows)
    plot("filters", f"Filter settings against their most expensive, {name}", series, labels=labels)


def study_normals():
    from synthetic_shapes import angles, shapes
    rng = np.random.default_rng(0)
    n = 50_000 if QUICK else 200_000
    print(f"## Normal estimation: k against angular error, synthetic shapes of {n:,} points\n")
    rows, series, labels = [], {}, {}
    for shape, (p, truth) in shapes(n, rng).items():
        for k in (4, 6, 10, 16, 24, 32, 48):
            t = None
            for _ in range(REPEATS):
                t0 = time.perf_counter()
                normals = pointnpr.estimate_normals(p, k=k, consistent=False)
                t = min(t, time.perf_counter() - t0) if t is not None else time.perf_counter() - t0
            err = angles(normals, truth)
            rows.append([shape, str(k), f"{t * 1e3:.0f}", f"{err.mean():.2f}", f"{np.percentile(err, 95):.2f}"])
            series.setdefault(shape, []).append((t * 1e3, err.mean()))
            labels.setdefault(shape, []).append(f"k={k}")
    table(["shape", "k", "ms", "mean error deg", "p95 deg"], rows)
    plot("normals", f"Normal estimation, {n:,} points", series, xlabel="ms (wall)",
         ylabel="mean angular error (deg)", labels=labels)


def study_packing():
    """pack_normals (render/gpu_cloud.h): signed 8-bit x, y, z, as the shaders unpack them."""
    rng = np.random.default_rng(1)
    n = rng.normal(size=(1_000_000, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    q = np.clip(np.round(n * 127.0), -127, 127) / 127.0
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    angle = np.degrees(np.arccos(np.clip((n * q).sum(1), -1, 1)))
    light = np.array([0.4, -0.3, 0.866])
    light /= np.linalg.norm(light)
    strength = 0.7  # the points mark's default shading_strength
    shade = lambda v: 1.0 - strength * (1.0 - np.abs(v @ light))
    levels = np.abs(shade(n) - shade(q)) * 255.0
    print("## 8-bit normal packing: 1,000,000 random unit normals\n")
    table(["mean angle deg", "max angle deg", "Lambert error mean / max (8-bit levels)",
           "% above 2/255", "bytes per normal"],
          [[f"{angle.mean():.3f}", f"{angle.max():.3f}", f"{levels.mean():.3f} / {levels.max():.2f}",
            f"{(levels > 2).mean() * 100:.3f}", "4 (float: 12)"]])


def study_inpaint(renderer):
    import inpaint_sweep
    from inpaint_compositing import nearest_index, render, scans
    name, clouds, world_from_camera, clip = next(scans())
    cam = pointnpr.Camera.perspective(world_from_camera, lens=35.0, clip_start=clip[0], clip_end=clip[1],
                                      width=inpaint_sweep.W, height=inpaint_sweep.H)
    ref, _, _ = render(renderer, clouds, cam, 2.0, [], "depth_test", {})
    covered = ref >= 0
    judge = nearest_index(ref, covered)
    print(f"## Inpainting radius: {name}, cartoon, sparse splats, {inpaint_sweep.W}x{inpaint_sweep.H}\n")
    rows, series, labels = [], {}, {}
    for method in inpaint_sweep.METHODS:
        for radius in inpaint_sweep.RADII:
            inside, added, ms = inpaint_sweep.measure(renderer, clouds, cam, ref, covered, judge,
                                                      {"method": method, "radius": radius}, repeat=REPEATS)
            wrong = (inside + added) / covered.size * 100.0
            rows.append([method, str(radius), f"{ms:.0f}", f"{inside + added:,}", f"{wrong:.2f}"])
            series.setdefault(method, []).append((ms, wrong))
            labels.setdefault(method, []).append(f"r={radius}")
    table(["method", "radius", "inpainting ms", "wrong-segment pixels", "% of frame"], rows)
    plot("inpaint", "Inpainting radius: wrong front-segment pixels", series, xlabel="inpainting ms (wall)",
         ylabel="wrong-segment pixels (% of frame)", labels=labels)


STUDIES = ["budget", "viewport", "rasterizer", "filters", "normals", "packing", "inpaint"]


def main():
    chosen = [s for s in STUDIES if s in sys.argv[1:]] or STUDIES
    renderer = pointnpr.Renderer()
    print(f"Measured {time.strftime('%Y-%m-%d')}, load average {os.getloadavg()[0]:.1f} at the start.\n")
    for study in chosen:
        fn = globals()["study_" + study]
        fn() if study in ("normals", "packing") else fn(renderer)


if __name__ == "__main__":
    main()
