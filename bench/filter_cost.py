"""Side-by-side cost of filter presets through the Renderer (issue 40): the
Renderer's `filters_ms` (`stage_timings`, the gap fill included) at
1920x1080 on real scans, for several builds of the package, in alternating
rounds so that the shared machine's load falls on all of them alike.

    python3 bench/filter_cost.py NAME=PKG_PARENT [NAME=PKG_PARENT ...] [--rounds=3]
        [--preset=Watercolor ...] [--scan=tile ...] [--cpu]

PKG_PARENT is a folder holding a built `pointnpr` package (e.g. `build`, or a
copy of another tree's build/pointnpr with its shaders folder, which the
package reads its shaders from). Each round runs every build once in its own
process; a run renders each (scan, preset) 3 times and keeps the best. The
table gives the median over rounds of those bests, and each build's ratio
to the first one named. `--cpu` measures instead the CPU time (all threads)
of a render with the preset's filters less that of one without them: the
work done on the filters, less moved by other processes' load.
"""
import json
import os
import statistics
import subprocess
import sys

W, H = 1920, 1080
SCANS = {"tile": "LiDAR HD tile (aerial)", "kinect": "Kinect mug (RGB-D)", "lion": "lion (photogrammetry)"}


def _cpu_ms(renderer, scene, cam):
    t = os.times()
    renderer.render(scene, cam, W, H)
    u = os.times()
    return 1000.0 * ((u.user + u.system) - (t.user + t.system))


def child(presets_wanted, scans_wanted, cpu):
    import numpy as np

    import pointnpr
    from pointnpr import presets

    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import look_audit

    renderer = pointnpr.Renderer()
    out = {}
    for name, pos, attrs, cam_m, clip in look_audit.scans():
        key = next((k for k, v in SCANS.items() if v == name), None)
        if key not in scans_wanted:
            continue
        cloud, centre = look_audit._cloud(pos, attrs)
        cam = pointnpr.Camera.perspective(cam_m, lens=35.0, clip_start=clip[0], clip_end=clip[1], width=W, height=H)
        for preset in presets_wanted:
            p = presets.PRESETS[preset]
            scene = pointnpr.Scene()
            m = np.eye(4)
            m[:3, 3] = centre
            scene.add_segment("scan", pointnpr.Style(mark=p["mark"], filters=p["filters"]), [(cloud, m)])
            if cpu:
                # The CPU time of every thread of this process over a render
                # with the filters less one without: llvmpipe's work on them,
                # which the other sessions' load on a shared machine delays
                # but does not add to (wall-clock time takes that load in).
                bare = pointnpr.Scene()
                bare.add_segment("scan", pointnpr.Style(mark=p["mark"]), [(cloud, m)])
                best = min(_cpu_ms(renderer, scene, cam) - _cpu_ms(renderer, bare, cam) for _ in range(3))
            else:
                best = min(renderer.render(scene, cam, W, H, stage_timings=True).stats["filters_ms"] for _ in range(3))
            out[f"{key}/{preset}"] = best
    print("RESULT " + json.dumps(out))


def main():
    args = sys.argv[1:]
    if args and args[0] == "--child":
        child(json.loads(args[1]), json.loads(args[2]), "--cpu" in args)
        return
    builds = [a.split("=", 1) for a in args if "=" in a and not a.startswith("--")]
    rounds = next((int(a.split("=")[1]) for a in args if a.startswith("--rounds=")), 3)
    presets_wanted = [a.split("=", 1)[1] for a in args if a.startswith("--preset=")] or ["Watercolor"]
    scans_wanted = [a.split("=", 1)[1] for a in args if a.startswith("--scan=")] or ["tile", "kinect"]
    cpu = "--cpu" in args
    results = {name: {} for name, _ in builds}
    here = os.path.dirname(os.path.abspath(__file__))
    for _ in range(rounds):
        for name, parent in builds:
            env = dict(os.environ, PYTHONPATH=os.path.abspath(parent))
            env.pop("POINTNPR_SHADER_DIR", None)
            command = [sys.executable, __file__, "--child", json.dumps(presets_wanted), json.dumps(scans_wanted)]
            run = subprocess.run(command + (["--cpu"] if cpu else []), env=env, cwd=os.path.dirname(here),
                                 capture_output=True, text=True, check=True)
            line = next(l for l in run.stdout.splitlines() if l.startswith("RESULT "))
            for k, v in json.loads(line[7:]).items():
                results[name].setdefault(k, []).append(v)
    first = builds[0][0]
    print("| scan/preset | " + " | ".join(f"{n} (ms)" for n, _ in builds) + " | "
          + " | ".join(f"{n} / {first}" for n, _ in builds[1:]) + " |")
    print("|---" * (2 * len(builds)) + "|")
    for k in results[first]:
        med = [statistics.median(results[n][k]) for n, _ in builds]
        print(f"| {k} | " + " | ".join(f"{m:.0f}" for m in med) + " | "
              + " | ".join(f"{m / med[0]:.2f}" for m in med[1:]) + " |")
    print("runs per build: " + json.dumps({n: results[n] for n, _ in builds}))


if __name__ == "__main__":
    main()
