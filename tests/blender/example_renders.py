"""Small renders of the example .blend files in blend_examples/.

Used two ways:

* as a script, to make the reference images tests/data/golden/legacy_<name>.png
  with a given package (they were made with the package from before the
  mark stage, whose styles still had a Rasterize node; urban_lidarhd was
  rendered again on purpose in issue 40, when eye-dome lighting began to
  read its neighbours between pixels; urban_lidarhd, warsaw_styles and
  lion_benchmark again when the gap fill began to close the gaps between
  splats before neighbourhood filters; urban_lidarhd and warsaw_styles again
  when the scan's spacing reached the filters: eye-dome lighting's noise
  floor and the gap fill's reach; and those two again when the gap fill
  began to close with the farther surface and each point's own spacing;
  urban_lidarhd and lion_benchmark again when the farther surface began to
  fill a gap no wider than the depth step beside a nearer edge; and
  urban_lidarhd again when the gap fill's reach began to follow the
  spacing of the points each pixel's lines meet; urban_lidarhd and
  warsaw_styles again when the gap fill began to close the gaps among lone
  splats from cells of 2 to 16 px):

      blender -b --factory-startup --python-exit-code 1 \
          --python tests/blender/example_renders.py -- <builddir> [names...]

* from tests/blender/test_versioning.py, which opens the same files with the
  current add-on (their Rasterize nodes are migrated to Points mark nodes on
  load) and compares its render with those references.

The resolution is set here, not in the files: 320 px wide, the files' aspect
ratio, 100 %, no dithering (dither adds noise that differs between renders).
"""
import os
import shutil
import subprocess
import sys

import bpy

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
EXAMPLES_DIR = os.path.join(REPO, "blend_examples")
GOLDEN = os.path.join(REPO, "tests", "data", "golden")
WIDTH = 320
# Frame each example is rendered at: warsaw_styles at 24, where its keyframed
# warp amplitude is halfway (about 6 px), so the animation matters.
EXAMPLES = {"urban_lidarhd": 1, "warsaw_styles": 24, "lion_benchmark": 1}
# As tests/python/test_golden.py: a pixel fails when a channel differs by
# more than 2/255; up to 0.5 % of pixels may fail.
FAIL_ABOVE, FAIL_PERCENT = 2.0 / 255.0, 0.5


def blend_path(name):
    return os.path.join(EXAMPLES_DIR, name + ".blend")


def golden_path(name):
    return os.path.join(GOLDEN, "legacy_%s.png" % name)


def open_example(name):
    bpy.ops.wm.open_mainfile(filepath=blend_path(name), load_ui=False)
    return bpy.context.scene


def render_open_example(name, out_path):
    """Renders the open file's scene (opened by open_example(name)) at the
    example's frame, small, to ``out_path`` (PNG, 8-bit RGB)."""
    scene = bpy.context.scene
    r = scene.render
    r.resolution_y = max(1, round(WIDTH * r.resolution_y / r.resolution_x))
    r.resolution_x = WIDTH
    r.resolution_percentage = 100
    r.dither_intensity = 0.0
    r.use_border = False
    r.use_stamp = False
    r.image_settings.file_format = 'PNG'
    r.image_settings.color_mode = 'RGB'
    r.image_settings.color_depth = '8'
    scene.frame_set(EXAMPLES[name])
    r.filepath = out_path
    bpy.ops.render.render(write_still=True)
    if not os.path.exists(out_path):
        raise RuntimeError("the render wrote no image " + out_path)
    return out_path


def idiff(reference, image, diff_image):
    """idiff's verdict with the tolerance above: (returncode, output);
    0 = pass, 1 = warning, 2 = failure, 3 = size differs, 4 = file error."""
    exe = shutil.which("idiff")
    if exe is None:
        raise RuntimeError("idiff (openimageio-tools) is needed")
    run = subprocess.run([exe, "-fail", str(FAIL_ABOVE), "-failpercent", str(FAIL_PERCENT), "-warn",
                          str(FAIL_ABOVE), "-warnpercent", str(FAIL_PERCENT), "-abs", "-scale", "10",
                          "-o", diff_image, reference, image], capture_output=True, text=True)
    return run.returncode, run.stdout + run.stderr


def _main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv:
        print(__doc__)
        sys.exit(2)
    sys.path.insert(0, os.path.abspath(argv[0]))
    import pointnpr

    print("package:", pointnpr.__file__)
    pointnpr.register()
    os.makedirs(GOLDEN, exist_ok=True)
    for name in argv[1:] or sorted(EXAMPLES):
        open_example(name)
        render_open_example(name, golden_path(name))
        print("wrote", golden_path(name))


if __name__ == "__main__":
    _main()
