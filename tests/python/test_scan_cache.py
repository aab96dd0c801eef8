"""Out-of-core scans (docs/io.md#scan-cache): a CachedCloud renders what the
same cloud in memory renders, draws within its budget a prefix of every
visible chunk's resolution queue, and refuses damaged caches with a clear
error while the renderer keeps working."""
import numpy as np
import pytest

import pointnpr

W, H = 240, 180
ORIGIN = np.array([6.5e5, 6.8e6, 120.0])  # georeferenced: chunks keep double origins
CHUNK = 2048  # small chunks: the view sees some of them


def scan(n=60000, seed=3):
    rng = np.random.default_rng(seed)
    pos = np.column_stack([rng.uniform(-6, 6, n), rng.uniform(-4, 4, n), rng.uniform(-0.3, 0.3, n)])
    pos[:, 2] += 0.3 * np.sin(pos[:, 0])  # a surface with relief: depth differs per pixel
    colors = rng.integers(0, 256, (n, 3), dtype=np.uint8)
    classification = rng.integers(1, 7, n, dtype=np.uint8)
    return pos + ORIGIN, colors, classification


def camera():
    # Looks at a corner of the scan from 6 m: part of it is out of view (culled chunks).
    world_from_camera = np.eye(4)
    world_from_camera[:3, 3] = ORIGIN + [4.0, 2.0, 6.0]
    return pointnpr.Camera.perspective(world_from_camera, lens=35.0, width=W, height=H)


def render(renderer, instance, style):
    scene = pointnpr.Scene()
    scene.add_segment("scan", style, [instance])
    return renderer.render(scene, camera(), W, H)


@pytest.fixture(scope="module")
def cached(tmp_path_factory):
    pos, colors, classification = scan()
    cloud = pointnpr.PointCloud(pos, colors=colors, classification=classification, chunk_size=CHUNK)
    path = tmp_path_factory.mktemp("cache") / "scan.pnprcache"
    pointnpr.write_scan_cache(str(path), cloud)
    return cloud, pointnpr.CachedCloud(str(path)), path, pos, colors


@pytest.mark.parametrize("rasterizer", ["compute", "gl_points", "native"])
def test_a_budget_covering_the_scan_renders_the_bytes_of_the_cloud_in_memory(renderer, cached, rasterizer):
    cloud, cache, _path, _pos, _colors = cached
    cache.point_budget = cloud.num_points
    # A filter that reads no neighbourhood: an out-of-core scan's point
    # spacing is not known yet (docs/filter_measurements.md, "Left"), so the
    # gap fill and eye-dome lighting see less than they do in memory.
    style = pointnpr.Style(rasterize={"point_size": 2, "rasterizer": rasterizer}, filters=[("posterize", {})])
    memory, streamed = render(renderer, cloud, style), render(renderer, cache, style)
    counts = cache.counts_for_view(camera(), np.eye(4), W, H)
    assert 0 < counts.sum() < cloud.num_points  # some chunks are out of view and not read
    assert (memory.segment_index >= 0).mean() > 0.3
    assert np.array_equal(memory.color, streamed.color)
    assert np.array_equal(memory.depth, streamed.depth)
    assert np.array_equal(memory.segment_index, streamed.segment_index)


def lowbias32(x):
    """The resolution queue's hash (render/gpu_cloud.h queue_hash), on uint32 arrays."""
    x = x.astype(np.uint64)
    x ^= x >> 16
    x = (x * 0x7feb352d) & 0xFFFFFFFF
    x ^= x >> 15
    x = (x * 0x846ca68b) & 0xFFFFFFFF
    x ^= x >> 16
    return x


def test_a_budget_draws_a_prefix_of_each_visible_chunks_queue_and_renders_as_those_points_in_memory(
        renderer, cached):
    cloud, cache, _path, pos, colors = cached
    budget = cloud.num_points // 6
    counts = cache.counts_for_view(camera(), np.eye(4), W, H, budget=budget)
    assert budget - len(counts) <= counts.sum() <= budget
    assert (counts < cache.chunk_counts).any() and (counts == 0).any()
    # The in-memory cloud's chunks are runs of CHUNK of its (Morton) order;
    # each chunk's queue orders its points by the hash of their ids.
    ids = np.asarray(cloud.point_index)
    expected = []
    for c, n in enumerate(counts):
        chunk_ids = ids[CHUNK * c:CHUNK * (c + 1)]
        keys = lowbias32(chunk_ids ^ np.uint32(0x5eed001))
        order = np.lexsort((np.arange(len(chunk_ids)), keys))
        expected.append(chunk_ids[np.sort(order[:n])])  # drawn in the chunk's own (spatial) order
    expected = np.concatenate(expected)
    cache.point_budget = budget
    style = pointnpr.Style(rasterize={"point_size": 3})
    streamed = render(renderer, cache, style)
    assert cache.stream_points == counts.sum()
    assert np.array_equal(np.asarray(cache.stream(counts).point_index), expected)
    # The same points as an ordinary cloud (chunked anew, so floats round
    # differently by ~1e-7 m): the same picture up to splat edges.
    subset = pointnpr.PointCloud(pos[expected], colors=colors[expected])
    memory = render(renderer, subset, style)
    covered_memory, covered_streamed = memory.segment_index >= 0, streamed.segment_index >= 0
    assert covered_streamed.mean() > 0.2
    assert (covered_memory != covered_streamed).mean() < 0.002
    same = covered_memory & covered_streamed
    assert np.mean(np.abs(memory.color[same] - streamed.color[same]).max(axis=-1) > 2 / 255) < 0.01
    # Fewer points than the full budget: sparser coverage, never more points than asked.
    cache.point_budget = budget // 4
    sparse = render(renderer, cache, style)
    assert cache.stream_points <= budget // 4
    assert (sparse.segment_index >= 0).mean() < covered_streamed.mean()


