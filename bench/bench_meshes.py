"""Cost of a mesh segment (issue 15): a frame of the lion scan alone
against the lion plus a 100k-triangle mesh segment (a "building": a box
whose faces are fine grids, standing behind the lion, in view), 1920x1080,
timed alternately in one run (median and best of N frames after a warm-up
frame that uploads and compiles shaders).

    PYTHONPATH=build /usr/bin/python3 bench/bench_meshes.py [frames]

Rows: the scan alone; scan + mesh (smooth Lambert); scan + mesh with a
cartoon filter on the mesh segment; the mesh sampled into points
(meshes = sampled, 2,000 points per m^2) drawn by the points mark. Reports
the whole render call, the mark stage (`mark_ms`) and the triangles drawn.
"""
import sys
import time

import numpy as np

import pointnpr

W, H = 1920, 1080
FRAMES = next((int(a) for a in sys.argv[1:] if a.isdigit()), 7)
EYE, TARGET = (2.6, -1.6, 1.5), (-2.9, 3.9, -1.2)


def grid_box(lo, hi, n):
    """A box with every face an n x n grid of quads: 12 n^2 triangles."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    t = np.linspace(0.0, 1.0, n + 1)
    U, V = np.meshgrid(t, t)
    u, v = U.ravel(), V.ravel()
    quads = np.array([(i * (n + 1) + j, i * (n + 1) + j + 1, (i + 1) * (n + 1) + j + 1, (i + 1) * (n + 1) + j)
                      for i in range(n) for j in range(n)])
    positions, triangles = [], []
    for axis in range(3):
        for side in (0, 1):
            a, b = [k for k in range(3) if k != axis]
            p = np.empty((u.size, 3))
            p[:, axis] = hi[axis] if side else lo[axis]
            p[:, a] = lo[a] + u * (hi[a] - lo[a])
            p[:, b] = lo[b] + v * (hi[b] - lo[b])
            base = sum(len(x) for x in positions)
            positions.append(p)
            q = quads + base
            triangles.append(np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]))
    return np.concatenate(positions), np.concatenate(triangles)


def main():
    data = pointnpr.read("data/lion_takanawa.ply")
    lion = data.to_cloud()
    lo, hi = (np.array(b) for b in lion.bounds)
    size = hi - lo
    # Behind the lion's left, on its plinth's level, as tall as it.
    b_lo = np.array([lo[0] - 2.0, hi[1] - 0.5, lo[2]])
    b_hi = b_lo + np.array([2.0, 2.0, size[2]])
    pos, tri = grid_box(b_lo, b_hi, 91)  # 12 x 91^2 = 99,372 triangles
    building = pointnpr.TriangleMesh(pos, tri, base_color=(0.8, 0.75, 0.7))
    camera = pointnpr.Camera.perspective(pointnpr.look_at(EYE, TARGET), lens=35.0, clip_start=0.1, clip_end=100.0,
                                         width=W, height=H)
    scan_style = pointnpr.Style()

    def scene(mesh_style):
        s = pointnpr.Scene()
        s.add_segment("scan", scan_style, [lion])
        if mesh_style is not None:
            s.add_segment("building", mesh_style, [building])
        return s

    cases = [("lion alone", scene(None)),
             ("lion + 99k-triangle mesh", scene(pointnpr.Style())),
             ("lion + mesh, cartoon on the mesh", scene(pointnpr.Style(filters=["cartoon"]))),
             ("lion + mesh sampled (2,000 / m^2) as points",
              scene(pointnpr.Style(surface={"meshes": "sampled", "sample_density": 2000.0})))]
    renderer = pointnpr.Renderer()
    times = {name: [] for name, _s in cases}
    marks = {name: [] for name, _s in cases}
    stats = {}
    for name, s in cases:  # warm-up: uploads, shader compiles, sampling
        r = renderer.render(s, camera, W, H, stage_timings=True)
        if len(sys.argv) > 2 and name == cases[2][0]:  # a picture of the composition
            pointnpr.save_image(sys.argv[2], np.ascontiguousarray(np.asarray(r.color)[..., :3]), srgb=True)
        stats[name] = (r.stats.get("triangles_drawn", 0), r.stats.get("points_drawn", 0),
                       (np.asarray(r.segment_index) == 1).sum())
    for _ in range(FRAMES):
        for name, s in cases:
            t0 = time.perf_counter()
            r = renderer.render(s, camera, W, H, stage_timings=True)
            times[name].append((time.perf_counter() - t0) * 1000.0)
            marks[name].append(r.stats["mark_ms"])
    base = np.median(times["lion alone"])
    print("%dx%d, %d frames each, timed alternately; triangles %s" % (W, H, FRAMES, f"{len(tri):,}"))
    print("| scene | frame ms (median / best) | mark stage ms (median) | vs the scan alone | triangles drawn | "
          "points drawn | mesh pixels |")
    print("|---|---|---|---|---|---|---|")
    for name, _s in cases:
        t = np.array(times[name])
        tris, points, pixels = stats[name]
        print("| %s | %.0f / %.0f | %.0f | %.2fx | %s | %s | %s |" % (
            name, np.median(t), t.min(), np.median(marks[name]), np.median(t) / base, f"{int(tris):,}",
            f"{int(points):,}", f"{int(pixels):,}"))


if __name__ == "__main__":
    main()
