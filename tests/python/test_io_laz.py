"""LAZ (LASzip) decoding: every test file decodes exactly as laspy + lazrs
decodes it, field by field; corrupt copies raise ReadError.

laspy and lazrs are test oracles from PyPI (tests/requirements.txt, installed
into .venv-test by scripts/install_deps.sh --tests); this test fails, not
skips, without them.
"""
import pathlib
import struct
import sys

import numpy as np
import pytest

import pointnpr
import laspy  # noqa: E402  (oracle; a missing one must fail the suite)
import lazrs  # noqa: F401,E402

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "data" / "io"))
import make_wavepacket_laz  # noqa: E402

DATA = pathlib.Path(__file__).resolve().parents[1] / "data" / "io"
LAZ = DATA / "laz"
# lazrs cannot read the early point-wise compressor (no chunks); that file
# holds the same points as pdal_laszip-generated.laz. pointnpr_v1_bytes.laz
# (LASzip 1.x POINT10 v1 + BYTE v1, written by tests/cpp/laz_test_encoder.h)
# is compared with laspy's reading of its uncompressed twin: lazrs reads
# BYTE v1 as v2, which LASzip's v1 is not. The encoder's POINT10 v1 in
# chunks (pointnpr_v1_chunked.laz) is read by lazrs itself below.
ORACLE_TWIN = {"pdal_simple-laszip-compressor-version-1.2r0.laz": "pdal_laszip-generated.laz",
               "pointnpr_v1_bytes.laz": "pointnpr_v1_bytes.las"}
FILES = sorted(p.name for p in LAZ.glob("*.laz"))


def test_laspy_uses_lazrs():
    assert laspy.LazBackend.Lazrs in laspy.LazBackend.detect_available()


def expected_colors(las):
    rgb = np.column_stack([las.red, las.green, las.blue]).astype(np.uint16)
    return (rgb >> 8).astype(np.uint8) if rgb.max() > 255 else rgb.astype(np.uint8)


@pytest.mark.parametrize("name", FILES)
def test_laz_decodes_exactly_like_laspy_lazrs(name):
    data = pointnpr.read(str(LAZ / name))
    las = laspy.read(str(LAZ / ORACLE_TWIN.get(name, name)), laz_backend=laspy.LazBackend.Lazrs)
    pf = las.header.point_format.id
    md = data.metadata
    assert md["compression"] == "laszip"
    assert md["point_format"] == pf
    assert data.num_points == len(las.points) > 0
    scale, offset = np.array(md["scale"]), np.array(md["offset"])
    integer_xyz = np.round((data.positions - offset) / scale).astype(np.int64)
    np.testing.assert_array_equal(integer_xyz, np.column_stack([las.X, las.Y, las.Z]))
    np.testing.assert_array_equal(data.positions, np.column_stack([las.x, las.y, las.z]))
    a = data.attributes
    np.testing.assert_array_equal(a["intensity"], np.asarray(las.intensity, np.float32))
    np.testing.assert_array_equal(a["return_number"], las.return_number)
    np.testing.assert_array_equal(a["number_of_returns"], las.number_of_returns)
    np.testing.assert_array_equal(a["classification"], las.classification)
    np.testing.assert_array_equal(a["user_data"], las.user_data)
    np.testing.assert_array_equal(a["point_source_id"], las.point_source_id)
    if pf >= 6:
        np.testing.assert_array_equal(a["scan_angle"], (np.asarray(las.scan_angle) * 0.006).astype(np.float32))
    else:
        np.testing.assert_array_equal(a["scan_angle"], np.asarray(las.scan_angle_rank, np.float32))
    if pf not in (0, 2):
        np.testing.assert_array_equal(a["gps_time"], las.gps_time)
    if "red" in las.point_format.dimension_names:
        if np.any(las.red) or np.any(las.green) or np.any(las.blue):
            np.testing.assert_array_equal(a["colors"], expected_colors(las))
    if "nir" in las.point_format.dimension_names:
        np.testing.assert_array_equal(a["nir"], las.nir)
    extra = [d for d in las.point_format.extra_dimension_names if d != "Reserved"]  # undocumented bytes
    for dim in extra:
        np.testing.assert_array_equal(np.asarray(a[dim]).reshape(len(las.points), -1),
                                      np.asarray(las[dim]).reshape(len(las.points), -1))


