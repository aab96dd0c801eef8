"""Makes tests/data/legacy_rasterize_anim.blend and its reference renders
tests/data/golden/legacy_anim_f<frame>.png with the add-on from BEFORE the
mark stage (styles began with a Rasterize node; the rasterizer was a scene
setting). tests/blender/test_versioning.py opens the file with the current
add-on and checks the migration against them. Made once, with the old
package; do not regenerate with a newer one (frames 1 and 6 were rendered
again from the migrated file on purpose in issue 40, when the Cartoon's
soft bands changed: "Right" runs through a Cartoon filter; frame 1 again
when the gap fill began to close the gaps between splats before it, and
all three when it began to close a notch's mouth, the outline's scallops):

    blender -b --factory-startup --python-exit-code 1 \
        --python tests/blender/make_legacy_blend.py -- <old builddir>

The scene: two collections of 7x7 points seen from above, 64x48 px.
* "Left" uses style "Animated": Rasterize with color_source never set (the
  old default "rgb"), point_size keyframed 2 px (frame 1) -> 9 px (frame 11),
  linear;
* "Right" uses style "Constant": Rasterize with color_source "constant", its
  colour keyframed red (1) -> blue (11), a Cartoon filter after it;
* the scene's rasterizer is "gl_points" (not the default).
"""
import os
import sys

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if not argv:
    print(__doc__)
    sys.exit(2)
sys.path.insert(0, os.path.abspath(argv[0]))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import bpy  # noqa: E402
import numpy as np  # noqa: E402
import pointnpr  # noqa: E402

pointnpr.register()
from pointnpr.blender import nodes  # noqa: E402

import helpers  # noqa: E402

FRAMES = (1, 6, 11)
BLEND = os.path.join(helpers.REPO, "tests", "data", "legacy_rasterize_anim.blend")
GOLDEN = os.path.join(helpers.REPO, "tests", "data", "golden")

assert not hasattr(nodes, "ROLE_MARK"), "run this with the package from before the mark stage"
scene = helpers.reset_scene()
helpers.add_camera()
pts = helpers.grid_points(1.5, 0.5, 0.0)
rgb = np.stack([(pts[:, 0] + 1.5) / 3.0, (pts[:, 1] + 1.5) / 3.0, np.full(len(pts), 0.3)], axis=1)
left = helpers.new_collection("Left")
right = helpers.new_collection("Right")
helpers.add_points("LeftPoints", left, pts + [-1.8, 0.0, 0.0], colors=rgb)
helpers.add_points("RightPoints", right, pts + [1.8, 0.0, 0.0], colors=rgb)

animated = nodes.new_style("Animated")
rast = animated.nodes["Rasterize"]
rast.point_size = 2.0
rast.keyframe_insert("point_size", frame=1)
rast.point_size = 9.0
rast.keyframe_insert("point_size", frame=11)
left.pointnpr_style = animated

constant = nodes.new_style("Constant")
rast = constant.nodes["Rasterize"]
rast.color_source = "constant"
rast.point_size = 5.0
color = nodes.property_identifier("color")
setattr(rast, color, (1.0, 0.0, 0.0, 1.0))
rast.keyframe_insert(color, frame=1)
setattr(rast, color, (0.0, 0.0, 1.0, 1.0))
rast.keyframe_insert(color, frame=11)
nodes.append_node(constant, nodes.ROLE_FILTER, "cartoon", name="Cartoon")
right.pointnpr_style = constant
for tree in (animated, constant):
    for fc in tree.animation_data.action.fcurves:
        for kp in fc.keyframe_points:
            kp.interpolation = 'LINEAR'
scene.pointnpr.rasterizer = "gl_points"
scene.world.color = (1.0, 1.0, 1.0)

bpy.ops.wm.save_as_mainfile(filepath=BLEND, compress=True)
print("wrote", BLEND)
for frame in FRAMES:
    scene.frame_set(frame)
    out = os.path.join(GOLDEN, "legacy_anim_f%d.png" % frame)
    helpers.render_to_png(out)
    print("wrote", out)
