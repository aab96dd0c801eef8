"""Stress probes of issue 17, inside Blender on the urban example:

1. 100 F12 renders: resident memory after each; flat within 5 % (the last
   render against the 10th, after warm-up).
2. Imports of every file of the malformed corpus (tests/data/io/malformed),
   each also with "Split by classification": a failed import leaves the
   scene exactly as it was (objects, meshes, collections); a successful one
   is undone and counted.
3. Renders from 4 threads on one Renderer: the same bytes as one thread.

    blender -b blend_examples/urban_lidarhd.blend --python bench/stress_probes.py -- build [renders]
"""
import os
import sys
import threading
import time

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
build_dir = os.path.abspath(argv[0] if argv else "build")
renders = int(argv[1]) if len(argv) > 1 else 100
sys.path.insert(0, build_dir)
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import pointnpr  # noqa: E402

pointnpr.register()
from pointnpr.blender import engine, sync  # noqa: E402


def rss_mb():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def snapshot():
    return (sorted(o.name for o in bpy.data.objects), sorted(m.name for m in bpy.data.meshes),
            sorted(c.name for c in bpy.data.collections),
            sorted(c.name for c in bpy.context.scene.collection.children))


scene = bpy.context.scene
print(f"scene: {scene.render.resolution_x}x{scene.render.resolution_y} at {scene.render.resolution_percentage} %, "
      f"GL: {pointnpr.gl_info()['renderer']}", flush=True)

# 1. Repeated F12 renders.
rss = []
t0 = time.perf_counter()
for i in range(renders):
    scene.frame_set(scene.frame_start + i % 10)
    bpy.ops.render.render()
    rss.append(rss_mb())
elapsed = time.perf_counter() - t0
ref = rss[min(9, len(rss) - 1)]
growth = (rss[-1] - ref) / ref
print(f"F12 x{renders}: {elapsed:.0f} s; RSS after render 1 {rss[0]:.0f} MB, 10 {ref:.0f} MB, "
      f"last {rss[-1]:.0f} MB, max {max(rss):.0f} MB; growth 10->last {growth * 100:+.2f} % "
      f"({'flat within 5 %' if abs(growth) <= 0.05 else 'NOT flat'})", flush=True)

# 2. The malformed corpus.
corpus = os.path.join(ROOT, "tests", "data", "io", "malformed")
failed = imported = residue = 0
for name in sorted(os.listdir(corpus)):
    for split in (False, True):
        before = snapshot()
        try:
            bpy.ops.import_scene.pointnpr_cloud(filepath=os.path.join(corpus, name), split_by_classification=split)
        except RuntimeError:
            failed += 1
            if snapshot() != before:
                residue += 1
                print(f"  RESIDUE after the failed import of {name} (split {split})", flush=True)
            continue
        imported += 1
        # Undo what it made, so the next import starts from the same scene.
        new_objects = set(o.name for o in bpy.data.objects) - set(before[0])
        for n in new_objects:
            bpy.data.objects.remove(bpy.data.objects[n])
        for n in set(m.name for m in bpy.data.meshes) - set(before[1]):
            bpy.data.meshes.remove(bpy.data.meshes[n])
        for n in set(c.name for c in bpy.data.collections) - set(before[2]):
            bpy.data.collections.remove(bpy.data.collections[n])
        if snapshot() != before:
            residue += 1
            print(f"  could not undo the import of {name}", flush=True)
print(f"malformed corpus: {len(os.listdir(corpus))} files x 2 (split off/on): {imported} imported, "
      f"{failed} refused with a message, {residue} left residue", flush=True)

# 3. Four threads, one renderer.
depsgraph = bpy.context.evaluated_depsgraph_get()
width, height = engine.render_size(scene)
camera = engine.make_camera(depsgraph, scene.camera, width, height)
synced = sync.build_scene(depsgraph, engine.scene_frame(scene))
composite = sync.scene_settings(scene)
renderer = engine.renderer()


def frame():
    r = renderer.render(synced.scene, camera, width, height, time=engine.scene_time(scene), composite=composite,
                        background=engine.background(scene))
    return np.asarray(r.color).tobytes() + np.asarray(r.depth).tobytes() + np.asarray(r.segment_index).tobytes()


reference = frame()
results = [None] * 4


def work(i):
    results[i] = [frame() for _ in range(3)]


threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
for t in threads:
    t.start()
for t in threads:
    t.join()
same = all(r == reference for rs in results for r in rs)
print(f"4 threads x 3 renders on one renderer: {'identical to one thread' if same else 'DIFFERENT'}", flush=True)
