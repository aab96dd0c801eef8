"""Golden images: every preset rendered on a real scan (the lion
photogrammetry scan; "Urban map" on the LiDAR HD tile, as it colours by
class; each hatching preset on both, preset_<name>_lion.png and
preset_<name>_tile.png; each feature strokes and each stipple preset on the
tile and the Stanford bunny, preset_<name>_tile.png and
preset_<name>_bunny.png; each brush_splats preset on the lion and on a
Kinect-like PCD, preset_<name>_lion.png and preset_<name>_mug.png),
compared with OpenImageIO's idiff.

Tolerance: a pixel fails when a channel differs by more than 2/255 (8-bit
PNG quantisation plus float rounding of a different build); up to 0.5 % of
pixels may fail (GPU drivers round filters differently). The render itself
is deterministic (tests/python/test_render_api.py), so on this machine the
difference is zero.

Regenerate on purpose only, after a change meant to alter the look, and
look at the images before committing them:

    POINTNPR_UPDATE_GOLDEN=1 POINTNPR_BUILD_DIR=build /usr/bin/python3 -m pytest -q tests/python/test_golden.py
"""
import os
import re
import shutil
import subprocess

import numpy as np
import pytest

import pointnpr
from pointnpr import presets

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
GOLDEN = os.path.join(ROOT, "tests", "data", "golden")
W, H = 320, 224
FAIL_ABOVE, FAIL_PERCENT = 2.0 / 255.0, 0.5


def _scene(name, scan=None):
    if scan == "mug":
        # A Kinect-like organized PCD (PCL's textured mug scene, cropped), seen from its sensor.
        mug = pointnpr.read(os.path.join(ROOT, "tests", "data", "io", "mug_crop.pcd"))
        pos = np.asarray(mug.positions)
        cloud = mug.to_cloud()
        camera = pointnpr.Camera.perspective(pointnpr.look_at((0.0, 0.0, 0.0), (pos.min(0) + pos.max(0)) / 2,
                                                              up=(0.0, -1.0, 0.0)),
                                             lens=280.0, clip_start=0.05, clip_end=100.0, width=W, height=H)
        scene = pointnpr.Scene()
        scene.add_segment("scan", presets.style(name), [(cloud, np.eye(4))])
        return scene, camera
    # The bunny: turned Z up for the stipple presets (their light is given
    # in a Z-up world); in its own Y-up frame for the feature strokes presets.
    stipples = presets.PRESETS[name]["mark"][0] == "stipples"
    if scan == "bunny" and stipples:
        bunny = pointnpr.read(os.path.join(ROOT, "tests", "data", "io", "bun_zipper_res2.ply"))
        pos = np.asarray(bunny.positions)
        pos = pos - (pos.min(0) + pos.max(0)) / 2
        cloud = pointnpr.PointCloud(np.c_[pos[:, 0], -pos[:, 2], pos[:, 1]])  # its Y up to Z up
        eye, target, clip = (0.12, -0.32, 0.1), (0.0, 0.0, 0.0), (0.01, 10.0)
    elif (scan or ("tile" if name == "Urban map" else "lion")) == "tile":
        tile = pointnpr.read(os.path.join(ROOT, "data", "lidarhd_myria3d_870000_6618000_subset.las"))
        pos = np.asarray(tile.positions)
        centre = (pos.min(0) + pos.max(0)) / 2
        cloud = pointnpr.PointCloud(pos - centre, colors=np.asarray(tile.attributes["colors"]),
                                    classification=np.asarray(tile.attributes["classification"]))
        eye, target, clip = (0.0, -70.0, 60.0), (0.0, 0.0, 0.0), (0.5, 1000.0)
    elif scan == "bunny":
        cloud = pointnpr.read(os.path.join(ROOT, "tests", "data", "io", "bun_zipper_res2.ply")).to_cloud()
        eye, target, clip = (-0.03, 0.14, 0.32), (-0.02, 0.11, 0.0), (0.01, 10.0)
        camera = pointnpr.Camera.perspective(pointnpr.look_at(eye, target, up=(0.0, 1.0, 0.0)), lens=35.0,
                                             clip_start=clip[0], clip_end=clip[1], width=W, height=H)
        scene = pointnpr.Scene()
        scene.add_segment("scan", presets.style(name), [(cloud, np.eye(4))])
        return scene, camera
    else:
        cloud = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()
        eye, target, clip = (2.6, -1.6, 1.5), (-2.9, 3.9, -1.2), (0.1, 100.0)
    camera = pointnpr.Camera.perspective(pointnpr.look_at(eye, target), lens=35.0, clip_start=clip[0],
                                         clip_end=clip[1], width=W, height=H)
    scene = pointnpr.Scene()
    scene.add_segment("scan", presets.style(name), [(cloud, np.eye(4))])
    return scene, camera