def test_test_encoders_v1_files_equal_their_las_twins():
    # The LAS twins are read by laspy, not by the LAZ decoder: every record
    # byte, the extra bytes included, is what the test-side encoder coded.
    for name in ("pointnpr_v1_bytes", "pointnpr_v1_chunked"):
        las = laspy.read(str(LAZ / (name + ".las")))
        data = pointnpr.read(str(LAZ / (name + ".laz")))
        assert data.num_points == len(las.points) == 1500
        if name == "pointnpr_v1_bytes":
            assert data.metadata["laszip_compressor"] == 1
            for i in range(7):
                np.testing.assert_array_equal(data.attributes["b%d" % i], las["b%d" % i])
            assert set(np.unique(las["b2"])) == {0, 255}  # the widest wrap-around is covered
        else:
            lazrs = laspy.read(str(LAZ / (name + ".laz")), laz_backend=laspy.LazBackend.Lazrs)
            np.testing.assert_array_equal(np.asarray(lazrs.points.array), np.asarray(las.points.array))


def test_autzen_laz_equals_its_las_twin():
    laz = pointnpr.read(str(LAZ / "laspy_autzen_trim.laz"))
    las = pointnpr.read(str(DATA / "autzen_trim.las"))
    np.testing.assert_array_equal(laz.positions, las.positions)
    assert set(laz.attributes) == set(las.attributes)
    for k in las.attributes:
        np.testing.assert_array_equal(laz.attributes[k], las.attributes[k])


def test_extra_bytes_and_copc_are_read():
    extra = pointnpr.read(str(LAZ / "laspy_extra.laz"))
    assert extra.metadata["point_record_length"] == 61
    copc = pointnpr.read(str(LAZ / "laspy_simple_with_page.copc.laz"))
    assert copc.metadata["laszip_compressor"] == 3 and copc.num_points == 1065


def corrupt(tmp_path, name, mutate):
    raw = bytearray((LAZ / name).read_bytes())
    raw = mutate(raw)
    path = tmp_path / ("bad_" + name)
    path.write_bytes(bytes(raw))
    return str(path)


def chunk_table_offset(raw):
    off, = struct.unpack_from("<I", raw, 96)
    return off, struct.unpack_from("<q", raw, off)[0]


@pytest.mark.parametrize("name", ["laspy_autzen_trim.laz", "laspy_1_4_w_evlr.laz",
                                  "laspy_simple_with_page.copc.laz", "pdal_lone-star-split-1.laz"])
@pytest.mark.parametrize("fraction", [0.2, 0.5, 0.9, 0.999])
def test_truncated_laz_raises_read_error(tmp_path, name, fraction):
    path = corrupt(tmp_path, name, lambda r: r[: int(len(r) * fraction)])
    with pytest.raises(pointnpr.ReadError):
        pointnpr.read(path)


@pytest.mark.parametrize("name", ["laspy_autzen_trim.laz", "laspy_1_4_w_evlr.laz",
                                  "pdal_lone-star-split-1.laz"])
