"""Engine time inside Blender for the 342k-point benchmark scene at 1920x1080
(three styled segments): whole F12-style frames through bpy.ops.render.render,
i.e. scene sync + core render + pass writes. Also splits sync from core time.

    blender -b blend_examples/lion_benchmark.blend --python bench/bench_blender.py -- build [frames]
"""
import os
import statistics
import sys
import time

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
build_dir = os.path.abspath(argv[0] if argv else "build")
frames = int(argv[1]) if len(argv) > 1 else 5
sys.path.insert(0, build_dir)

import bpy  # noqa: E402

import pointnpr  # noqa: E402

pointnpr.register()
from pointnpr.blender import engine, sync  # noqa: E402

scene = bpy.context.scene
points = sum(len(o.data.vertices) for o in scene.objects if o.type == 'MESH')
print(f"scene: {points} points, {scene.render.resolution_x}x{scene.render.resolution_y}, "
      f"GL: {pointnpr.gl_info()['renderer']}")

times = []
for i in range(frames + 1):
    scene.frame_set(scene.frame_start + i)
    t0 = time.perf_counter()
    bpy.ops.render.render()
    times.append(time.perf_counter() - t0)
cold, warm = times[0], times[1:]

# The same frame split into its parts, outside the operator.
depsgraph = bpy.context.evaluated_depsgraph_get()
width, height = engine.render_size(scene)
camera = engine.make_camera(depsgraph, scene.camera, width, height)
t0 = time.perf_counter()
synced = sync.build_scene(depsgraph, engine.scene_frame(scene))
t_sync = time.perf_counter() - t0
composite = sync.scene_settings(scene)
result = engine.renderer().render(synced.scene, camera, width, height, time=engine.scene_time(scene),
                                  composite=composite, background=engine.background(scene), stage_timings=True)
print(f"first frame (uploads, shader compiles): {cold * 1000:.0f} ms")
print(f"warm frames: median {statistics.median(warm) * 1000:.0f} ms, min {min(warm) * 1000:.0f} ms "
      f"over {len(warm)} frames (bpy.ops.render.render: sync + core + passes)")
print(f"  sync (cached clouds): {t_sync * 1000:.1f} ms; core: {result.stats['total_ms']:.0f} ms = "
      + ", ".join(f"{k[:-3]} {result.stats[k]:.0f}" for k in
                  ("mark_ms", "filters_ms", "inpaint_ms", "composite_ms", "readback_ms")))
