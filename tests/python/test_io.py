"""pointnpr.read / PointData / ReadError: the numpy API of the file readers.

Run with the build folder on the path, e.g.
POINTNPR_BUILD_DIR=build /usr/bin/python3 -m pytest tests/python/test_io.py
"""
import gc
import os
import pathlib
import struct

import numpy as np
import pytest

try:
    import pointnpr
    from pointnpr import _pointnpr as _mod
except ImportError:  # the package __init__ may be mid-edit: use the module itself
    from pointnpr import _pointnpr as _mod  # noqa: F811

    pointnpr = _mod

DATA = pathlib.Path(__file__).resolve().parents[1] / "data" / "io"


def las_records(path):
    """Independent LAS decoding with numpy (formats 3/6/8 used below)."""
    raw = path.read_bytes()
    off, = struct.unpack_from("<I", raw, 96)
    pf = raw[104]
    rl, = struct.unpack_from("<H", raw, 105)
    n, = struct.unpack_from("<I", raw, 107)
    if raw[25] >= 4:
        n64, = struct.unpack_from("<Q", raw, 247)
        n = n64 or n
    scale = np.array(struct.unpack_from("<3d", raw, 131))
    offset = np.array(struct.unpack_from("<3d", raw, 155))
    rec = np.frombuffer(raw, np.uint8, count=n * rl, offset=off).reshape(n, rl)
    xyz = rec[:, :12].copy().view("<i4").astype(np.float64) * scale + offset
    return pf, rec, xyz


def test_module_exports():
    assert callable(pointnpr.read)
    assert issubclass(pointnpr.ReadError, ValueError)
    assert pointnpr.ReadError is _mod.ReadError
    assert pointnpr.PointData is _mod.PointData


def test_las_numpy_api_matches_independent_decoding():
    path = DATA / "warsaw_small.las"
    data = pointnpr.read(str(path))
    pf, rec, xyz = las_records(path)
    assert pf == 3
    assert data.num_points == len(data) == 3000
    assert data.positions.dtype == np.float64 and data.positions.shape == (3000, 3)
    np.testing.assert_array_equal(data.positions, xyz)  # exact, not approximately
    a = data.attributes
    assert a["colors"].dtype == np.uint8 and a["colors"].shape == (3000, 3)
    rgb16 = rec[:, 28:34].copy().view("<u2")
    np.testing.assert_array_equal(a["colors"], (rgb16 >> 8).astype(np.uint8))
    assert a["intensity"].dtype == np.float32 and a["intensity"].shape == (3000,)
    np.testing.assert_array_equal(a["intensity"], rec[:, 12:14].copy().view("<u2")[:, 0])
    assert a["classification"].dtype == np.uint8
    np.testing.assert_array_equal(a["classification"], rec[:, 15] & 31)
    assert a["gps_time"].dtype == np.float64
    m = data.metadata
    assert m["format"] == "las" and m["version"] == "1.2" and m["point_format"] == 3
    assert m["scale"] == (0.01, 0.01, 0.01)
    assert m["offset"][:2] == (639000.0, 485000.0)
    assert m["color_bits"] == 16


def test_las14_format6_and_crs():
    path = DATA / "laspy_nebraska_classified.las"
    data = pointnpr.read(path)  # os.PathLike accepted
    pf, rec, xyz = las_records(path)
    assert pf == 6 and data.num_points == 25408
    np.testing.assert_array_equal(data.positions, xyz)
    np.testing.assert_array_equal(data.attributes["classification"], rec[:, 16])
    assert "colors" not in data.attributes
    assert "NAD83_2011_Nebraska_ft" in data.metadata["crs_wkt"]
    assert data.metadata["crs_epsg"] == 32104


