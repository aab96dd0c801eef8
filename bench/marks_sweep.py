"""The marks' parameter sweep (issue 39, "every parameter acts or is
greyed out"), as a report: every parameter of every point mark set to other
valid values (tests/python/test_filter_sweep.py's rules and measure: 8/255
on 0.5 % of a 320x180 picture) on three scans: the lion (every 4th point)
and the LiDAR HD tile seen low, both coloured, as the filters' sweep, and
the sparse colourless Stanford bunny (bun_zipper, where `auto` colour and
shading resolve the other way). A parameter whose schema "when" does not
hold is swept with it made to hold.

    PYTHONPATH=build python3 bench/marks_sweep.py [mark ...]

Prints each parameter that changes no picture, with the share each value
changed. Not yet a test: docs/marks_audit.md lists what it finds and why.
"""
import os
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
import pointnpr  # noqa: E402

import test_filter_sweep as sweep  # noqa: E402

MARKS = ["points", "hatching", "stipples", "feature_strokes", "brush_splats"]


def scans():
    out = sweep.scans.__wrapped__()
    bunny = pointnpr.read("/work/shared/data/scans/stanford_bunny/bun_zipper.ply")
    pos = np.asarray(bunny.positions, np.float64)
    centre = (pos.min(0) + pos.max(0)) / 2
    cam = pointnpr.Camera.perspective(pointnpr.look_at(tuple(centre + (0.0, 0.05, 0.35)), tuple(centre),
                                                       up=(0.0, 1.0, 0.0)), lens=35.0, clip_start=0.01,
                                      clip_end=10.0, width=sweep.W, height=sweep.H)
    return out + [(pointnpr.PointCloud(pos), cam)]


def render(renderer, scan, mark, settings):
    cloud, camera = scan
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=(mark, settings)), [(cloud, np.eye(4))])
    return renderer.render(scene, camera, sweep.W, sweep.H, sweep.TIME, background=(1, 1, 1, 1)).color[..., :3]


def ramp_image():
    class Factory:
        def mktemp(self, _name):
            import pathlib
            return pathlib.Path(tempfile.mkdtemp())
    return sweep.images.__wrapped__(Factory())


def main():
    renderer, all_scans, image = pointnpr.Renderer(), scans(), ramp_image()
    dead_count = 0
    for mark in sys.argv[1:] or MARKS:
        schema = pointnpr.schema(mark, "mark")
        by_name = {p["name"]: p for p in schema["params"]}
        base = {p["name"]: (image if p["type"] == "path" else p["default"]) for p in schema["params"]}
        for param in schema["params"]:
            settings = dict(base)
            when = param["when"]
            if when and sweep._when_value(settings[when["param"]]) not in when["values"]:
                settings[when["param"]] = sweep._holding(when, by_name[when["param"]])
            reference = [render(renderer, s, mark, settings) for s in all_scans]
            tried = []
            for value in sweep._other_values(param, settings[param["name"]], image):
                try:
                    shares = [sweep._changed_share(render(renderer, s, mark, dict(settings, **{param["name"]: value})),
                                                   ref) for s, ref in zip(all_scans, reference)]
                    tried.append((value, max(shares)))
                except (pointnpr.Error, pointnpr.ParameterError) as e:
                    tried.append((value, float("nan")))
                    print(f"  {mark}.{param['name']} = {value!r}: {e}")
            numeric = param["type"] in ("float", "int")
            acting = [share >= sweep.MIN_SHARE for _value, share in tried]
            if not tried or not (any(acting) if numeric else all(acting)):
                dead_count += 1
                print(f"{mark}.{param['name']} (from {settings[param['name']]!r}): "
                      + ", ".join(f"{v!r}: {s:.4f}" for v, s in tried), flush=True)
    print(f"{dead_count} parameters change no picture")


if __name__ == "__main__":
    main()
