"""Geometry analysis and segmentation from Python (docs/geometry.md)."""
import os

import numpy as np
import pytest

import pointnpr
from conftest import plane

IO_DATA = os.path.join(os.path.dirname(__file__), "..", "data", "io")


def sphere(n, noise=0.0, seed=0):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return d * (1.0 + noise * rng.normal(size=(n, 1))), d


def angles_deg(a, b):
    cos = np.abs(np.sum(a * b, axis=1)) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1)
    return np.degrees(np.arccos(np.clip(cos, 0.0, 1.0)))


def test_normals_of_a_noisy_sphere_are_accurate_and_oriented():
    p, truth = sphere(5000, noise=0.003)
    n = pointnpr.estimate_normals(p, k=16)
    assert n.shape == (5000, 3) and n.dtype == np.float32
    assert np.all(np.isfinite(n))
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-5)
    err = angles_deg(n, truth)
    assert err.mean() < 4.0 and np.percentile(err, 95) < 8.0
    # Consistent orientation (no viewpoint): all outward, the top points up.
    assert np.all(np.sum(n * truth, axis=1) > 0)
    inward = pointnpr.estimate_normals(p, k=16, orient_toward=(0, 0, 0))
    assert np.all(np.sum(inward * truth, axis=1) < 0)
    down = pointnpr.estimate_normals(p, k=16, orient_direction=(0, 0, -1))
    assert np.all(down[:, 2] <= 0)
    with pytest.raises(pointnpr.ParameterError):
        pointnpr.estimate_normals(p, orient_toward=(0, 0, 0), orient_direction=(0, 0, 1))


def test_results_follow_the_input_order_and_a_million_metre_offset_changes_nothing():
    p, _ = sphere(3000, noise=0.002, seed=1)
    perm = np.random.default_rng(2).permutation(len(p))
    a = pointnpr.estimate_normals(p, k=12)
    b = pointnpr.estimate_normals(p[perm], k=12)
    assert np.all(np.sum(a[perm] * b, axis=1) > 0.9999)
    far = p + np.array([1e6, -2e6, 1e6])
    c = pointnpr.estimate_normals(far, k=12)
    assert np.all(np.sum(a * c, axis=1) > 0.9999)
    r0, e0 = pointnpr.local_resolution(p, k=6)
    r1, e1 = pointnpr.local_resolution(far, k=6)
    np.testing.assert_allclose(r0, r1, atol=1e-6)
    np.testing.assert_allclose(e0, e1, atol=1e-6)
    np.testing.assert_array_equal(pointnpr.connected_components(p, 5, 3), pointnpr.connected_components(far, 5, 3))


def test_degenerate_inputs_give_documented_results():
    same = np.tile([[5.0, 6.0, 7.0]], (20, 1))
    n = pointnpr.estimate_normals(same, k=8)
    np.testing.assert_array_equal(n, np.tile([[0, 0, 1]], (20, 1)))
    np.testing.assert_array_equal(pointnpr.curvature(same, k=8), 0)
    r, eps = pointnpr.local_resolution(same, k=4)
    np.testing.assert_array_equal(r, 0)
    np.testing.assert_array_equal(eps, 0)
    np.testing.assert_array_equal(pointnpr.connected_components(same, 8, 1), 0)

    line = np.outer(np.arange(50) * 0.1, [1.0, 0.0, 0.0])
    n = pointnpr.estimate_normals(line, k=8)
    np.testing.assert_allclose(n[:, 0], 0.0, atol=1e-5)  # perpendicular to the line
    d, err = pointnpr.line_fit(line, k=5)
    np.testing.assert_allclose(np.abs(d[:, 0]), 1.0, atol=1e-5)
    np.testing.assert_allclose(err, 0.0, atol=1e-6)
    # The line is one chain: every point but its root links to a neighbour
    # 0.1 away along it, and it has two free ends; a mask leaves the rest out.
    to_parent, ends = pointnpr.feature_chains(line, k=5)
    linked = np.linalg.norm(to_parent, axis=1) > 0
    assert linked.sum() == 49 and ends.dtype == np.uint8
    np.testing.assert_allclose(np.abs(to_parent[linked, 0]), 0.1, atol=1e-6)
    assert (ends & 1).astype(bool).sum() + (ends & 2).astype(bool).sum() == 2
    to_parent, _ = pointnpr.feature_chains(line, k=5, mask=np.arange(50) < 30)
    assert (np.linalg.norm(to_parent, axis=1) > 0).sum() == 29 and not to_parent[30:].any()

    three = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    n = pointnpr.estimate_normals(three, k=30)  # k larger than the cloud
    np.testing.assert_allclose(np.abs(n[:, 2]), 1.0, atol=1e-6)
    idx, dist = pointnpr.knn(three, 30)
    assert idx.shape == (3, 3) and np.all(dist[:, 0] == 0)

    one = np.array([[1e6, 2e6, 3.0]])
    assert pointnpr.estimate_normals(one).tolist() == [[0.0, 0.0, 1.0]]
    assert pointnpr.connected_components(one, 8, 1).tolist() == [0]
    assert pointnpr.connected_components(one, 8, 2).tolist() == [-1]

    empty = np.zeros((0, 3))
    assert pointnpr.estimate_normals(empty).shape == (0, 3)
    assert pointnpr.curvature(empty).shape == (0,)
    assert pointnpr.connected_components(empty).shape == (0,)

    with pytest.raises(pointnpr.Error):
        pointnpr.estimate_normals(np.array([[0.0, np.nan, 0.0]]))
    with pytest.raises(pointnpr.Error):
        pointnpr.estimate_normals(same, k=0)
    with pytest.raises(pointnpr.Error):
        pointnpr.connected_components(same, level=22)


