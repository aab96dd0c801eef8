"""Viewport navigation in Blender's UI (needs a display: Xvfb): redraws per
second while orbiting, new frames per second, time to the full frame after
the view stops, and the longest block of Blender's UI thread by PointNPR.

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup \\
        --python bench/bench_viewport.py -- build [tiles_per_side] [factors] [orbit_s]

The scene: the LiDAR HD tile of data/ (70,840 points) tiled tiles_per_side²
times (12 -> 10.2M points) as one mesh object, plain 2 px points of the
scene's default style, the 3D view of the default layout in Rendered
shading. For each navigation factor (e.g. "1,2,4,8"): rest until the full
frame is drawn, orbit by 1 degree per UI tick for orbit_s seconds, stop,
wait for the full frame of the resting view. PointNPR's main-thread time is
viewport_worker.timing (view_draw, view_update, its timer); the first sync
of the scan (reading it from Blender and building the core cloud, once per
geometry edit) is reported apart from navigation.
"""
import os
import resource
import sys
import time
import traceback

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
BUILD = os.path.abspath(argv[0] if argv else "build")
TILES = int(argv[1]) if len(argv) > 1 else 12
FACTORS = [int(f) for f in (argv[2] if len(argv) > 2 else "1,2,4,8").split(",")]
ORBIT_S = float(argv[3]) if len(argv) > 3 else 6.0
sys.path.insert(0, BUILD)

import bpy  # noqa: E402
import numpy as np  # noqa: E402

bpy.context.preferences.view.show_splash = False

import pointnpr  # noqa: E402
from pointnpr.blender import engine, viewport_worker  # noqa: E402

HERE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TICK_S = 1.0 / 60.0


def log(msg):
    print("[bench_viewport] %s" % msg, flush=True)


def tiled_positions(tiles):
    data = pointnpr.read(os.path.join(HERE, "data", "lidarhd_myria3d_870000_6618000_subset.las"))
    p = np.asarray(data.positions)
    lo, hi = p.min(0), p.max(0)
    local = (p - (lo + hi) / 2).astype(np.float32)
    size = (hi - lo)[:2].astype(np.float32)
    out = np.empty((tiles * tiles * len(p), 3), dtype=np.float32)
    k = 0
    for i in range(tiles):
        for j in range(tiles):
            block = out[k:k + len(p)]
            block[:] = local
            block[:, 0] += (i - (tiles - 1) / 2) * size[0]
            block[:, 1] += (j - (tiles - 1) / 2) * size[1]
            k += len(p)
    return out, float(max(size) * tiles)


def build_scene():
    scene = bpy.context.scene
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    scene.render.engine = 'POINTNPR'
    positions, extent = tiled_positions(TILES)
    mesh = bpy.data.meshes.new("Scan")
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    mesh.update()
    scene.collection.objects.link(bpy.data.objects.new("Scan", mesh))
    return len(positions), extent


def view3d():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                return window, area, next(r for r in area.regions if r.type == 'WINDOW')
    raise RuntimeError("no 3D view")


def settled():
    sessions = viewport_worker.sessions()
    if len(sessions) != 1:
        return False
    s = sessions[0]
    frame = s.frame()
    return frame is not None and frame.full and frame.key == s.last_key and s.drawn_generation == frame.generation