def test_flipped_byte_in_a_chunk_names_the_chunk(tmp_path, name):
    def flip(r):
        off, table = chunk_table_offset(r)
        r[(off + table) // 2] ^= 0x5A  # inside the compressed points
        return r
    with pytest.raises(pointnpr.ReadError) as info:
        pointnpr.read(corrupt(tmp_path, name, flip))
    assert "LAZ chunk" in str(info.value) and "is corrupt" in str(info.value)


def test_wrong_chunk_table_raises_read_error(tmp_path):
    def shift_table(r):
        off, table = chunk_table_offset(r)
        struct.pack_into("<q", r, off, table - 7)
        return r
    with pytest.raises(pointnpr.ReadError):
        pointnpr.read(corrupt(tmp_path, "laspy_autzen_trim.laz", shift_table))

    def garble_table(r):
        _, table = chunk_table_offset(r)
        r[table + 9] ^= 0xFF
        return r
    with pytest.raises(pointnpr.ReadError):
        pointnpr.read(corrupt(tmp_path, "laspy_autzen_trim.laz", garble_table))


@pytest.mark.parametrize("name", ["laspy_autzen_trim.laz", "laspy_1_4_w_evlr.laz",
                                  "laspy_simple_with_page.copc.laz", "pdal_lone-star-split-1.laz"])
def test_missing_chunk_table_is_scanned_in_order(tmp_path, name):
    def drop_table(r):
        off, _ = chunk_table_offset(r)
        struct.pack_into("<q", r, off, -1)
        if r[25] < 4 or struct.unpack_from("<I", r, 243)[0] == 0:
            r[-8:] = struct.pack("<q", 0)  # no table pointer at the end either
        return r  # (with EVLRs the last 8 bytes are an EVLR's)
    data = pointnpr.read(corrupt(tmp_path, name, drop_table))
    ref = pointnpr.read(str(LAZ / name))
    np.testing.assert_array_equal(data.positions, ref.positions)
    for k in ref.attributes:
        np.testing.assert_array_equal(data.attributes[k], ref.attributes[k])


@pytest.mark.parametrize("count", [220000, 10**9, 2**32 - 1])
def test_absurd_point_count_raises_read_error(tmp_path, count):
    def set_count(r):
        struct.pack_into("<I", r, 107, count)
        return r
    with pytest.raises(pointnpr.ReadError) as info:
        pointnpr.read(corrupt(tmp_path, "laspy_autzen_trim.laz", set_count))
    assert "points" in str(info.value)


def test_unknown_item_version_is_named(tmp_path):
    def bump_version(r):
        i = bytes(r).index(b"laszip encoded")
        vlr = i - 2 + 54
        struct.pack_into("<H", r, vlr + 34 + 4, 7)  # first item's version
        return r
    with pytest.raises(pointnpr.ReadError) as info:
        pointnpr.read(corrupt(tmp_path, "laspy_autzen_trim.laz", bump_version))
    assert "POINT10 version 7" in str(info.value)


def test_read_reports_progress_by_chunk_and_stops_when_cancelled():
    progress = pointnpr.Progress()
    data = pointnpr.read(str(LAZ / "pdal_lone-star-split-1.laz"), progress=progress)  # 3 chunks
    assert data.num_points == 122893
    assert progress.fraction == 1.0
    cancelled = pointnpr.Progress()
    cancelled.cancel()
    with pytest.raises(pointnpr.Cancelled):
        pointnpr.read(str(LAZ / "pdal_lone-star-split-1.laz"), progress=cancelled)


@pytest.mark.parametrize("point_format", [4, 5])
def test_wave_packet_formats_decode_like_laspy_lazrs(tmp_path, point_format):
    # No real LAZ of formats 4/5 is at hand: lazrs (the oracle) writes one,
    # with every way LASzip codes a waveform's offset (the last packet's,
    # right after it, a 32-bit difference, raw 64 bits) and arbitrary float
    # fields, over several chunks, with extra bytes after the packets. A
    # packet's models decoded wrongly put every later field out of step (the
    # packets' own bytes: tests/cpp/test_io_laz.cpp, against a LAS twin).
    rng = np.random.default_rng(point_format)
    n = 120_000
    header = laspy.LasHeader(point_format=point_format, version="1.3")
    header.add_extra_dim(laspy.ExtraBytesParams(name="tag", type=np.uint16))
    las = laspy.LasData(header)
    las.x, las.y, las.z = (np.cumsum(rng.normal(0, 0.1, n)) for _ in range(3))
    las.intensity = rng.integers(0, 65535, n)
    las.classification = rng.integers(0, 20, n)
    las.gps_time = np.cumsum(rng.exponential(1e-5, n)) + 3e8
    if point_format == 5:
        las.red, las.green, las.blue = (rng.integers(0, 65535, n) for _ in range(3))
    offset = make_wavepacket_laz.add_wave_packets(las, rng)
    las.tag = rng.integers(0, 65535, n)
    path = tmp_path / f"wave{point_format}.laz"
    las.write(str(path), laz_backend=laspy.LazBackend.Lazrs)
    oracle = laspy.read(str(path), laz_backend=laspy.LazBackend.Lazrs)
    np.testing.assert_array_equal(oracle.wavepacket_offset, offset)

    data = pointnpr.read(str(path))
    assert data.metadata["point_format"] == point_format and data.metadata["compression"] == "laszip"
    np.testing.assert_array_equal(data.positions, np.column_stack([oracle.x, oracle.y, oracle.z]))
    np.testing.assert_array_equal(data.attributes["gps_time"], oracle.gps_time)
    np.testing.assert_array_equal(data.attributes["intensity"], np.asarray(oracle.intensity, np.float32))
    np.testing.assert_array_equal(data.attributes["classification"], oracle.classification)
    np.testing.assert_array_equal(data.attributes["tag"], oracle.tag)
    if point_format == 5:
        np.testing.assert_array_equal(data.attributes["colors"], expected_colors(oracle))
