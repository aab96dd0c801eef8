"""PSNR of the gaussians mark against the numpy reference rasterizer
(tests/python/gaussian_reference.py) on the renders of
tests/python/test_marks_gaussians.py (which requires 40 dB): PLAYBOT from the
test's two views, and 400 random splats of SH degree 0-3, colour
(premultiplied display sRGB; for the random splats also over only the
pixels whose colour fits their coverage) and opacity; then how many splats
the floater thresholds drop on PLAYBOT. The figures of docs/marks.md.

    PYTHONPATH=build:tests/python /usr/bin/python3 bench/gaussians_reference_psnr.py
"""
import numpy as np

import pointnpr
from gaussian_reference import perspective, premultiplied_srgb, psnr, random_splats, render, view_matrix
from test_marks_gaussians import PLAYBOT, H, W, _cloud, _playbot_camera, _render


def main():
    r = pointnpr.Renderer()
    d = pointnpr.read(PLAYBOT)
    A = d.attributes
    for offset in ((1.6, 0.5, -2.0), (-2.2, -0.4, 1.0)):
        view, proj = _playbot_camera(d, offset)
        res = _render(r, d.to_cloud(), view, proj)
        mine, a = premultiplied_srgb(res.color)
        ref, ra = render(d.positions, A["rotations"].astype(float), A["scales"].astype(float),
                         A["opacity"].astype(float), A["sh"].reshape(d.num_points, -1, 3).astype(float), 2,
                         view, proj, W, H)
        print("PLAYBOT view %s: colour %.1f dB, opacity %.1f dB" % (offset, psnr(mine, ref), psnr(a, ra)))
    for degree in range(4):
        means, q, scales, opacity, sh = random_splats(400, degree, seed=degree + 10)
        sh[:, 1:] *= 0.5
        view, proj = view_matrix((0.4, -3.2, 0.9), (0, 0, 0)), perspective(1.8, 1.8 * W / H, 0.1, 100.0)
        res = _render(r, _cloud(means, q, scales, opacity, sh, degree), view, proj)
        mine, a = premultiplied_srgb(res.color)
        ref, ra = render(means, q, scales, opacity, sh, degree, view, proj, W, H)
        fits = ~(ref > ra[..., None] + 1e-6).any(-1)
        print("random splats, SH degree %d: colour %.1f dB where it fits (%.1f %% of pixels), %.1f dB over all, "
              "opacity %.1f dB" % (degree, psnr(mine[fits], ref[fits]), 100 * fits.mean(), psnr(mine, ref), psnr(a, ra)))
    view, proj = _playbot_camera(d)
    for params in ({"min_opacity": 0.1}, {"max_scale": 0.05}, {"isolation": 4.0}, {"isolation": 6.0}):
        print("floaters", params, int(_render(r, d.to_cloud(), view, proj, params).stats["gaussians_floaters"]))


if __name__ == "__main__":
    main()