def _slug(name):
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")


def _cases():
    """(preset, scan or None): the splat presets on their one scan (golden
    names unchanged), the hatching presets on the lion and on the tile."""
    cases = []
    for name in sorted(presets.PRESETS):
        if presets.PRESETS[name]["mark"][0] == "hatching":
            cases += [(name, "lion"), (name, "tile")]
        elif presets.PRESETS[name]["mark"][0] == "feature_strokes":
            cases += [(name, "tile"), (name, "bunny")]
        elif presets.PRESETS[name]["mark"][0] == "stipples":
            cases += [(name, "bunny"), (name, "tile")]
        elif presets.PRESETS[name]["mark"][0] == "brush_splats":
            cases += [(name, "lion"), (name, "mug")]
        else:
            cases.append((name, None))
    return cases


@pytest.mark.parametrize("name,scan", _cases())
def test_preset_matches_its_golden_image(renderer, name, scan, tmp_path):
    scene, camera = _scene(name, scan)
    color = np.asarray(renderer.render(scene, camera, W, H, background=(1, 1, 1, 1)).color)
    slug = _slug(name) + (f"_{scan}" if scan else "")
    out = str(tmp_path / (slug + ".png"))
    pointnpr.save_image(out, np.ascontiguousarray(color[..., :3]), srgb=True)
    golden = os.path.join(GOLDEN, "preset_" + slug + ".png")
    if os.environ.get("POINTNPR_UPDATE_GOLDEN"):
        os.makedirs(GOLDEN, exist_ok=True)
        shutil.copyfile(out, golden)
    assert os.path.exists(golden), f"no golden image {golden}: see this file's docstring to make one"
    idiff = shutil.which("idiff")
    assert idiff, "idiff (openimageio-tools) is needed"
    diff_image = str(tmp_path / "diff.png")
    run = subprocess.run([idiff, "-fail", str(FAIL_ABOVE), "-failpercent", str(FAIL_PERCENT), "-warn",
                          str(FAIL_ABOVE), "-warnpercent", str(FAIL_PERCENT), "-abs", "-scale", "10",
                          "-o", diff_image, golden, out], capture_output=True, text=True)
    # idiff: 0 = pass, 1 = warning, 2 = failure, 3 = size differs, 4 = file error.
    assert run.returncode == 0, f"{name}: {out} differs from {golden} ({diff_image}):\n{run.stdout}{run.stderr}"


def test_idiff_catches_a_changed_look(renderer, tmp_path):
    """The comparison can fail: a preset with one parameter changed does not
    pass against the golden image."""
    scene, camera = _scene("Toon")
    changed = presets.PRESETS["Toon"]
    style = pointnpr.Style(mark=changed["mark"],
                           filters=[(f, dict(p, levels=6) if f == "cartoon" else p) for f, p in changed["filters"]])
    scene = pointnpr.Scene()
    cloud = pointnpr.read(os.path.join(ROOT, "data", "lion_takanawa.ply")).to_cloud()
    scene.add_segment("scan", style, [(cloud, np.eye(4))])
    color = np.asarray(renderer.render(scene, camera, W, H, background=(1, 1, 1, 1)).color)
    out = str(tmp_path / "toon_changed.png")
    pointnpr.save_image(out, np.ascontiguousarray(color[..., :3]), srgb=True)
    run = subprocess.run(["idiff", "-fail", str(FAIL_ABOVE), "-failpercent", str(FAIL_PERCENT),
                          os.path.join(GOLDEN, "preset_toon.png"), out], capture_output=True, text=True)
    assert run.returncode == 2, run.stdout
