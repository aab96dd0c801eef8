"""Tiled frames (issue 17), inside Blender on the urban example.

f12 SIZE [BUDGET_GB]: one F12 render at SIZE x SIZE; prints its time, the
tiles and the process's peak RSS (run each size in its own process: peak RSS
is per process).
core SIZE [BUDGET_GB]: the same frame through the core alone (the Python
API: no Blender render result), for sizes whose Blender buffers would not fit.
compare [SIZE_X SIZE_Y]: the core's time per pixel drawn whole (budget
large enough) against tiled (budget 0.5 GB), side by side, best of 3.

    blender -b blend_examples/urban_lidarhd.blend --python bench/bench_tiles.py -- build f12 8000
    blender -b blend_examples/urban_lidarhd.blend --python bench/bench_tiles.py -- build core 16384
    blender -b blend_examples/urban_lidarhd.blend --python bench/bench_tiles.py -- build compare 3840 2160
"""
import os
import resource
import sys
import time

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
build_dir = os.path.abspath(argv[0] if argv else "build")
mode = argv[1] if len(argv) > 1 else "compare"
sys.path.insert(0, build_dir)

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import pointnpr  # noqa: E402

pointnpr.register()
from pointnpr.blender import engine, sync  # noqa: E402

scene = bpy.context.scene
scene.render.resolution_percentage = 100


def peak_rss_gb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20  # KiB -> GiB


if mode == "f12":
    size = int(argv[2])
    budget = float(argv[3]) if len(argv) > 3 else 2.0
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.pointnpr.memory_budget_gb = budget
    before = peak_rss_gb()
    t0 = time.perf_counter()
    bpy.ops.render.render()
    elapsed = time.perf_counter() - t0
    # Output buffers per pixel: Blender's passes (Combined 16 B, Depth 4,
    # Segment Index 4) and its 8-bit display copy (4); the core's result
    # (colour 16, depth 4, segment index 4); the engine's float copy of the
    # segment index for its pass (4).
    blender_buffers = size * size * 28 / 2**30
    core_result = size * size * 24 / 2**30
    engine_copy = size * size * 4 / 2**30
    bound = before + budget + blender_buffers + core_result + engine_copy
    print(f"F12 {size}x{size}, budget {budget} GB: {elapsed:.0f} s; peak RSS {peak_rss_gb():.2f} GB "
          f"(before the render {before:.2f} GB); output buffers: Blender's {blender_buffers:.2f} GB, the core's "
          f"result {core_result:.2f} GB, the engine's copy {engine_copy:.2f} GB; before + budget + buffers "
          f"= {bound:.2f} GB", flush=True)
elif mode == "core":
    # The same scene through the core alone (no Blender render result).
    size = int(argv[2])
    budget = float(argv[3]) if len(argv) > 3 else 2.0
    depsgraph = bpy.context.evaluated_depsgraph_get()
    camera = engine.make_camera(depsgraph, scene.camera, size, size)
    synced = sync.build_scene(depsgraph, engine.scene_frame(scene))
    before = peak_rss_gb()
    t0 = time.perf_counter()
    r = engine.renderer().render(synced.scene, camera, size, size, time=engine.scene_time(scene),
                                 composite=sync.scene_settings(scene), background=engine.background(scene),
                                 memory_budget_gb=budget)
    elapsed = time.perf_counter() - t0
    core_result = size * size * 24 / 2**30
    print(f"core {size}x{size}, budget {budget} GB: {elapsed:.0f} s, {int(r.stats['tiles'])} tiles of "
          f"{int(r.stats['tile_region_width'])}x{int(r.stats['tile_region_height'])}; peak RSS "
          f"{peak_rss_gb():.2f} GB (before {before:.2f} GB); the result {core_result:.2f} GB; before + budget + "
          f"result = {before + budget + core_result:.2f} GB", flush=True)
else:
    w = int(argv[2]) if len(argv) > 2 else 3840
    h = int(argv[3]) if len(argv) > 3 else 2160
    scene.render.resolution_x, scene.render.resolution_y = w, h
    depsgraph = bpy.context.evaluated_depsgraph_get()
    camera = engine.make_camera(depsgraph, scene.camera, w, h)
    synced = sync.build_scene(depsgraph, engine.scene_frame(scene))
    composite = sync.scene_settings(scene)
    renderer = engine.renderer()

    def run(budget):
        r = renderer.render(synced.scene, camera, w, h, time=engine.scene_time(scene), composite=composite,
                            background=engine.background(scene), memory_budget_gb=budget)
        return r

    run(64.0)  # warm-up: uploads, shader compiles
    best = {}
    frames = {}
    for _ in range(3):
        for label, budget in (("whole", 64.0), ("tiled", 0.5)):
            t0 = time.perf_counter()
            r = run(budget)
            dt = time.perf_counter() - t0
            if dt < best.get(label, (1e9,))[0]:
                best[label] = (dt, int(r.stats["tiles"]), int(r.stats["tile_region_width"]),
                               int(r.stats["tile_region_height"]))
            frames[label] = np.asarray(r.color).tobytes()
    for label, (dt, tiles, rw, rh) in best.items():
        print(f"{w}x{h} {label}: {dt * 1000:.0f} ms, {dt * 1e9 / (w * h):.1f} ns per pixel, {tiles} tiles "
              f"of {rw}x{rh}", flush=True)
    print(f"tiled / whole: {best['tiled'][0] / best['whole'][0]:.2f}x; same bytes: "
          f"{frames['tiled'] == frames['whole']}", flush=True)