def test_las_format8_nir_and_extra_bytes():
    d8 = pointnpr.read(DATA / "lidarhd_myria3d_subset.las")
    assert d8.attributes["nir"].dtype == np.uint16 and d8.attributes["nir"].shape == (2000,)
    d7 = pointnpr.read(DATA / "lion_takanawa_subset.las")
    origin = d7.attributes["OriginId"]
    assert origin.dtype == np.uint32 and origin[0] == 41 and origin[-1] == 140


def test_ply_normals_colors_and_other_properties():
    d = pointnpr.read(DATA / "malformed" / "ply_assimp_points.ply")
    assert d.metadata["format"] == "ply"
    assert d.attributes["normals"].dtype == np.float32
    assert d.attributes["normals"].shape == (4, 3)
    np.testing.assert_array_equal(d.attributes["normals"][2], [1, 0, 0])
    np.testing.assert_array_equal(d.attributes["colors"][1], [255, 0, 255])
    bunny = pointnpr.read(DATA / "bun_zipper_res2.ply")
    assert bunny.num_points == 8171
    assert bunny.attributes["confidence"].dtype == np.float32
    assert bunny.positions[0, 0] == -0.036872


def test_big_endian_ply_generated_with_numpy(tmp_path):
    rng = np.random.default_rng(3)
    n = 257
    rec = np.zeros(n, dtype=[("x", ">f8"), ("y", ">f8"), ("z", ">f4"), ("red", "u1"),
                             ("green", "u1"), ("blue", "u1"), ("quality", ">i2")])
    rec["x"] = rng.normal(6617080.0, 10.0, n)
    rec["y"] = rng.normal(-1e5, 10.0, n)
    rec["z"] = rng.normal(0.0, 1.0, n)
    for c in ("red", "green", "blue"):
        rec[c] = rng.integers(0, 256, n)
    rec["quality"] = rng.integers(-1000, 1000, n)
    header = ("ply\nformat binary_big_endian 1.0\ncomment numpy\nelement vertex %d\n"
              "property double x\nproperty double y\nproperty float z\nproperty uchar red\n"
              "property uchar green\nproperty uchar blue\nproperty short quality\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n" % n)
    face = b"\x03" + np.array([0, 1, 2], ">i4").tobytes()
    path = tmp_path / "be.ply"
    path.write_bytes(header.encode() + rec.tobytes() + face)
    d = pointnpr.read(path)
    np.testing.assert_array_equal(d.positions[:, 0], rec["x"])
    np.testing.assert_array_equal(d.positions[:, 1], rec["y"])
    np.testing.assert_array_equal(d.positions[:, 2], rec["z"].astype(np.float64))
    np.testing.assert_array_equal(d.attributes["colors"],
                                  np.column_stack([rec["red"], rec["green"], rec["blue"]]))
    np.testing.assert_array_equal(d.attributes["quality"], rec["quality"].astype(np.float32))


def test_arrays_outlive_the_point_data():
    d = pointnpr.read(DATA / "mvk-thin.las")
    pos, cls = d.positions, d.attributes["classification"]
    first = pos[0].copy()
    del d
    gc.collect()
    np.testing.assert_array_equal(pos[0], first)
    assert cls.shape == (6280,)


@pytest.mark.parametrize("name, reason", [
    ("las_pdal_1.2-no-points_truncated.las", "file is truncated"),
    ("las_pdal_bad_vlr_count.las", "VLR count"),
    ("las_pdal_garbage_nVariableLength.las", "variable length records"),
    ("ply_pdal_sized_dims.ply", "no 'z' property"),
    ("ply_trimesh_emptyIO_ply_empty_header.ply", "no 'vertex' element"),
])
def test_broken_files_raise_read_error(name, reason):
    path = str(DATA / "malformed" / name)
    with pytest.raises(ValueError) as info:
        pointnpr.read(path)
    err = info.value
    assert isinstance(err, pointnpr.ReadError)
    assert reason in str(err)
    assert path in str(err)
    assert err.file == path
    assert reason in err.reason
    assert isinstance(err.byte_offset, int)