def test_duplicated_points_count_as_neighbours_at_distance_zero():
    p, _ = sphere(1000, seed=3)
    twice = np.vstack([p, p])
    r, _ = pointnpr.local_resolution(twice, k=1)
    np.testing.assert_array_equal(r, 0)
    n = pointnpr.estimate_normals(twice, k=16)
    assert np.all(np.sum(n[:1000] * n[1000:], axis=1) > 0.99999)


def test_local_resolution_and_outliers():
    xs, ys = np.meshgrid(np.arange(20) * 0.25, np.arange(20) * 0.25)
    grid = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(400)])
    r, eps = pointnpr.local_resolution(grid, k=4)
    interior = 10 * 20 + 10
    assert r[interior] == pytest.approx(0.25, abs=1e-6) and eps[interior] == pytest.approx(0.0, abs=1e-6)
    noisy = np.vstack([grid, [[20.0, 20.0, 20.0]]])
    keep = pointnpr.remove_outliers(noisy, k=8, std_ratio=2.0)
    assert keep.dtype == bool and not keep[-1] and keep[:-1].all()


def test_feature_degree_marks_sharp_edges_and_colour_borders():
    rng = np.random.default_rng(4)
    u = rng.random((4000, 2))
    top = np.column_stack([u[:2000, 0], u[:2000, 1], np.zeros(2000)])
    side = np.column_stack([np.zeros(2000), u[2000:, 1], u[2000:, 0]])
    p = np.vstack([top, side])
    f = pointnpr.feature_degree(p, k=16)
    assert f.min() >= 0 and f.max() <= 1
    d = np.maximum(p[:, 0], p[:, 2])
    assert f[d < 0.03].mean() > 0.3 and f[d > 0.3].mean() < 0.02
    flat = np.column_stack([u[:, 0], u[:, 1], np.zeros(4000)])
    colors = np.where(flat[:, :1] < 0.5, 0, 255).astype(np.uint8).repeat(3, axis=1)
    f = pointnpr.feature_degree(flat, k=12, colors=colors, color_weight=1.0)
    border = np.abs(flat[:, 0] - 0.5) < 0.01
    assert f[border].mean() > 0.5 and f[np.abs(flat[:, 0] - 0.5) > 0.2].max() == 0


def test_connected_components_26_connectivity_and_min_points():
    # Cube edge 1.01 * extent; level 2 -> cells of 1.01*9/4 = 2.27 m.
    blob_a = np.array([[0.0, 0, 0], [0.5, 0, 0], [1.0, 0, 0]])
    diag = np.array([[3.0, 3.0, 3.0]])          # the diagonal neighbour cell: joins blob_a
    far = np.array([[9.0, 9.0, 0.0], [9.0, 8.5, 0.0]])
    lonely = np.array([[9.0, 0.0, 9.0]])
    p = np.vstack([blob_a, diag, far, lonely])
    labels = pointnpr.connected_components(p, level=2, min_points=1)
    assert labels.dtype == np.int32
    assert len(set(labels[:4])) == 1 and labels[4] == labels[5] and len(set(labels)) == 3
    assert labels[0] == 0 and labels[4] == 1 and labels[6] == 2  # by decreasing size
    labels = pointnpr.connected_components(p, level=2, min_points=2)
    assert labels[6] == -1 and labels[0] == 0 and labels[4] == 1
    # A single-point segment is a component of its own when min_points is 1.
    assert (pointnpr.connected_components(p, level=2, min_points=1) == 2).sum() == 1


