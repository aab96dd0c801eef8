"""E57 (ASTM E2807): every scan of every test file read by pointnpr and by
pye57 (libE57Format), positions after the pose and attributes compared to
the file's precision; files written here through pye57's libE57 binding
cover what pye57's test files lack; broken files raise one ReadError each.

pye57 is a test oracle from PyPI (tests/requirements.txt, installed into
.venv-test by scripts/install_deps.sh --tests); this test fails, not skips,
without it.
"""
import pathlib
import struct
import uuid

import numpy as np
import pytest

import pointnpr
import pye57  # noqa: E402  (oracle; a missing one must fail the suite)
from pye57 import libe57

DATA = pathlib.Path(__file__).resolve().parents[1] / "data" / "io" / "e57"
REAL_FILES = sorted(DATA.glob("*.e57"))
TAU = 2 * np.pi


# -- the oracle ------------------------------------------------------------

def oracle_scans(path):
    """Per scan: pye57's positions (pose applied, invalid points dropped, as
    E57.read_scan does it) and every prototype field's raw values (as
    float64, scaled) of the points kept."""
    e = pye57.E57(str(path))
    scans = []
    for i in range(e.scan_count):
        header = e.get_header(i)
        fields = list(header.point_fields)
        n = header.point_count
        raw = {}
        buffers = libe57.VectorSourceDestBuffer()
        for f in fields:
            raw[f] = np.empty(n, np.float64)
            buffers.append(libe57.SourceDestBuffer(e.image_file, f, raw[f], n, True, True))
        header.points.reader(buffers).read()
        state = "cartesianInvalidState" if "cartesianX" in fields else "sphericalInvalidState"
        keep = raw[state] == 0 if state in raw else np.ones(n, bool)
        data = e.read_scan(i, ignore_missing_fields=True)
        xyz = np.column_stack([data["cartesianX"], data["cartesianY"], data["cartesianZ"]])
        scans.append({"positions": xyz, "raw": {f: v[keep] for f, v in raw.items()}, "node": e.data3d[i]})
    return e, scans


def node_value(node, *path):
    for p in path:
        node = node[p]
    return node.value() if hasattr(node, "value") else node.scaledValue()


def assert_matches_oracle(path):
    ours = pointnpr.read_e57_scans(str(path))
    e, theirs = oracle_scans(path)
    assert len(ours) == len(theirs) == e.scan_count
    for i, (d, t) in enumerate(zip(ours, theirs)):
        raw = t["raw"]
        assert d.metadata["scan_name"] == str(node_value(t["node"], "name"))
        assert d.num_points == len(t["positions"])
        # pyquaternion and pointnpr build the rotation matrix each its own
        # way: equal to ~1e-15 relative, far below a float32 coordinate's step.
        scale = max(1.0, float(np.abs(t["positions"]).max(initial=0)))
        np.testing.assert_allclose(d.positions, t["positions"], rtol=0, atol=1e-12 * scale)
        a = d.attributes
        if "intensity" in raw:
            np.testing.assert_array_equal(a["intensity"], raw["intensity"].astype(np.float32))
        if "colorRed" in raw:
            lo = np.array(d.metadata["color_limits"][0::2])
            hi = np.array(d.metadata["color_limits"][1::2])
            rgb = np.column_stack([raw["colorRed"], raw["colorGreen"], raw["colorBlue"]])
            expected = np.rint(np.clip((rgb - lo) / (hi - lo), 0, 1) * 255).astype(np.uint8)
            np.testing.assert_array_equal(a["colors"], expected)
        for field, attr in (("rowIndex", "row_index"), ("columnIndex", "column_index"),
                            ("timeStamp", "time_stamp"), ("returnCount", "number_of_returns")):
            if field in raw:
                np.testing.assert_array_equal(a[attr], raw[field])
        if "returnIndex" in raw:
            np.testing.assert_array_equal(a["return_number"], raw["returnIndex"] + 1)
        if "nor:normalX" in raw:
            assert list(d.metadata["pose_rotation"]) == [1.0, 0.0, 0.0, 0.0]
            normals = np.column_stack([raw["nor:normalX"], raw["nor:normalY"], raw["nor:normalZ"]])
            np.testing.assert_array_equal(a["normals"], normals.astype(np.float32))
    return ours