def test_streaming_is_deterministic_and_reuses_the_cloud_while_the_view_rests(renderer, cached):
    _cloud, cache, path, _pos, _colors = cached
    cache.point_budget = 5000
    style = pointnpr.Style(rasterize={"point_size": 2})
    first = render(renderer, cache, style)
    uploads = renderer.upload_count()
    second = render(renderer, cache, style)
    assert renderer.upload_count() == uploads  # same counts: the same cloud, no new upload
    assert np.array_equal(first.color, second.color)
    other = pointnpr.CachedCloud(str(path), point_budget=5000)  # another process would do the same
    assert np.array_equal(render(renderer, other, style).color, first.color)


def test_cached_and_in_memory_clouds_share_a_scene_with_a_transform(renderer, cached):
    cloud, cache, _path, _pos, _colors = cached
    cache.point_budget = cloud.num_points
    shift = np.eye(4)
    shift[2, 3] = -1.0
    style = pointnpr.Style(rasterize={"point_size": 2})
    scenes = []
    for instance in (cloud, cache):
        scene = pointnpr.Scene()
        scene.add_segment("moved", style, [(instance, shift, "scan")])
        scene.add_segment("other", style, [cloud])
        scenes.append(renderer.render(scene, camera(), W, H))
    assert np.array_equal(scenes[0].color, scenes[1].color)
    assert set(np.unique(scenes[1].segment_index)) == {-1, 0, 1}


def test_the_gpu_holds_one_frames_stream_whatever_the_views(cached):
    _cloud, cache, _path, _pos, _colors = cached
    renderer = pointnpr.Renderer()
    style = pointnpr.Style(rasterize={"point_size": 2})
    for budget in (3000, 9000, 27000, 1000):
        cache.point_budget = budget
        render(renderer, cache, style)
        assert cache.stream_points <= budget
        # The previous frame's cloud is let go, and its GPU buffers with it.
        assert renderer.cached_clouds() == 1


def test_damaged_caches_raise_read_errors_and_the_renderer_keeps_working(renderer, cached, tmp_path):
    cloud, _cache, path, _pos, _colors = cached
    data = path.read_bytes()
    truncated = tmp_path / "truncated.pnprcache"
    truncated.write_bytes(data[:len(data) // 3])
    with pytest.raises(pointnpr.ReadError, match="truncated scan cache"):
        pointnpr.CachedCloud(str(truncated))
    newer = tmp_path / "newer.pnprcache"
    newer.write_bytes(data[:8] + (7).to_bytes(4, "little") + data[12:])
    with pytest.raises(pointnpr.ReadError, match="version 7, this PointNPR reads version %d" % pointnpr.SCAN_CACHE_VERSION):
        pointnpr.CachedCloud(str(newer))
    with pytest.raises(pointnpr.ReadError, match="cannot open"):
        pointnpr.CachedCloud(str(tmp_path / "missing.pnprcache"))
    # A flipped bit in the points: found when that chunk is first read, by the render.
    altered = bytearray(data)
    altered[len(data) // 2] ^= 0x01
    bad = tmp_path / "altered.pnprcache"
    bad.write_bytes(bytes(altered))
    damaged = pointnpr.CachedCloud(str(bad), point_budget=cloud.num_points)
    style = pointnpr.Style(rasterize={"point_size": 2})
    with pytest.raises(pointnpr.ReadError, match="checksum does not match"):
        scene = pointnpr.Scene()
        scene.add_segment("scan", style, [damaged])
        scene.add_segment("other", style, [cloud])
        renderer.render(scene, pointnpr.Camera.perspective(_look_at_everything(), width=W, height=H), W, H)
    assert (render(renderer, cloud, style).segment_index >= 0).any()


def _look_at_everything():
    m = np.eye(4)
    m[:3, 3] = ORIGIN + [0.0, 0.0, 30.0]
    return m


def test_writing_refuses_an_unwritable_path(tmp_path):
    cloud = pointnpr.PointCloud(np.zeros((3, 3)))
    with pytest.raises(pointnpr.Error, match="cannot write the scan cache"):
        pointnpr.write_scan_cache(str(tmp_path / "no" / "such" / "dir.pnprcache"), cloud)
    assert list(tmp_path.iterdir()) == []


def test_the_frames_point_budget_is_what_a_cached_scan_streams(renderer, cached):
    cloud, cache, _path, _pos, _colors = cached
    cache.point_budget = cloud.num_points  # its own budget: every point
    scene = pointnpr.Scene()
    scene.add_segment("scan", pointnpr.Style(rasterize={"point_size": 2}), [cache])
    whole = renderer.render(scene, camera(), W, H)
    in_view = int(cache.counts_for_view(camera(), np.eye(4), W, H).sum())
    assert cache.stream_points == in_view
    thinned = renderer.render(scene, camera(), W, H, point_budget=3000)
    assert cache.stream_points <= 3000 < in_view
    assert thinned.stats["point_budget_points"] <= 3000
    assert (thinned.segment_index >= 0).sum() < (whole.segment_index >= 0).sum()