def test_region_growing_separates_colours_on_one_surface():
    xs, ys = np.meshgrid(np.arange(40) * 0.02, np.arange(20) * 0.02)
    p = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)])
    colors = np.where(p[:, :1] < 0.39, [[200, 30, 30]], [[30, 30, 200]]).astype(np.uint8)
    colors[5] = [90, 30, 30]        # a speck: too small, merged into its surroundings
    labels = pointnpr.region_growing_rgb(p, colors, distance_threshold=0.05, point_color_threshold=10,
                                         region_color_threshold=10, min_cluster_size=5)
    assert labels.dtype == np.int32
    assert set(labels.tolist()) == {0, 1}
    assert len(set(labels[p[:, 0] < 0.39])) == 1 and len(set(labels[p[:, 0] > 0.39])) == 1
    # A cloud whose colours come with it.
    cloud = pointnpr.PointCloud(p, colors=colors)
    by_cloud = pointnpr.region_growing_rgb(cloud, distance_threshold=0.05, point_color_threshold=10,
                                           region_color_threshold=10, min_cluster_size=5)
    assert set(by_cloud.tolist()) == {0, 1}
    big = pointnpr.region_growing_rgb(p, colors, distance_threshold=0.05, point_color_threshold=10,
                                      region_color_threshold=10, min_cluster_size=5, max_cluster_size=300)
    assert set(big.tolist()) == {-1}  # both regions exceed the maximum
    with pytest.raises(pointnpr.Error):
        pointnpr.region_growing_rgb(p)  # positions without colours


def test_split_by_attribute():
    groups = pointnpr.split_by_attribute(np.array([2, 6, 2, 9, 6, 2], np.uint8))
    assert list(groups) == [2, 6, 9]
    assert groups[2].tolist() == [0, 2, 5] and groups[9].tolist() == [3]
    assert pointnpr.split_by_attribute(np.array([], np.int64)) == {}


def test_las_classification_split_matches_numpy():
    data = pointnpr.read(os.path.join(IO_DATA, "laspy_nebraska_classified.las"))
    cls = np.asarray(dict(data.attributes)["classification"])
    groups = pointnpr.split_by_attribute(cls)
    assert sorted(groups) == sorted(np.unique(cls).tolist())
    for value, idx in groups.items():
        np.testing.assert_array_equal(idx, np.nonzero(cls == value)[0])


def test_a_cloud_computes_nothing_until_asked_then_caches(renderer, camera):
    cloud = plane(-1, 1, -1, 1, -5, 0.05, (200, 100, 50))
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(filters=[("cartoon", {})]), [cloud])
    renderer.render(scene, camera, 320, 240)
    # No style needs normals: none computed; the filters' point spacing only
    # (ScanSampling: the distances to the 8 nearest neighbours, itself included in the kNN).
    assert sorted(pointnpr.computed_attributes(cloud)) == ["knn:9", "points", "surface_resolution:8"]
    n1 = pointnpr.estimate_normals(cloud, k=10)
    assert "normals:10:consistent" in pointnpr.computed_attributes(cloud)
    before = pointnpr.computed_attributes(cloud)
    n2 = pointnpr.estimate_normals(cloud, k=10)
    assert pointnpr.computed_attributes(cloud) == before
    np.testing.assert_array_equal(n1, n2)
    np.testing.assert_allclose(np.abs(n1[:, 2]), 1.0, atol=1e-5)
    pointnpr.curvature(cloud, k=10)  # served from the cached PCA
    assert [a for a in pointnpr.computed_attributes(cloud) if a.startswith("pca")] == ["pca:10"]


