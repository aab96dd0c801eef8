"""The hatching mark's depth discs (issue 39): by default sized from the
scan's own median spacing, so they close a surface at any density. With a
fixed pixel size a sparse scan's discs leave gaps, and the strokes of the
surface behind show through the one in front."""
import numpy as np

import pointnpr

W, H = 320, 240


def _two_planes(spacing):
    """A red plane at z = 0 in front of a blue one at z = -0.5, both
    sampled on a grid of `spacing`, normals toward the camera (+z)."""
    g = np.arange(-1.5, 1.5, spacing)
    x, y = np.meshgrid(g, g)
    n = x.size
    pos = np.concatenate([np.stack([x.ravel(), y.ravel(), np.full(n, z)], 1) for z in (0.0, -0.5)])
    colors = np.concatenate([np.tile(np.uint8([230, 40, 40]), (n, 1)), np.tile(np.uint8([40, 40, 230]), (n, 1))])
    return pointnpr.PointCloud(pos, normals=np.tile([0.0, 0.0, 1.0], (2 * n, 1)), colors=colors)


def _back_share(renderer, cloud, extra):
    """Share of the front plane's pixels where the back plane's (blue)
    strokes show."""
    params = {"coloring": "point", "color_source": "rgb", "point_blend": 0.0, "opacity": 1.0,
              "alpha_jitter": 0.0, "density": 1.0, "cross_hatch": 1.0, "ambient": 0.0, "light_space": "world", "light_elevation": -60.0, **extra}
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("hatching", params)), [(cloud, np.eye(4))])
    cam = pointnpr.Camera.perspective(pointnpr.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0)),
                                      lens=35.0, clip_start=0.1, clip_end=100.0, width=W, height=H)
    img = np.asarray(renderer.render(scene, cam, W, H, background=(1, 1, 1, 1)).color)[H // 4:3 * H // 4, W // 4:3 * W // 4]
    blue = (img[..., 2] > img[..., 0] + 0.2) & (img[..., 2] > 0.3)
    return float(blue.mean())


def test_spacing_discs_hide_the_strokes_behind_a_sparse_surface_where_fixed_pixel_discs_leave_gaps(renderer):
    spacing = 0.12  # about 12 px apart on screen: 4 px discs leave most of the plane open
    cloud = _two_planes(spacing)
    fixed = _back_share(renderer, cloud, {"depth_disc": "pixels", "depth_size": 4.0})
    spacing_discs = _back_share(renderer, cloud, {})
    assert fixed > 0.02, fixed  # the back plane shows through the gaps
    assert spacing_discs < 0.1 * fixed, (spacing_discs, fixed)