@pytest.mark.parametrize("path", REAL_FILES, ids=lambda p: p.name)
def test_pye57_test_files_read_as_pye57_reads_them(path):
    scans = assert_matches_oracle(path)
    assert sum(s.num_points for s in scans) > 0


def test_pump_scan_keeps_its_attributes_and_lists_its_image():
    (scan,) = pointnpr.read_e57_scans(str(DATA / "pye57_pumpAVisualReferenceImage.e57"))
    assert scan.num_points == 155201
    assert {"intensity", "colors", "row_index", "column_index"} <= set(scan.attributes)
    assert scan.metadata["images2d"] == "pumpVisual (visualReferenceRepresentation, 3072x2304)"
    assert scan.metadata["images2d_count"] == 1


# -- files written here through libE57 --------------------------------------

def write_e57(path, scans, coordinate_metadata=""):
    """Writes scans with libE57 (pye57's binding). Each scan: "fields", a list
    of (name, node factory(imf), values); optional "name", "rotation"
    (w, x, y, z), "translation", "intensity_limits", "color_limits"."""
    imf = libe57.ImageFile(str(path), "w")
    root = imf.root()
    root.set("formatName", libe57.StringNode(imf, "ASTM E57 3D Imaging Data File"))
    root.set("guid", libe57.StringNode(imf, "{%s}" % uuid.UUID(int=1)))
    root.set("versionMajor", libe57.IntegerNode(imf, 1))
    root.set("versionMinor", libe57.IntegerNode(imf, 0))
    root.set("coordinateMetadata", libe57.StringNode(imf, coordinate_metadata))
    data3d = libe57.VectorNode(imf, True)
    root.set("data3D", data3d)
    root.set("images2D", libe57.VectorNode(imf, True))
    for k, scan in enumerate(scans):
        node = libe57.StructureNode(imf)
        node.set("guid", libe57.StringNode(imf, "{%s}" % uuid.UUID(int=100 + k)))
        node.set("name", libe57.StringNode(imf, scan.get("name", "scan %d" % k)))
        if "rotation" in scan or "translation" in scan:
            pose = libe57.StructureNode(imf)
            rotation = libe57.StructureNode(imf)
            for axis, v in zip("wxyz", scan.get("rotation", (1, 0, 0, 0))):
                rotation.set(axis, libe57.FloatNode(imf, float(v)))
            translation = libe57.StructureNode(imf)
            for axis, v in zip("xyz", scan.get("translation", (0, 0, 0))):
                translation.set(axis, libe57.FloatNode(imf, float(v)))
            pose.set("rotation", rotation)
            pose.set("translation", translation)
            node.set("pose", pose)
        if "intensity_limits" in scan:
            box = libe57.StructureNode(imf)
            box.set("intensityMinimum", libe57.FloatNode(imf, float(scan["intensity_limits"][0])))
            box.set("intensityMaximum", libe57.FloatNode(imf, float(scan["intensity_limits"][1])))
            node.set("intensityLimits", box)
        if "color_limits" in scan:
            box = libe57.StructureNode(imf)
            lo, hi = scan["color_limits"]
            for c in ("Red", "Green", "Blue"):
                box.set("color%sMinimum" % c, libe57.IntegerNode(imf, lo))
                box.set("color%sMaximum" % c, libe57.IntegerNode(imf, hi))
            node.set("colorLimits", box)
        prototype = libe57.StructureNode(imf)
        for name, make, _ in scan["fields"]:
            prototype.set(name, make(imf))
        points = libe57.CompressedVectorNode(imf, prototype, libe57.VectorNode(imf, True))
        node.set("points", points)
        data3d.append(node)
        n = len(scan["fields"][0][2])
        buffers = libe57.VectorSourceDestBuffer()
        arrays = []
        for name, _, values in scan["fields"]:
            arrays.append(np.ascontiguousarray(values, dtype=np.float64))
            buffers.append(libe57.SourceDestBuffer(imf, name, arrays[-1], n, True, True))
        writer = points.writer(buffers)
        writer.write(n)
        writer.close()
    imf.close()