def test_a_shaded_style_estimates_normals_once_for_the_cloud(renderer, camera):
    cloud = plane(-1, 1, -1, 1, -5, 0.05, (200, 100, 50))
    scene = pointnpr.Scene()
    scene.add_segment("s", pointnpr.Style(rasterize={"shading": "diffuse", "normal_neighbors": 12}), [cloud])
    first = renderer.render(scene, camera, 320, 240)
    assert "normals:12:consistent" in pointnpr.computed_attributes(cloud)
    before = pointnpr.computed_attributes(cloud)
    again = renderer.render(scene, camera, 320, 240)
    assert pointnpr.computed_attributes(cloud) == before  # nothing recomputed
    np.testing.assert_array_equal(first.color, again.color)
    # The plane faces the camera: a light from the camera leaves it as it
    # is, one 75 degrees off darkens it by strength x (1 - cos 75).
    flat = pointnpr.Scene()
    flat.add_segment("s", pointnpr.Style(), [cloud])
    grazing = pointnpr.Scene()
    grazing.add_segment("s", pointnpr.Style(rasterize={"shading": "diffuse", "normal_neighbors": 12,
                                                       "light_elevation": 75, "shading_strength": 1.0}), [cloud])
    centre = lambda r: r.color[120, 160, :3]  # noqa: E731
    plain, low = centre(renderer.render(flat, camera, 320, 240)), centre(renderer.render(grazing, camera, 320, 240))
    head_on = pointnpr.Style(rasterize={"shading": "diffuse", "normal_neighbors": 12, "light_elevation": 0})
    lit = pointnpr.Scene()
    lit.add_segment("s", head_on, [cloud])
    np.testing.assert_allclose(centre(renderer.render(lit, camera, 320, 240)), plain, rtol=0.01)
    expected = 1.0 - (1.0 - np.cos(np.radians(75)))  # display-referred factor
    srgb = lambda v: np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)  # noqa: E731
    np.testing.assert_allclose(srgb(low) / srgb(plain), expected, rtol=0.03)


def test_knn_and_radius_search_agree_with_brute_force():
    rng = np.random.default_rng(5)
    p = rng.random((500, 3)) * 10 + 1e6
    idx, dist = pointnpr.knn(p, 6)
    d = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=2)
    np.testing.assert_allclose(dist, np.sort(d, axis=1)[:, :6], atol=1e-5)
    np.testing.assert_allclose(np.take_along_axis(d, idx, axis=1), dist, atol=1e-5)
    hits, hd = pointnpr.radius_search(p, p[0], 2.0)
    np.testing.assert_array_equal(np.sort(hits), np.nonzero(d[0] <= 2.0)[0])
    assert np.all(np.diff(hd) >= 0)


def test_feature_degree_edges_from_intensity_and_from_a_point_cloud():
    xs, ys = np.meshgrid(np.arange(60) * 0.02, np.arange(60) * 0.02)
    flat = np.column_stack([xs.ravel(), ys.ravel(), 0.3 * xs.ravel()])
    intensity = np.where(flat[:, 0] < 0.6, 300.0, 2000.0).astype(np.float32)
    f = pointnpr.feature_degree(flat, k=16, intensity=intensity, color_weight=1.0)
    border = np.abs(flat[:, 0] - 0.6) < 0.01
    assert f[border].mean() > 0.9 and f[np.abs(flat[:, 0] - 0.6) > 0.2].max() == 0
    # From a PointCloud, its own intensity is used (results in its internal order).
    cloud = pointnpr.PointCloud(flat, intensity=intensity)
    order = np.asarray(cloud.point_index)
    np.testing.assert_array_equal(pointnpr.feature_degree(cloud, k=16, color_weight=1.0), f[order])
    with pytest.raises(pointnpr.Error, match="intensity"):
        pointnpr.feature_degree(flat, intensity=intensity[:10])
    with pytest.raises(pointnpr.Error, match="contrast"):
        pointnpr.feature_degree(flat, intensity=intensity, contrast=0.0)


def test_progress_reaches_one_and_a_cancel_raises_cancelled():
    import threading
    import time

    rng = np.random.default_rng(4)
    pts = rng.uniform(0, 30, (300000, 3)) * [1, 1, 0.05]
    colors = rng.integers(0, 255, (300000, 3)).astype(np.uint8)
    done = pointnpr.Progress()
    assert done.fraction == 0.0 and not done.cancelled
    pointnpr.connected_components(pts, level=8, progress=done)
    assert done.fraction == 1.0

    early = pointnpr.Progress()
    early.cancel()
    with pytest.raises(pointnpr.Cancelled):
        pointnpr.estimate_normals(pts, progress=early)
    assert issubclass(pointnpr.Cancelled, pointnpr.Error) and issubclass(pointnpr.RenderCancelled, pointnpr.Cancelled)

    # From another thread, while the core works (the GIL is released).
    watched = pointnpr.Progress()
    outcome = []

    def run():
        try:
            pointnpr.region_growing_rgb(pts, colors, progress=watched)
            outcome.append("completed")
        except pointnpr.Cancelled:
            outcome.append("cancelled")

    worker = threading.Thread(target=run)
    worker.start()
    while watched.fraction == 0.0 and worker.is_alive():
        time.sleep(0.0005)
    watched.cancel()
    worker.join()
    assert outcome == ["cancelled"] and watched.fraction < 0.9
