"""Brush splats under light (issue 39, "light for every mark"): a colourless
scan must read as a shaded shape. `shading` auto lights the brushes of
points without colours of their own by their splat's plane; coloured
scans keep their colours; GL and native backends agree."""
import numpy as np
import pytest

import pointnpr

W, H = 200, 150


def _sphere(n=8000):
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(1.0 - z * z)
    a = 2.399963229728653 * np.arange(n)
    normals = np.column_stack([r * np.cos(a), r * np.sin(a), z])
    return normals + np.array([0.0, 0.0, -5.0]), normals.astype(np.float32)


def _render(renderer, cloud, **params):
    scene = pointnpr.Scene()
    params.setdefault("blending", "none")
    scene.add_segment("s", pointnpr.Style(mark=("brush_splats", params)), [(cloud, np.eye(4))])
    cam = pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=W, height=H)
    return np.asarray(renderer.render(scene, cam, W, H, background=(0, 0, 0, 0)).color)


def _lambert(cam_light_az=135.0, cam_light_el=45.0):
    """|n . L| of the unit sphere at (0, 0, -5) per pixel (camera light), NaN off the sphere."""
    a, e = np.radians(cam_light_az), np.radians(cam_light_el)
    light = np.array([np.sin(e) * np.cos(a), np.sin(e) * np.sin(a), np.cos(e)])
    f = 50.0 / 36.0 * W  # pixels per unit at depth 1 (lens 50 mm, sensor 36 mm, fit to width)
    y, x = np.mgrid[0:H, 0:W]
    d = np.stack([(x + 0.5 - W / 2) / f, (y + 0.5 - H / 2) / f, -np.ones_like(x, float)], -1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    c = np.array([0.0, 0.0, -5.0])
    b = d @ c
    disc = b * b - (c @ c - 1.0)
    t = b - np.sqrt(np.maximum(disc, 0.0))
    n = d * t[..., None] - c
    out = np.abs(n @ light)
    out[disc <= 0.05] = np.nan  # off the sphere or at its rim (brushes overhang it there)
    return out


@pytest.fixture(scope="module")
def sphere():
    return _sphere()


@pytest.mark.parametrize("rasterizer", ["gl", "native"])
def test_a_colourless_scan_reads_as_a_shaded_shape(renderer, sphere, rasterizer):
    pos, normals = sphere
    img = _render(renderer, pointnpr.PointCloud(pos, normals=normals), rasterizer=rasterizer)
    lum = img[..., :3].mean(-1)
    lam = _lambert()
    inside = np.isfinite(lam) & (img[..., 3] > 0.99)
    assert inside.sum() > 2000
    r = np.corrcoef(lum[inside], lam[inside])[0, 1]
    assert r > 0.9, r
    assert np.percentile(lum[inside], 95) - np.percentile(lum[inside], 5) > 0.15
    # Off: the constant colour, flat.
    flat = _render(renderer, pointnpr.PointCloud(pos, normals=normals), rasterizer=rasterizer, shading="none")
    assert np.ptp(flat[..., :3].mean(-1)[inside]) < 0.02


@pytest.mark.parametrize("rasterizer", ["gl", "native"])
def test_auto_keeps_a_coloured_scans_colours_and_diffuse_lights_them(renderer, sphere, rasterizer):
    pos, normals = sphere
    colors = np.full((len(pos), 3), 200, np.uint8)
    cloud = pointnpr.PointCloud(pos, normals=normals, colors=colors)
    auto = _render(renderer, cloud, rasterizer=rasterizer)
    none = _render(renderer, cloud, rasterizer=rasterizer, shading="none")
    lit = _render(renderer, cloud, rasterizer=rasterizer, shading="diffuse", shading_strength=1.0)
    assert auto.tobytes() == none.tobytes()
    inside = np.isfinite(_lambert()) & (lit[..., 3] > 0.99)
    assert lit[..., :3].mean(-1)[inside].mean() < none[..., :3].mean(-1)[inside].mean() - 0.1


def test_the_light_moves_with_its_azimuth(renderer, sphere):
    pos, normals = sphere
    cloud = pointnpr.PointCloud(pos, normals=normals)
    a = _render(renderer, cloud, light_azimuth=0.0, light_elevation=60.0)[..., :3].mean(-1)
    b = _render(renderer, cloud, light_azimuth=180.0, light_elevation=60.0)[..., :3].mean(-1)
    lam_a, lam_b = _lambert(0.0, 60.0), _lambert(180.0, 60.0)
    inside = np.isfinite(lam_a)
    assert np.corrcoef(a[inside], lam_a[inside])[0, 1] > 0.9
    assert np.corrcoef(b[inside], lam_b[inside])[0, 1] > 0.9


def test_gl_and_native_light_alike(renderer, sphere):
    pos, normals = sphere
    cloud = pointnpr.PointCloud(pos, normals=normals)
    gl = _render(renderer, cloud, rasterizer="gl")
    native = _render(renderer, cloud, rasterizer="native")
    both = (gl[..., 3] > 0.99) & (native[..., 3] > 0.99)
    assert np.abs(gl[..., :3] - native[..., :3])[both].mean() < 0.01