def test_missing_and_unknown_files(tmp_path):
    with pytest.raises(pointnpr.ReadError, match="cannot open file"):
        pointnpr.read(tmp_path / "nope.las")
    (tmp_path / "x.foo").write_text("hello")
    with pytest.raises(pointnpr.ReadError, match="unrecognised point cloud format"):
        pointnpr.read(tmp_path / "x.foo")
    with pytest.raises(pointnpr.ReadError, match="is a directory"):
        pointnpr.read(str(tmp_path) + os.sep + ".")


def test_truncated_copy_reports_byte_offset(tmp_path):
    raw = (DATA / "warsaw_small.las").read_bytes()
    p = tmp_path / "cut.las"
    p.write_bytes(raw[:-10])
    with pytest.raises(pointnpr.ReadError) as info:
        pointnpr.read(p)
    assert "declares 3000 points of 34 bytes" in str(info.value)
    assert info.value.byte_offset == len(raw) - 10


def test_point_data_constructor_and_repr():
    pos = np.arange(12, dtype=np.float64).reshape(4, 3)
    d = pointnpr.PointData(pos, {"intensity": np.ones(4, np.float32)}, {"format": "mine"})
    assert d.num_points == 4
    assert "mine" in repr(d) and "intensity" in repr(d)
    with pytest.raises(ValueError):
        pointnpr.PointData(np.zeros((4, 2)))
    with pytest.raises(ValueError):
        pointnpr.PointData(pos, {"intensity": np.ones(3, np.float32)})


def test_to_cloud():
    from pointnpr import io as pio

    d = pointnpr.read(DATA / "warsaw_small.las")
    cloud = d.to_cloud()
    assert cloud.num_points == 3000
    assert cloud.has("colors") and cloud.has("intensity") and cloud.has("classification")
    cloud2 = pio.to_cloud(pointnpr.read(DATA / "tinyply_elephant.ply"))
    assert cloud2.num_points == 19753
    assert not cloud2.has("colors")


def test_pcd_and_text():
    mug = pointnpr.read(DATA / "mug_crop.pcd")
    assert mug.metadata["format"] == "pcd" and mug.metadata["organized"] == 1
    assert mug.num_points == 4749  # 4800 minus the NaN (missing) pixels
    assert np.isfinite(mug.positions).all()
    assert mug.attributes["colors"].shape == (4749, 3)
    txt = pointnpr.read(DATA / "malformed" / "text_pdal_crlf_test.txt")
    assert txt.metadata["format"] == "text"
    np.testing.assert_array_equal(txt.attributes["intensity"], np.arange(10, dtype=np.float32))


def test_binary_garbage_in_names_and_messages(tmp_path):
    p = tmp_path / "names.ply"
    p.write_bytes(b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                  b"property float z\nproperty float t\xe9mp\xff\nend_header\n1 2 3 4\n")
    d = pointnpr.read(p)
    (name,) = [k for k in d.attributes if k.startswith("t")]
    assert d.attributes[name][0] == 4.0
    bad = tmp_path / "bad.ply"
    bad.write_bytes(b"ply\nformat ascii 1.0\n\xff\xfe\x00garbage\nend_header\n")
    with pytest.raises(pointnpr.ReadError) as info:
        pointnpr.read(bad)
    assert "\\xff\\xfe\\x00garbage" in str(info.value)


def test_unusual_file_names(tmp_path):
    src = (DATA / "malformed" / "ply_pdal_simple_binary.ply").read_bytes()
    p = tmp_path / "Wolkë punkt 点.ply"
    p.write_bytes(src)
    assert pointnpr.read(p).num_points == 3
    assert pointnpr.read(os.fsencode(p)).num_points == 3
    raw = os.path.join(os.fsencode(tmp_path), b"bad\xff.ply")
    with open(raw, "wb") as f:
        f.write(src)
    assert pointnpr.read(raw).num_points == 3
