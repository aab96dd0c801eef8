"""Scan caches written straight from a LAS/LAZ file (pointnpr.write_scan_caches,
docs/io.md#scan-cache): the same bytes as the in-memory path (read the file,
PointCloud of float32 offsets, write_scan_cache), whatever the memory given
to the external sort; bad files, unwritable folders and a cancel leave
nothing behind."""
import pathlib
import threading

import numpy as np
import pytest

import pointnpr

DATA = pathlib.Path(__file__).resolve().parents[1] / "data"
ORIGIN = np.array([6.5e5, 6.8e6, 120.0])


def scan_file(tmp_path, n=40000, seed=5):
    """A LAS 1.4 file (format 7: colours) with three classes, a dense cluster
    (Morton buckets far fuller than the rest) and a far outlier."""
    rng = np.random.default_rng(seed)
    pos = np.column_stack([rng.uniform(-50, 50, n), rng.uniform(-30, 30, n), rng.uniform(0, 5, n)])
    pos[: n // 7] = rng.normal(0, 0.02, (n // 7, 3)) + [10, 10, 2]  # one cell of the coarse buckets
    pos[-1] = [4000.0, -3000.0, 900.0]
    attrs = {
        "colors": rng.integers(0, 256, (n, 3), dtype=np.uint8),
        "intensity": rng.integers(0, 65536, n).astype(np.float32),
        "classification": rng.choice(np.array([2, 5, 6], dtype=np.uint8), n),
    }
    path = tmp_path / "scan.las"
    pointnpr.write(path, pointnpr.PointData(pos + ORIGIN, attrs))
    return path


def in_memory_caches(path, origin, split, chunk_size, folder):
    """What the importer's in-memory path writes for the same file."""
    data = pointnpr.read(path)
    attrs = dict(data.attributes)
    local = (np.asarray(data.positions) - origin).astype(np.float32)
    groups = [(-1, np.arange(len(local)))]
    if split:
        groups = [(int(c), np.nonzero(attrs["classification"] == c)[0]) for c in np.unique(attrs["classification"])]
    out = {}
    for code, rows in groups:
        cloud = pointnpr.PointCloud(local[rows], colors=attrs["colors"][rows], intensity=attrs["intensity"][rows],
                                    classification=attrs["classification"][rows], chunk_size=chunk_size)
        target = folder / ("memory_%d.pnprcache" % code)
        pointnpr.write_scan_cache(str(target), cloud)
        out[code] = target.read_bytes()
    return out


@pytest.mark.parametrize("split", [False, True])
@pytest.mark.parametrize("memory_bytes", [64 << 10, 256 << 20])
def test_streamed_caches_are_the_bytes_of_the_in_memory_path(tmp_path, split, memory_bytes):
    path = scan_file(tmp_path)
    origin = np.round(ORIGIN + [3.0, -2.0, 1.0])
    expected = in_memory_caches(path, origin, split, 512, tmp_path)
    written = pointnpr.write_scan_caches(
        path, lambda c: str(tmp_path / ("streamed_%d.pnprcache" % c)), origin=list(origin),
        split_by_classification=split, memory_bytes=memory_bytes, chunk_size=512)
    assert [w["classification"] for w in written] == sorted(expected)
    for w in written:
        got = pathlib.Path(w["path"]).read_bytes()
        assert got == expected[w["classification"]], w
        assert w["points"] == w["rows"] == pointnpr.CachedCloud(w["path"]).num_points
        if memory_bytes < 1 << 20:  # the sort really ran in parts, the cluster's buckets counted again
            assert w["runs"] > 3 and w["refined_buckets"] >= 1
        else:
            assert w["runs"] == 1 and w["refined_buckets"] == 0
    assert sum(w["rows"] for w in written) == 40000
    assert not list(tmp_path.glob("*.sorting")) and not list(tmp_path.glob("*.partial"))


def test_streamed_caches_of_a_laz_file_equal_those_of_its_points(tmp_path):
    # LAZ chunks are decoded in parallel and reach the writer in any order.
    path = DATA / "io" / "laz" / "laspy_autzen_trim.laz"
    origin = np.array([637000.0, 851000.0, 400.0])
    expected = in_memory_caches(path, origin, True, 1024, tmp_path)
    written = pointnpr.write_scan_caches(path, lambda c: str(tmp_path / ("s%d.pnprcache" % c)), origin=list(origin),
                                         split_by_classification=True, memory_bytes=1 << 20, chunk_size=1024)
    assert len(written) == len(expected) > 1
    for w in written:
        assert pathlib.Path(w["path"]).read_bytes() == expected[w["classification"]]


def test_a_bad_file_raises_a_read_error_and_leaves_nothing(tmp_path):
    good = scan_file(tmp_path, n=5000)
    bad = tmp_path / "cut.las"
    bad.write_bytes(good.read_bytes()[:-777])
    with pytest.raises(pointnpr.ReadError, match="truncated"):
        pointnpr.write_scan_caches(bad, lambda c: str(tmp_path / "out.pnprcache"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cut.las", "scan.las"]


def test_an_unwritable_folder_raises_and_a_cancel_stops(tmp_path):
    path = scan_file(tmp_path, n=5000)
    with pytest.raises(pointnpr.Error, match="sort file|cannot write"):
        pointnpr.write_scan_caches(path, lambda c: str(tmp_path / "missing" / "out.pnprcache"))
    progress = pointnpr.Progress()
    progress.cancel()
    with pytest.raises(pointnpr.Cancelled):
        pointnpr.write_scan_caches(path, lambda c: str(tmp_path / "out.pnprcache"), progress=progress)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scan.las"]


def test_recentring_chooses_the_importers_origin_and_the_header_gives_the_count(tmp_path):
    path = scan_file(tmp_path, n=8000)
    data = pointnpr.read(path)
    positions = np.asarray(data.positions)
    centre = np.round((positions.min(axis=0) + positions.max(axis=0)) * 0.5)  # importer.rounded_centre
    written = pointnpr.write_scan_caches(path, lambda c: str(tmp_path / "r.pnprcache"), chunk_size=512)
    assert written[0]["origin"] == tuple(centre)
    assert pathlib.Path(written[0]["path"]).read_bytes() == in_memory_caches(path, centre, False, 512, tmp_path)[-1]
    header = pointnpr.read_header(path)
    assert header["point_count"] == 8000 and header["format"] == "las"
    # All of read's metadata but what only the points tell (their colours' bits).
    assert header == {k: v for k, v in dict(data.metadata).items() if k != "color_bits"}
