"""Triangle meshes in segments (issue 15): the mesh_surface mark, meshes
composited with point segments in one depth, surface sampling, uploads.

The camera sits at the origin looking down -Z (lens 50 mm on a 36 mm wide
sensor), so a pixel's ray is known exactly and scenes have an analytic
ground truth."""
import numpy as np
import pytest

import pointnpr

W, H = 240, 180
TAN_X = 18.0 / 50.0  # half the sensor width over the focal length
TAN_Y = TAN_X * H / W


def camera(width=W, height=H):
    return pointnpr.Camera.perspective(np.eye(4), lens=50.0, width=width, height=height)


def rays(width=W, height=H):
    """Unit directions of the pixel centres (row 0 = bottom), (H, W, 3)."""
    x = ((np.arange(width) + 0.5) / width * 2.0 - 1.0) * TAN_X
    y = ((np.arange(height) + 0.5) / height * 2.0 - 1.0) * TAN_X * height / width
    X, Y = np.meshgrid(x, y)
    d = np.stack([X, Y, -np.ones_like(X)], axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def box_mesh(lo, hi, **kwargs):
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    v = np.array([[(hi if x else lo)[0], (hi if y else lo)[1], (hi if z else lo)[2]]
                  for x in (0, 1) for y in (0, 1) for z in (0, 1)])
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tri = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.int64)
    return pointnpr.TriangleMesh(v, tri, **kwargs), v, tri