def run():
    from mathutils import Euler
    t0 = time.perf_counter()
    n, extent = build_scene()
    log("scene: %d points (%d x %d tiles), built in %.1f s; GL %s" % (
        n, TILES, TILES, time.perf_counter() - t0, pointnpr.gl_info()["renderer"]))
    window, area, region = view3d()
    space = area.spaces.active
    space.overlay.show_overlays = False
    space.show_gizmo = False
    rv3d = space.region_3d
    rv3d.view_perspective = 'PERSP'
    rv3d.view_location = (0.0, 0.0, 0.0)
    rv3d.view_distance = extent * 0.9
    rv3d.view_rotation = Euler((np.radians(55.0), 0.0, 0.0)).to_quaternion()
    space.clip_end = extent * 10
    scene = bpy.context.scene
    scene.pointnpr.refine_delay = 0.5
    scene.pointnpr.navigation_resolution = str(FACTORS[0])
    viewport_worker.reset_timing()
    t0 = time.perf_counter()
    space.shading.type = 'RENDERED'
    while not settled():
        area.tag_redraw()
        yield 0.05
    first = time.perf_counter() - t0
    log("region %dx%d; first full frame %.2f s after Rendered shading; longest main-thread block then "
        "(the first sync) %.0f ms; %s" % (region.width, region.height, first, viewport_worker.longest_block_ms(),
                                          {k: "max %.1f mean %.1f" % (v[2], v[1] / max(v[0], 1)) for k, v in viewport_worker.timing.items()}))
    rows = []
    for factor in FACTORS:
        scene.pointnpr.navigation_resolution = str(factor)
        area.tag_redraw()
        while not settled():
            area.tag_redraw()
            yield 0.05
        viewport_worker.reset_timing()
        mark = len(viewport_worker.events)
        draws0 = engine.stats["viewport_draws"]
        start = time.perf_counter()
        while time.perf_counter() - start < ORBIT_S:
            rv3d.view_rotation = Euler((0.0, 0.0, np.radians(1.0))).to_quaternion() @ rv3d.view_rotation
            area.tag_redraw()
            yield TICK_S
        stop = time.perf_counter()
        orbit_s = stop - start
        draws = engine.stats["viewport_draws"] - draws0
        events = list(viewport_worker.events)[mark:]
        drawn = [e for e in events if e[0] == "drawn"]
        reduced_ms = [e[3] for e in events if e[0] == "published" and e[2] != 1]
        while not settled():
            area.tag_redraw()
            yield 0.01
        to_full = time.perf_counter() - stop
        full_ms = [e[3] for e in list(viewport_worker.events)[mark:] if e[0] == "published" and e[2] == 1]
        block = viewport_worker.longest_block_ms()
        rows.append((factor, draws / orbit_s, len(drawn) / orbit_s,
                     np.median(reduced_ms) if reduced_ms else float("nan"),
                     to_full, full_ms[-1] if full_ms else float("nan"), block,
                     {k: "max %.1f mean %.1f" % (v[2], v[1] / max(v[0], 1)) for k, v in viewport_worker.timing.items()}))
        log("1/%d: %.1f redraws/s, %.2f new frames/s orbiting, full frame %.2f s after stopping, "
            "longest block %.1f ms" % (factor, rows[-1][1], rows[-1][2], to_full, block))
    # Blender's own redraw rate with PointNPR drawing its last frame and
    # rendering nothing (every request held): the UI's ceiling here.
    viewport_worker.hold = lambda request: True
    draws0, start = engine.stats["viewport_draws"], time.perf_counter()
    while time.perf_counter() - start < ORBIT_S:
        rv3d.view_rotation = Euler((0.0, 0.0, np.radians(1.0))).to_quaternion() @ rv3d.view_rotation
        area.tag_redraw()
        yield TICK_S
    ceiling = (engine.stats["viewport_draws"] - draws0) / (time.perf_counter() - start)
    viewport_worker.hold = None
    log("UI redraws/s orbiting with no frame rendering (Blender's ceiling here): %.1f; load average %s" %
        (ceiling, open("/proc/loadavg").read().split()[:3]))
    log("| navigation resolution | UI redraws/s orbiting | new frames/s orbiting | reduced frame ms (median) "
        "| full frame after stopping (s) | full frame ms | longest UI-thread block by PointNPR (ms) |")
    log("|---|---|---|---|---|---|---|")
    for factor, redraws, frames, reduced, to_full, full, block, _per in rows:
        log("| 1/%d | %.1f | %.2f | %.0f | %.2f | %.0f | %.1f |" % (factor, redraws, frames, reduced, to_full, full, block))
    log("per callback ms: %s" % [(r[0], r[7]) for r in rows])
    log("peak RSS %.2f GB" % (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20))


def main():
    steps = run()

    def tick():
        try:
            return next(steps)
        except StopIteration:
            os._exit(0)
        except Exception:
            traceback.print_exc()
            os._exit(1)
    pointnpr.register()
    bpy.app.timers.register(tick, first_interval=1.0)


main()