def single(lo, hi):
    return lambda imf: libe57.FloatNode(imf, 0.0, libe57.E57_SINGLE, lo, hi)


def double(lo=-1e300, hi=1e300):
    return lambda imf: libe57.FloatNode(imf, 0.0, libe57.E57_DOUBLE, lo, hi)


def integer(lo, hi):
    return lambda imf: libe57.IntegerNode(imf, lo, lo, hi)


def scaled(lo, hi, scale, offset=0.0):
    return lambda imf: libe57.ScaledIntegerNode(imf, lo, lo, hi, scale, offset)


def quaternion(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return (np.cos(angle / 2), *(np.sin(angle / 2) * axis))


def test_spherical_coordinates_with_a_pose_and_invalid_states(tmp_path):
    rng = np.random.default_rng(1)
    n = 5000
    state = rng.choice([0, 0, 0, 1, 2], n)
    write_e57(tmp_path / "spherical.e57", [{
        "name": "spherical",
        "rotation": quaternion((1, 2, 3), 0.7), "translation": (1000.25, -2000.5, 30.125),
        "fields": [("sphericalRange", double(0, 1000), rng.uniform(0.5, 80, n)),
                   ("sphericalAzimuth", double(-np.pi, np.pi), rng.uniform(-np.pi, np.pi, n)),
                   ("sphericalElevation", double(-np.pi / 2, np.pi / 2), rng.uniform(-1.5, 1.5, n)),
                   ("sphericalInvalidState", integer(0, 2), state),
                   ("timeStamp", double(), rng.uniform(0, 100, n))]}])
    (scan,) = assert_matches_oracle(tmp_path / "spherical.e57")
    assert scan.num_points == np.count_nonzero(state == 0)
    assert scan.metadata["dropped_invalid"] == np.count_nonzero(state != 0)
    assert scan.metadata["coordinates"] == "spherical"


def test_scaled_integers_of_odd_widths_indices_returns_and_limits(tmp_path):
    rng = np.random.default_rng(2)
    n = 20000
    rows, cols = np.divmod(np.arange(n), 200)
    write_e57(tmp_path / "scaled.e57", [{
        "intensity_limits": (0, 4095), "color_limits": (0, 1023),
        "fields": [("cartesianX", scaled(-(1 << 20), (1 << 20) + 5, 0.001, 500.0), rng.integers(-1000, 1000, n) * 0.001 + 500),
                   ("cartesianY", scaled(-3, 8000, 0.01), rng.integers(-3, 8000, n) * 0.01),
                   ("cartesianZ", scaled(-(1 << 36), 1 << 36, 1e-4), rng.integers(-50000, 50000, n) * 1e-4),
                   ("intensity", integer(0, 4095), rng.integers(0, 4096, n)),
                   ("colorRed", integer(0, 1023), rng.integers(0, 1024, n)),
                   ("colorGreen", integer(0, 1023), rng.integers(0, 1024, n)),
                   ("colorBlue", integer(0, 1023), rng.integers(0, 1024, n)),
                   ("rowIndex", integer(0, 99), rows),
                   # 63 bits: values straddle 8-byte words
                   ("columnIndex", integer(-(1 << 62), 1 << 62), cols),
                   ("returnIndex", integer(0, 3), rng.integers(0, 4, n)),
                   ("returnCount", integer(1, 4), rng.integers(1, 5, n)),
                   ("cartesianInvalidState", integer(0, 2), rng.choice([0, 0, 0, 2], n))]}])
    (scan,) = assert_matches_oracle(tmp_path / "scaled.e57")
    assert list(scan.metadata["intensity_limits"]) == [0.0, 4095.0]
    assert list(scan.metadata["color_limits"]) == [0.0, 1023.0] * 3
    assert scan.attributes["colors"].max() == 255


def test_several_scans_with_poses_and_a_large_multi_packet_scan(tmp_path):
    rng = np.random.default_rng(3)
    scans = []
    for k, n in enumerate((10, 700000, 3000)):
        scans.append({"name": "station %d" % k, "rotation": quaternion(rng.normal(size=3), k + 0.3),
                      "translation": (650000.0 + 10 * k, 6860000.0 - k, 50.0),
                      "intensity_limits": (-1.0, 1.0),
                      "fields": [("cartesianX", single(-100, 100), rng.uniform(-100, 100, n)),
                                 ("cartesianY", single(-100, 100), rng.uniform(-100, 100, n)),
                                 ("cartesianZ", double(), rng.uniform(-5, 5, n)),
                                 ("intensity", single(-1, 1), rng.uniform(-1, 1, n))]})
    path = tmp_path / "stations.e57"
    write_e57(path, scans, coordinate_metadata="EPSG:2154")
    ours = assert_matches_oracle(path)
    assert [s.metadata["scan_name"] for s in ours] == ["station 0", "station 1", "station 2"]
    assert all(s.metadata["coordinate_metadata"] == "EPSG:2154" for s in ours)
    merged = pointnpr.read(str(path))
    assert merged.metadata["scan_names"] == "station 0\nstation 1\nstation 2"
    np.testing.assert_array_equal(merged.positions, np.concatenate([s.positions for s in ours]))
    np.testing.assert_array_equal(merged.attributes["scan_index"], np.repeat([0, 1, 2], [10, 700000, 3000]))


# -- broken files ------------------------------------------------------------

def crc32c(data):
    table = crc32c.table
    c = 0xFFFFFFFF
    for b in data:
        c = (c >> 8) ^ table[(c ^ b) & 0xFF]
    return c ^ 0xFFFFFFFF


crc32c.table = []
for _i in range(256):
    _c = _i
    for _ in range(8):
        _c = (_c >> 1) ^ (0x82F63B78 if _c & 1 else 0)
    crc32c.table.append(_c)


def logical_bytes(raw):
    return b"".join(raw[p:p + 1020] for p in range(0, len(raw), 1024))


def paged(logical):
    logical += b"\0" * (-len(logical) % 1020)
    pages = [logical[p:p + 1020] for p in range(0, len(logical), 1020)]
    return b"".join(page + struct.pack(">I", crc32c(page)) for page in pages)


def with_xml(path, edit):
    """The file with its XML section (the last section, as libE57 writes it)
    replaced by edit(xml), pages and CRCs rebuilt."""
    raw = path.read_bytes()
    xml_offset, xml_length = struct.unpack_from("<QQ", raw, 24)
    logical = logical_bytes(raw)
    start = xml_offset // 1024 * 1020 + xml_offset % 1024
    xml = edit(logical[start:start + xml_length].decode())
    logical = bytearray(logical[:start] + xml.encode())
    struct.pack_into("<Q", logical, 32, len(xml.encode()))
    out = bytearray(paged(bytes(logical)))
    struct.pack_into("<Q", out, 16, len(out))
    return bytes(paged(logical_bytes(out)))  # CRCs of the header page again


@pytest.fixture
def normals_file():
    return DATA / "pye57_testWithNormals.e57"


def read_error(tmp_path, data):
    bad = tmp_path / "bad.e57"
    bad.write_bytes(data)
    with pytest.raises(pointnpr.ReadError) as err:
        pointnpr.read_e57_scans(str(bad))
    with pytest.raises(pointnpr.ReadError):
        pointnpr.read(str(bad))
    return err.value


def test_a_rewritten_file_still_reads(tmp_path, normals_file):
    same = tmp_path / "same.e57"
    same.write_bytes(with_xml(normals_file, lambda x: x))
    np.testing.assert_array_equal(pointnpr.read(str(same)).positions, pointnpr.read(str(normals_file)).positions)


@pytest.mark.parametrize("edit, message", [
    (lambda x: x.replace("</e57Root>", "</e57Roo>"), "malformed XML section"),
    (lambda x: x.replace('recordCount="2"', 'recordCount="999999999999"'), "recordCount 999999999999 is more than"),
    (lambda x: x.replace('<nor:normalZ type="Float" precision="single"', '<nor:normalZ type="Float" precision="double"'),
     "ends after 1 of 2 records"),
    (lambda x: x.replace('<nor:normalZ type="Float" precision="single" minimum="-1" maximum="1"/>', ""),
     "carries 6 bytestreams but the prototype has 5 fields"),
    (lambda x: x.replace('fileOffset="48"', 'fileOffset="1020"'), "points into a page's checksum"),
    (lambda x: x.replace('<cartesianZ type="Float" precision="single" minimum="0" maximum="0"/>',
                         '<cartesianZ type="Integer" minimum="5" maximum="-5"/>'), "minimum 5 above maximum -5"),
    (lambda x: x.replace('<cartesianZ type="Float" precision="single" minimum="0" maximum="0"/>',
                         '<cartesianZ type="String"/>'), "of type 'String'"),
    (lambda x: x.replace('recordCount="2"', 'recordCount="2x"'), "recordCount='2x' is not an unsigned 64-bit integer"),
    (lambda x: x.replace('<codecs type="Vector" allowHeterogeneousChildren="1">',
                         '<codecs type="Vector" allowHeterogeneousChildren="1"><c type="Structure"/>'),
     "a codec other than bitPackCodec"),
])
def test_broken_xml_and_prototypes_are_one_read_error_each(tmp_path, normals_file, edit, message):
    err = read_error(tmp_path, with_xml(normals_file, edit))
    assert message in str(err)


def test_truncated_file_and_bad_crc(tmp_path, normals_file):
    raw = normals_file.read_bytes()
    assert "truncated" in str(read_error(tmp_path, raw[:-1024]))
    longer = bytearray(raw)
    struct.pack_into("<Q", longer, 16, len(raw) + 1024)
    assert "the header gives a length of 4096 bytes but the file has 3072 (truncated)" in str(
        read_error(tmp_path, bytes(longer)))
    flipped = bytearray(raw)
    flipped[1024 + 5] ^= 1
    err = read_error(tmp_path, bytes(flipped))
    assert "CRC-32C mismatch in page 1 (bytes 1024-2047)" in str(err)
    assert err.byte_offset == 1024 + 1020
    assert "not an E57 file" in str(read_error(tmp_path, b"ASTM-E58" + raw[8:]))


def test_progress_reports_and_cancels(tmp_path):
    path = DATA / "pye57_pumpAVisualReferenceImage.e57"
    progress = pointnpr.Progress()
    assert pointnpr.read(str(path), progress=progress).num_points == 155201
    assert progress.fraction == 1.0
    cancelled = pointnpr.Progress()
    cancelled.cancel()
    with pytest.raises(pointnpr.Cancelled):
        pointnpr.read(str(path), progress=cancelled)


def test_nan_positions_are_dropped_and_integer_attributes_saturate(tmp_path):
    path = tmp_path / "odd_types.e57"
    write_e57(path, [{"fields": [("cartesianX", double(), [1.0, np.nan, 3.0, 4.0, 5.0]),
                                 ("cartesianY", double(), [0.0] * 5),
                                 ("cartesianZ", double(), [0.0] * 5),
                                 # a float where the standard has an integer
                                 ("rowIndex", double(), [1e300, 0.0, np.nan, -5.0, 3.0]),
                                 ("returnIndex", double(), [300.0, 0.0, -9.0, np.nan, 1.0])]}])
    (scan,) = pointnpr.read_e57_scans(str(path))
    assert scan.metadata["dropped_nonfinite"] == 1
    np.testing.assert_array_equal(scan.positions[:, 0], [1.0, 3.0, 4.0, 5.0])
    assert scan.attributes["row_index"].dtype == np.int64
    np.testing.assert_array_equal(scan.attributes["row_index"], [np.iinfo(np.int64).max, 0, -5, 3])
    np.testing.assert_array_equal(scan.attributes["return_number"], [255, 0, 0, 2])


def packet(kind, body):
    """A packet with its logical length (minus 1) filled in, padded to 4 bytes."""
    body = bytes(body) + b"\0" * (-len(body) % 4)
    return bytes([kind, 0]) + struct.pack("<H", len(body) + 3) + body


def with_packets(path, make_packets):
    """pye57_testWithNormals.e57 with its one CompressedVector section (at
    byte 48, 6 streams of 8 bytes) rebuilt from make_packets(streams, section
    data offset), followed by the XML; header, pages and CRCs rebuilt."""
    raw = path.read_bytes()
    logical = logical_bytes(raw)
    xml_offset, xml_length = struct.unpack_from("<QQ", raw, 24)
    xml = logical[xml_offset:xml_offset + xml_length]  # page 0: physical == logical
    data = logical[80:148]
    assert data[0] == 1 and struct.unpack_from("<H", data, 4)[0] == 6
    streams = [data[18 + 8 * s:26 + 8 * s] for s in range(6)]
    packets = make_packets(streams, 80)
    section = bytearray(32)
    section[0] = 1
    struct.pack_into("<QQQ", section, 8, 32 + len(packets), 80, 0)
    body = bytearray(logical[:48] + bytes(section) + packets)
    xml_logical = len(body)
    body += xml
    struct.pack_into("<QQ", body, 24, xml_logical // 1020 * 1024 + xml_logical % 1020, len(xml))
    out = bytearray(paged(bytes(body)))
    struct.pack_into("<Q", out, 16, len(out))
    return paged(logical_bytes(out))


def test_index_and_empty_packets_are_skipped_and_values_straddle_data_packets(tmp_path, normals_file):
    def make(streams, data_offset):
        empty = packet(2, b"\0" * 4)
        index = packet(0, struct.pack("<HB9sQQ", 1, 0, b"", 0, data_offset))
        first = packet(1, struct.pack("<H6H", 6, *[3] * 6) + b"".join(s[:3] for s in streams))
        second = packet(1, struct.pack("<H6H", 6, *[5] * 6) + b"".join(s[3:] for s in streams))
        return empty + index + first + empty + second

    path = tmp_path / "packets.e57"
    path.write_bytes(with_packets(normals_file, make))
    (ours,) = pointnpr.read_e57_scans(str(path))
    (original,) = pointnpr.read_e57_scans(str(normals_file))
    np.testing.assert_array_equal(ours.positions, original.positions)
    np.testing.assert_array_equal(ours.attributes["normals"], original.attributes["normals"])
    assert ours.positions[:, 0].tolist() == [1.0, 2.0]


@pytest.mark.parametrize("make, message", [
    # (padded: a section too short for its records is refused before its packets)
    (lambda s, o: packet(7, b"\0" * 60), "unknown packet type 7"),
    (lambda s, o: packet(1, struct.pack("<H6H", 6, *[9] * 6) + b"".join(s)), "overruns its data packet"),
    (lambda s, o: packet(1, struct.pack("<H6H", 6, *[4] * 6) + b"".join(x[:4] for x in s)), "ends after 1 of 2 records"),
    (lambda s, o: b"\x01\x00\xff\xff" + b"\0" * 60, "runs past the end of its section"),
])
def test_broken_packets_are_one_read_error_each(tmp_path, normals_file, make, message):
    assert message in str(read_error(tmp_path, with_packets(normals_file, make)))


def test_scans_sharing_a_section_are_a_read_error(tmp_path, normals_file):
    def twice(xml):
        start = xml.index("<vectorChild")
        end = xml.index("</vectorChild>") + len("</vectorChild>")
        return xml[:end] + xml[start:end] + xml[end:]

    assert "two scans' CompressedVector sections overlap" in str(read_error(tmp_path, with_xml(normals_file, twice)))