def box_depth(lo, hi, d):
    """View depth (-z) of the first hit of rays from the origin with the box, inf where missed."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = lo / d, hi / d
    tmin = np.nanmax(np.minimum(t0, t1), axis=-1)
    tmax = np.nanmin(np.maximum(t0, t1), axis=-1)
    hit = (tmax >= tmin) & (tmax > 0)
    return np.where(hit, tmin * -d[..., 2], np.inf)


def sphere_depth(centre, radius, d):
    c = np.asarray(centre, float)
    b = d @ c
    disc = b * b - (c @ c - radius * radius)
    t = b - np.sqrt(np.maximum(disc, 0.0))
    return np.where(disc > 0, t * -d[..., 2], np.inf)


def sphere_points(n, centre, radius):
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(1.0 - z * z)
    a = 2.399963229728653 * np.arange(n)
    normals = np.column_stack([r * np.cos(a), r * np.sin(a), z])
    return normals * radius + np.asarray(centre), normals


def band(labels, width):
    """Pixels within `width` of a change of label (silhouettes, intersection curves)."""
    edge = np.zeros(labels.shape, bool)
    edge[:, 1:] |= labels[:, 1:] != labels[:, :-1]
    edge[:, :-1] |= labels[:, 1:] != labels[:, :-1]
    edge[1:, :] |= labels[1:, :] != labels[:-1, :]
    edge[:-1, :] |= labels[1:, :] != labels[:-1, :]
    out = edge.copy()
    for _ in range(width):
        grown = out.copy()
        grown[1:, :] |= out[:-1, :]
        grown[:-1, :] |= out[1:, :]
        grown[:, 1:] |= out[:, :-1]
        grown[:, :-1] |= out[:, 1:]
        out = grown
    return out


# A cube half inside a point-cloud sphere: the sphere (radius 1 at z = -5)
# is segment 0, the cube (side 1, centred on the sphere's right surface,
# turned toward the camera a little) segment 1.
SPHERE_C, SPHERE_R = (0.0, 0.0, -5.0), 1.0
CUBE_LO, CUBE_HI = (0.5, -0.5, -5.3), (1.5, 0.5, -4.3)


def cube_in_sphere(renderer, mode, sphere_style=None, cube_style=None):
    pos, normals = sphere_points(200000, SPHERE_C, SPHERE_R)
    sphere = pointnpr.PointCloud(pos, normals=normals.astype(np.float32))
    cube, _v, _t = box_mesh(CUBE_LO, CUBE_HI, base_color=(0.9, 0.3, 0.2))
    scene = pointnpr.Scene()
    scene.add_segment("sphere", sphere_style or pointnpr.Style(mark=("points", {"point_size": 3.0})), [sphere])
    scene.add_segment("cube", cube_style or pointnpr.Style(), [(cube, np.eye(4), "Cube")])
    return renderer.render(scene, camera(), W, H, composite={"mode": mode})


def truth():
    d = rays()
    ds, dc = sphere_depth(SPHERE_C, SPHERE_R, d), box_depth(CUBE_LO, CUBE_HI, d)
    labels = np.where(np.isinf(ds) & np.isinf(dc), -1, np.where(dc < ds, 1, 0))
    return labels, ds, dc


def test_analytic_ground_truth_matches_the_camera():
    # The cube alone: its covered pixels and depths are the ray cast's.
    r = pointnpr.Renderer()
    cube, _v, _t = box_mesh(CUBE_LO, CUBE_HI)
    scene = pointnpr.Scene()
    scene.add_segment("cube", pointnpr.Style(), [cube])
    res = r.render(scene, camera(), W, H)
    dc = box_depth(CUBE_LO, CUBE_HI, rays())
    covered = np.asarray(res.segment_index) == 0
    inside = ~band(np.isfinite(dc).astype(int), 1)
    assert np.array_equal(covered[inside], np.isfinite(dc)[inside])
    depth = np.asarray(res.depth)
    both = covered & np.isfinite(dc) & inside
    assert both.sum() > 2000
    assert np.abs(depth[both] - dc[both]).max() < 1e-4 * 5.0


@pytest.mark.parametrize("mode", ["depth_test", "inpaint"])
def test_cube_half_inside_a_point_sphere_front_surface_wins_at_every_pixel(renderer, mode):
    labels, _ds, _dc = truth()
    res = cube_in_sphere(renderer, mode)
    seg = np.asarray(res.segment_index)
    # Splats reach 1.5 px beyond the surface they sample.
    away = ~band(labels, 3)
    assert (labels[away] == 1).sum() > 1500 and (labels[away] == 0).sum() > 5000
    assert int((seg[away] != labels[away]).sum()) == 0
    # Depth pass: the front surface's depth.
    depth = np.asarray(res.depth)
    cube_px = away & (labels == 1)
    assert np.abs(depth[cube_px] - _dc[cube_px]).max() < 1e-3


def test_cube_half_inside_a_point_sphere_with_filters_is_wrong_only_in_the_filters_footprint(renderer):
    labels, _ds, _dc = truth()
    cartoon = pointnpr.Style(filters=[("cartoon", {})])
    for mode in ("depth_test", "inpaint"):
        res = cube_in_sphere(renderer, mode, cube_style=cartoon,
                             sphere_style=pointnpr.Style(mark=("points", {"point_size": 3.0}),
                                                         filters=[("cartoon", {})]))
        seg = np.asarray(res.segment_index)
        away = ~band(labels, 8)
        assert int((seg[away] != labels[away]).sum()) == 0, mode


def test_layering_puts_the_later_segment_on_top_everywhere(renderer):
    labels, ds, dc = truth()
    res = cube_in_sphere(renderer, "layering")
    seg = np.asarray(res.segment_index)
    # Away from the cube's hidden silhouette, too.
    away = ~band(labels * 4 + np.isfinite(dc) * 2 + np.isfinite(ds), 3)
    # The cube (drawn last) covers every pixel it projects to, also where
    # the sphere is in front: exactly those pixels are wrong.
    expected_wrong = away & np.isfinite(dc) & (ds < dc)
    assert expected_wrong.sum() > 500
    wrong = away & (seg != labels)
    assert np.array_equal(wrong, expected_wrong)


def test_cartoon_outlines_of_a_mesh_keep_their_depth_and_hide_behind_a_scan_in_front(renderer):
    # A building (box) at 6 m with a cartoon; a scan (point plane) at 5 m
    # covering the box's left half, in front of it.
    building, _v, _t = box_mesh((-1.0, -0.8, -6.5), (1.0, 0.8, -6.0), base_color=(0.8, 0.8, 0.7))
    xs, ys = np.meshgrid(np.arange(-2.0, 0.0, 0.01), np.arange(-1.5, 1.5, 0.01))
    plane = np.column_stack([xs.ravel(), ys.ravel(), np.full(xs.size, -5.0)])
    scan = pointnpr.PointCloud(plane, colors=np.tile(np.array([[40, 120, 40]], np.uint8), (len(plane), 1)))
    scene = pointnpr.Scene()
    scene.add_segment("scan", pointnpr.Style(mark=("points", {"point_size": 3.0})), [scan])
    scene.add_segment("building", pointnpr.Style(filters=[("cartoon", {})]), [building])
    res = renderer.render(scene, camera(), W, H, composite={"mode": "inpaint"})
    seg, depth = np.asarray(res.segment_index), np.asarray(res.depth)
    d = rays()
    building_px = np.isfinite(box_depth((-1.0, -0.8, -6.5), (1.0, 0.8, -6.0), d))
    # x of the ray at depth 5: the scan covers x < 0 at z = -5.
    scan_px = (d[..., 0] / -d[..., 2] * 5.0 < 0.0) & (np.abs(d[..., 1] / -d[..., 2] * 5.0) < 1.5)
    labels = np.where(scan_px, 0, np.where(building_px, 1, -1))
    away = ~band(labels, 2)
    # Where the scan is in front, the building (outlines included) never shows.
    assert int((seg[away & scan_px] == 1).sum()) == 0
    # The outlines the cartoon drew beyond the building's silhouette, on the
    # empty side: they belong to the building and keep its depth.
    outline = (seg == 1) & ~building_px & ~scan_px
    assert outline.sum() > 50
    assert np.all(np.abs(depth[outline] - 6.0) < 0.6)


def test_points_and_faces_of_one_segment_occlude_each_other_per_pixel(renderer):
    # One segment: a point plane at 5 m over the left half, a mesh quad at 6 m.
    quad = pointnpr.TriangleMesh(np.array([[-1, -1, -6], [1, -1, -6], [1, 1, -6], [-1, 1, -6]], float),
                                 np.array([[0, 1, 2], [0, 2, 3]]), base_color=(1.0, 0.0, 0.0))
    xs, ys = np.meshgrid(np.arange(-1.0, 0.0, 0.01), np.arange(-1.0, 1.0, 0.01))
    pts = np.column_stack([xs.ravel(), ys.ravel(), np.full(xs.size, -5.0)])
    cloud = pointnpr.PointCloud(pts, colors=np.tile(np.array([[0, 0, 255]], np.uint8), (len(pts), 1)))
    scene = pointnpr.Scene()
    scene.add_segment("both", pointnpr.Style(mark=("points", {"point_size": 3.0}),
                                             surface={"shading": "none"}), [cloud, quad])
    res = renderer.render(scene, camera(), W, H)
    color, depth = np.asarray(res.color), np.asarray(res.depth)
    # Centre row: left of centre the points at 5 m, right of it the quad at 6 m.
    row = H // 2
    left, right = W // 2 - 30, W // 2 + 30
    assert color[row, left, 2] > 0.9 and color[row, left, 0] < 0.05 and depth[row, left] == pytest.approx(5.0, abs=1e-3)
    assert color[row, right, 0] > 0.9 and color[row, right, 2] < 0.05 and depth[row, right] == pytest.approx(6.0, abs=1e-3)


def test_a_mesh_far_from_the_origin_renders_the_same_bytes():
    r = pointnpr.Renderer()
    offset = np.array([1.0e6, 5.0e6, 0.0])
    out = []
    for shift in (np.zeros(3), offset):
        cube, _v, _t = box_mesh(np.array(CUBE_LO) + shift, np.array(CUBE_HI) + shift, base_color=(0.5, 0.6, 0.7))
        m = np.eye(4)
        m[:3, 3] = -shift
        scene = pointnpr.Scene()
        scene.add_segment("cube", pointnpr.Style(), [(cube, m)])
        res = r.render(scene, camera(), W, H)
        out.append((np.asarray(res.color).copy(), np.asarray(res.depth).copy()))
    assert np.array_equal(out[0][0], out[1][0])
    assert np.abs(out[0][1] - out[1][1]).max() < 1e-5


def test_colour_sources_base_colour_corner_colours_and_texture(renderer):
    v = np.array([[-1, -1, -5], [1, -1, -5], [1, 1, -5], [-1, 1, -5]], float)
    tri = np.array([[0, 1, 2], [0, 2, 3]])
    flat = {"shading": "none"}

    def centre_colours(mesh, surface=flat):
        scene = pointnpr.Scene()
        scene.add_segment("m", pointnpr.Style(surface=surface), [mesh])
        res = renderer.render(scene, camera(), W, H)
        return np.asarray(res.color)

    # Base colour (display sRGB 0.5 -> scene-linear 0.214 in the frame).
    c = centre_colours(pointnpr.TriangleMesh(v, tri, base_color=(0.5, 0.5, 0.5)))
    assert c[H // 2, W // 2, 0] == pytest.approx(0.214, abs=0.01)
    # Per-corner colours: triangle 0 red, triangle 1 blue (no blending across
    # the diagonal, which vertex colours could not do).
    corner = np.array([[255, 0, 0]] * 3 + [[0, 0, 255]] * 3, np.uint8)
    c = centre_colours(pointnpr.TriangleMesh(v, tri, colors=corner, base_color=(0.5, 0.5, 0.5)))
    assert c[H // 2, W // 2 + 20, 0] > 0.99 and c[H // 2 + 20, W // 2 - 20, 2] > 0.99
    # The texture: left half green, right half white, by UV.
    tex = np.zeros((4, 4, 4), np.uint8)
    tex[..., 3] = 255
    tex[:, :2, 1] = 255
    tex[:, 2:, :3] = 255
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
    mesh = pointnpr.TriangleMesh(v, tri, uvs=uv, texture=tex, base_color=(0.5, 0.5, 0.5))
    c = centre_colours(mesh)
    assert c[H // 2, W // 2 - 40, 1] > 0.99 and c[H // 2, W // 2 - 40, 0] < 0.01
    assert np.all(c[H // 2, W // 2 + 40, :3] > 0.99)
    # color_source constant overrides the texture.
    c = centre_colours(mesh, {"shading": "none", "color_source": "constant", "color": (0, 0, 0, 1)})
    assert np.all(c[H // 2, W // 2 - 40, :3] < 0.01)


def test_flat_and_smooth_shading_follow_the_light(renderer):
    # A cube seen from the front-right: flat shading gives each visible face
    # one shade, lit faces brighter.
    cube, _v, _t = box_mesh((-0.5, -0.5, -5.5), (0.5, 0.5, -4.5), base_color=(1, 1, 1))
    m = np.eye(4)
    ang = np.radians(30)
    m[:3, :3] = [[np.cos(ang), 0, np.sin(ang)], [0, 1, 0], [-np.sin(ang), 0, np.cos(ang)]]
    m[:3, 3] = np.array([0, 0, -5.0]) - m[:3, :3] @ np.array([0, 0, -5.0])

    def render(surface):
        scene = pointnpr.Scene()
        scene.add_segment("c", pointnpr.Style(surface=surface), [(cube, m)])
        return np.asarray(renderer.render(scene, camera(), W, H).color)

    # Light from the camera's right (camera space): the face turned right is lit.
    lit = render({"shading": "flat", "light_space": "camera", "light_azimuth": 0.0, "light_elevation": 80.0})
    front, side = lit[H // 2, W // 2 - 25, 0], lit[H // 2, W // 2 + 25, 0]
    assert side > front + 0.05
    # One face, one shade (flat).
    assert np.ptp(lit[H // 2 - 10:H // 2 + 10, W // 2 - 30:W // 2 - 20, 0]) < 1e-4
    none = render({"shading": "none"})
    assert none[H // 2, W // 2 - 25, 0] > front


def test_mesh_modes_hand_meshes_to_the_point_mark(renderer):
    cube, v, _t = box_mesh(CUBE_LO, CUBE_HI)
    for surface, expected in (({"meshes": "points"}, 8), ({"meshes": "sampled", "sample_density": 1000.0}, None)):
        scene = pointnpr.Scene()
        scene.add_segment("c", pointnpr.Style(surface=surface), [cube])
        res = renderer.render(scene, camera(), W, H)
        assert res.stats.get("triangles_drawn", 0) == 0
        if expected is not None:
            assert res.stats["points_drawn"] == expected
        else:  # 6 faces of 1 m^2 at 1000 / m^2
            assert abs(res.stats["points_drawn"] - 6000) < 6 * 4 * np.sqrt(1000)
    # A mesh without faces is drawn as points in the default surface mode.
    dots = pointnpr.TriangleMesh(v, np.zeros((0, 3), np.int64))
    scene = pointnpr.Scene()
    scene.add_segment("c", pointnpr.Style(), [dots])
    assert renderer.render(scene, camera(), W, H).stats["points_drawn"] == 8


def test_surface_sampling_is_seeded_by_triangle_and_lies_on_the_surface():
    cube, v, tri = box_mesh(CUBE_LO, CUBE_HI, base_color=(0.2, 0.4, 0.6))
    a = cube.sample_surface(2000.0)
    again, _v, _t = box_mesh(CUBE_LO, CUBE_HI, base_color=(0.2, 0.4, 0.6))
    b = again.sample_surface(2000.0)
    assert a.num_points == b.num_points and abs(a.num_points - 12000) < 4 * np.sqrt(12000)
    assert a.has("normals") and a.has("colors")
    # Same points, same ids: a camera move cannot make them pop (they do not
    # depend on the view at all), and a second mesh of the same data agrees.
    assert np.array_equal(a.point_index, b.point_index)
    r = pointnpr.Renderer()
    dense = [m.sample_surface(20000.0) for m in (cube, again)]
    res = [r.render(_scene(c), camera(), W, H) for c in dense]
    assert np.array_equal(np.asarray(res[0].color), np.asarray(res[1].color))
    # On the cube's surface: every sampled point (rendered depth) is on a face.
    d = rays()
    dc = box_depth(CUBE_LO, CUBE_HI, d)
    depth = np.asarray(res[0].depth)
    # The face toward the camera (z = -4.3; the side face in view is too
    # oblique for a pixel's depth to be sharp): its points, or points further
    # back showing through the gaps, never anything in front.
    front = (depth < 1e9) & np.isclose(dc, 4.3) & ~band(np.isclose(dc, 4.3).astype(int), 2)
    assert front.sum() > 500
    assert np.all(depth[front] >= 4.3 - 1e-4)
    assert np.median(depth[front]) == pytest.approx(4.3, abs=1e-4)
    # The cached cloud is the same object for the same density.
    assert cube.sample_surface(20000.0).id == dense[0].id and cube.sample_surface(1000.0).id != dense[0].id


def _scene(c):
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(mark=("points", {"point_size": 2.0})), [c])
    return scene


def test_object_space_marks_take_points_sampled_on_a_mesh(renderer):
    cube, _v, _t = box_mesh(CUBE_LO, CUBE_HI, base_color=(0.9, 0.9, 0.9))
    scene = pointnpr.Scene()
    scene.add_segment("c", pointnpr.Style(mark="hatching", surface={"meshes": "sampled", "sample_density": 3000.0}),
                      [cube])
    res = renderer.render(scene, camera(), W, H, capture_marks=True)
    assert len(res.marks["point_id"]) > 100
    assert (np.asarray(res.segment_index) == 0).sum() > 1000


def test_a_mesh_is_uploaded_once_and_only_what_the_style_reads():
    r = pointnpr.Renderer()
    v = np.array([[-1, -1, -5], [1, -1, -5], [1, 1, -5], [-1, 1, -5]], float)
    tri = np.array([[0, 1, 2], [0, 2, 3]])
    colors = np.full((4, 3), 200, np.uint8)

    def draw(mesh, surface):
        scene = pointnpr.Scene()
        scene.add_segment("m", pointnpr.Style(surface=surface), [mesh])
        r.render(scene, camera(), W, H)

    mesh = pointnpr.TriangleMesh(v, tri, colors=colors)
    draw(mesh, {"shading": "flat", "color_source": "constant"})
    assert r.mesh_upload_count() == 1  # positions only
    draw(mesh, {"shading": "flat", "color_source": "constant"})
    assert r.mesh_upload_count() == 1  # unchanged: nothing read again
    draw(mesh, {"shading": "smooth", "color_source": "colors"})
    assert r.mesh_upload_count() == 3  # + normals, colours
    # An edited mesh (a new TriangleMesh, as the add-on makes on a depsgraph
    # update) is uploaded once, and the old one is dropped.
    edited = pointnpr.TriangleMesh(v + [0, 0, -0.5], tri, colors=colors)
    del mesh
    draw(edited, {"shading": "smooth", "color_source": "colors"})
    assert r.mesh_upload_count() == 6 and r.cached_meshes() == 1
    draw(edited, {"shading": "smooth", "color_source": "colors"})
    assert r.mesh_upload_count() == 6


@pytest.mark.parametrize("kwargs,message", [
    (dict(positions=[[0, 0, np.nan], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]]), "non-finite"),
    (dict(positions=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 3]]), "uses vertex 3 of 3"),
    (dict(positions=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, -1]]), "negative"),
    (dict(positions=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1]]), "(T,3)"),
    (dict(positions=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0.5, 1, 2]]), "integer"),
    (dict(positions=[[0, 0, 0], [1, 0, 0]], triangles=np.zeros((0, 3), int), colors=np.zeros((5, 3))),
     "one row per vertex"),
    (dict(positions=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]], uvs=[[0, np.inf]] * 3), "finite"),
    (dict(positions=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]], texture=np.zeros((4, 4, 3))),
     "(H,W,4)"),
    (dict(positions=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]], base_color=(1, 1)), "RGB"),
])
def test_bad_meshes_raise_clear_errors(kwargs, message):
    with pytest.raises(pointnpr.ParameterError, match=message.replace("(", r"\(").replace(")", r"\)")):
        pointnpr.TriangleMesh(**kwargs)


def test_styles_take_surface_parameters_and_refuse_mesh_surface_as_their_mark():
    s = pointnpr.Style(surface={"meshes": "sampled", "sample_density": 50.0})
    assert s.surface["meshes"] == "sampled" and s.surface["sample_density"] == 50.0
    with pytest.raises(pointnpr.ParameterError, match="surface"):
        pointnpr.Style(mark="mesh_surface")
    with pytest.raises(pointnpr.ParameterError):
        pointnpr.Style(surface={"meshes": "wireframe"})
    assert set(pointnpr.Style().mesh_source_attributes) == {"base_color", "colors", "texture", "uvs"}
    assert pointnpr.Style(surface={"color_source": "constant"}).mesh_source_attributes == []


def wavy_mesh(n, z0, **kwargs):
    """A wavy grid of n x n quads with random per-corner colours and a random
    texture: every pixel differs, so any tile seam would show."""
    rng = np.random.default_rng(7)
    u, v = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    x, y = (u - 0.5) * 4.0, (v - 0.5) * 3.0
    z = z0 + 0.5 * np.sin(3 * x) * np.cos(2 * y)
    verts = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    idx = np.arange((n + 1) * (n + 1)).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    uvs = np.column_stack([u.ravel(), v.ravel()]).astype(np.float32)
    texture = rng.integers(0, 255, (64, 64, 4)).astype(np.uint8)
    colors = rng.integers(0, 255, (len(tri) * 3, 3)).astype(np.uint8)
    return pointnpr.TriangleMesh(verts, tri, uvs=uvs, texture=texture, colors=colors, **kwargs)


@pytest.mark.parametrize("surface", [
    {},                                                         # auto: the texture, smooth shading
    {"color_source": "colors", "shading": "flat"},
    {"color_source": "base_color", "shading": "smooth", "light_space": "world"},
    {"color_source": "constant", "shading": "none"},
])
@pytest.mark.parametrize("ortho", [False, True])
def test_mesh_surfaces_tiled_are_the_bytes_of_the_whole_frame(renderer, surface, ortho):
    # A wavy textured mesh with a point sphere in front and a filtered second
    # segment; a triangle that reaches behind the camera crosses the frame.
    mesh = wavy_mesh(24, -6.0, base_color=(0.3, 0.6, 0.9))
    near_plane = pointnpr.TriangleMesh([[-3, -1, -4], [3, -1, -4], [0, -0.2, 2]], [[0, 1, 2]],
                                       base_color=(0.9, 0.8, 0.1))
    pos, normals = sphere_points(20000, (0.8, 0.2, -5.0), 0.7)
    sphere = pointnpr.PointCloud(pos, normals=normals.astype(np.float32))
    scene = pointnpr.Scene()
    scene.add_segment("site", pointnpr.Style(mark=("points", {"point_size": 2.0}), surface=surface,
                                             inpaint={"radius": 3}),
                      [sphere, (mesh, np.eye(4), "Wavy"), (near_plane, np.eye(4), "Ramp")])
    scene.add_segment("toon", pointnpr.Style(surface=surface, filters=[("cartoon", {})]),
                      [(wavy_mesh(6, -4.5), np.diag([0.3, 0.3, 1.0, 1.0]), "Small")])
    width, height = 301, 233
    cam = (pointnpr.Camera.orthographic(np.eye(4), ortho_scale=5.0, width=width, height=height) if ortho
           else pointnpr.Camera.perspective(np.eye(4), lens=30.0, width=width, height=height))
    whole = renderer.render(scene, cam, width, height)
    tiled = renderer.render(scene, cam, width, height, tile_size=64)
    assert whole.stats["tiles"] == 1 and tiled.stats["tiles"] > 4
    assert not any("does not draw in tiles" in w for w in tiled.warnings), tiled.warnings
    color = np.asarray(whole.color)
    assert color[..., 3].mean() > 0.5  # a picture, not an empty frame
    if not ortho:
        assert color[: height // 8, :, 3].mean() > 0.99  # the triangle reaching behind the camera: the lowest rows
    for name in ("color", "depth", "segment_index"):
        a, b = np.asarray(getattr(whole, name)), np.asarray(getattr(tiled, name))
        assert a.tobytes() == b.tobytes(), f"{name}: {int(np.count_nonzero(a != b))} values differ"


def test_mesh_surfaces_tile_within_the_memory_budget(renderer):
    cube, _v, _t = box_mesh(CUBE_LO, CUBE_HI, base_color=(0.9, 0.3, 0.2))
    scene = pointnpr.Scene()
    scene.add_segment("cube", pointnpr.Style(), [(cube, np.eye(4), "Cube")])
    whole = renderer.render(scene, camera(), W, H)
    tight = renderer.render(scene, camera(), W, H, memory_budget_gb=0.004)
    assert tight.stats["tiles"] > 1 and not tight.warnings, tight.warnings
    assert np.asarray(whole.color).tobytes() == np.asarray(tight.color).tobytes()


def test_a_mesh_drawn_as_points_takes_the_mean_of_its_vertices_corner_colours(renderer):
    # Two triangles sharing the diagonal's vertices 0 and 2: red and blue corners.
    v = np.array([[-1, -1, -5], [1, -1, -5], [1, 1, -5], [-1, 1, -5]], float)
    tri = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    corner = np.array([[255, 0, 0]] * 3 + [[0, 0, 255]] * 3, np.uint8)
    mesh = pointnpr.TriangleMesh(v, tri, colors=corner)
    scene = pointnpr.Scene()
    style = pointnpr.Style(mark=("points", {"point_size": 9.0, "color_source": "rgb"}), surface={"meshes": "points"})
    scene.add_segment("m", style, [mesh])
    res = renderer.render(scene, camera(), W, H)
    assert not any("colors" in w for w in res.warnings), res.warnings
    img = np.asarray(res.color)
    covered = img[..., 3] > 0.5
    rgb = img[covered][:, :3]
    # Vertex 1 is only red, vertex 3 only blue, 0 and 2 half of each (purple).
    assert (rgb[:, 0] > 0.9).any() and (rgb[:, 2] > 0.9).any()
    purple = (rgb[:, 0] > 0.1) & (rgb[:, 0] < 0.5) & (rgb[:, 2] > 0.1) & (rgb[:, 2] < 0.5)
    assert purple.any()
