"""pointnpr.write: binary PLY and LAS 1.4; write then read gives the same data.

Run with the build folder on the path, e.g.
POINTNPR_BUILD_DIR=build /usr/bin/python3 -m pytest tests/python/test_io_write.py
"""
import pathlib
import struct

import numpy as np
import pytest

import pointnpr

DATA = pathlib.Path(__file__).resolve().parents[1] / "data" / "io"


def cloud(n=1000, seed=0, base=(500000.0, 6600000.0, 100.0)):
    rng = np.random.default_rng(seed)
    pos = rng.uniform(-100, 100, (n, 3)) + np.asarray(base)
    return rng, pos


def assert_same_attributes(a, b, same_dtype=True, skip=()):
    for name, values in a.attributes.items():
        if name in skip:
            continue
        assert name in b.attributes, name
        got = b.attributes[name]
        assert got.shape == values.shape, name
        if same_dtype:
            assert got.dtype == values.dtype, name
        np.testing.assert_array_equal(got, values, err_msg=name)


def test_write_is_exported():
    assert pointnpr.write is pointnpr._pointnpr.write
    from pointnpr import io as pio

    assert pio.write is pointnpr.write


def test_ply_round_trip_every_dtype(tmp_path):
    rng, pos = cloud(5000, 1)
    attrs = {
        "colors": rng.integers(0, 256, (5000, 3), dtype=np.uint8),
        "normals": rng.normal(size=(5000, 3)).astype(np.float32),
        "intensity": rng.random(5000, dtype=np.float32),
        "classification": rng.integers(0, 20, 5000).astype(np.uint8),
        "segment": rng.integers(-2**31, 2**31, 5000).astype(np.int32),
        "weight": rng.random(5000),  # float64 stays float64
        "flag": rng.random(5000) > 0.5,  # bool is written as uint8
        "u16": rng.integers(0, 65536, 5000).astype(np.uint16),
        "i8": rng.integers(-128, 128, 5000).astype(np.int8),
    }
    data = pointnpr.PointData(pos, attrs, {"comments": "scan 7"})
    path = tmp_path / "all.ply"
    pointnpr.write(path, data)
    back = pointnpr.read(path)
    np.testing.assert_array_equal(back.positions, pos)  # exact
    expected = dict(attrs, flag=attrs["flag"].astype(np.uint8))
    assert_same_attributes(pointnpr.PointData(pos, expected), back)
    assert back.metadata["comments"] == "written by PointNPR\nscan 7"
    # The file is what the header says: independent decoding with numpy.
    raw = path.read_bytes()
    header, body = raw.split(b"end_header\n", 1)
    assert b"format binary_little_endian 1.0" in header
    assert b"element vertex 5000" in header
    xyz = np.frombuffer(body, dtype="<f8", count=3)
    np.testing.assert_array_equal(xyz, pos[0])


def test_las_round_trip_of_real_files_is_exact(tmp_path):
    for name in ["warsaw_small.las", "lidarhd_myria3d_subset.las", "mvk-thin.las",
                 "malformed/las_pdal_test1_4.las"]:
        src = pointnpr.read(DATA / name)
        out = tmp_path / "copy.las"
        pointnpr.write(out, src)
        back = pointnpr.read(out)
        np.testing.assert_array_equal(back.positions, src.positions, err_msg=name)
        assert back.metadata["scale"] == src.metadata["scale"]
        assert back.metadata["offset"] == src.metadata["offset"]
        # Formats 0-5 store whole degrees; 6-10 steps of 0.006 degrees.
        assert_same_attributes(src, back, skip=("scan_angle",))
        np.testing.assert_allclose(back.attributes["scan_angle"], src.attributes["scan_angle"],
                                   atol=0.003 + 1e-5)
        for key in ("crs_wkt", "crs_epsg", "system_identifier"):
            assert back.metadata.get(key) == src.metadata.get(key), (name, key)
        assert back.metadata["version"] == "1.4"


def test_las_generated_cloud(tmp_path):
    rng, pos = cloud(3000, 2)
    wkt = 'PROJCS["RGF93 / Lambert-93",AUTHORITY["EPSG","2154"]]'
    attrs = {
        "colors": rng.integers(0, 256, (3000, 3), dtype=np.uint8),
        "intensity": rng.integers(0, 65536, 3000).astype(np.float32),
        "classification": rng.integers(0, 256, 3000).astype(np.uint8),
        "gps_time": rng.uniform(0, 1e9, 3000),
        "normals": rng.normal(size=(3000, 3)).astype(np.float32),
        "height_above_ground": rng.normal(size=3000),
        "instance": rng.integers(0, 2**40, 3000).astype(np.uint64),
    }
    data = pointnpr.PointData(pos, attrs, {"crs_wkt": wkt})
    path = tmp_path / "gen.las"
    pointnpr.write(path, data)
    back = pointnpr.read(path)
    scale = np.asarray(back.metadata["scale"])
    assert (scale <= 1e-4).all()
    err = np.abs(back.positions - pos)
    assert (err <= scale / 2 + 1e-9).all()
    assert err.max() <= 0.5e-4  # better than 0.1 mm
    assert back.metadata["crs_wkt"] == wkt
    assert back.metadata["point_format"] == 7
    assert_same_attributes(data, back, same_dtype=False)
    for name in ("normals", "height_above_ground", "instance", "colors", "gps_time"):
        assert back.attributes[name].dtype == attrs[name].dtype, name
    # Header fields checked independently.
    raw = path.read_bytes()
    assert raw[:4] == b"LASF" and raw[24:26] == bytes([1, 4])
    assert raw[104] == 7
    assert struct.unpack_from("<Q", raw, 247)[0] == 3000
    assert struct.unpack_from("<H", raw, 6)[0] & 16  # WKT bit
    assert b"LASF_Spec" in raw[375:2000] and b"height_above_ground" in raw[375:2000]


def test_write_errors(tmp_path):
    pos = np.zeros((2, 3))
    with pytest.raises(pointnpr.Error, match="value 300 at point 1"):
        pointnpr.write(tmp_path / "a.las",
                       pointnpr.PointData(pos, {"classification": np.array([1, 300])}))
    assert not (tmp_path / "a.las").exists()
    with pytest.raises(pointnpr.Error, match="cannot write '.xyz' files"):
        pointnpr.write(tmp_path / "a.xyz", pointnpr.PointData(pos))
    with pytest.raises(pointnpr.Error, match="non-finite"):
        pointnpr.write(tmp_path / "a.ply", pointnpr.PointData(np.full((1, 3), np.nan)))
    with pytest.raises(ValueError, match="dtype"):
        pointnpr.write(tmp_path / "a.ply",
                       pointnpr.PointData(pos, {"c": np.zeros(2, np.complex64)}))
    with pytest.raises(pointnpr.Error, match="cannot open the file for writing"):
        pointnpr.write(tmp_path / "missing" / "a.ply", pointnpr.PointData(pos))


def test_round_trip_through_both_formats_with_unicode_name(tmp_path):
    src = pointnpr.read(DATA / "mug_crop.pcd")
    ply = tmp_path / "tasse à café.ply"
    pointnpr.write(ply, src)
    las = tmp_path / "tasse à café.las"
    pointnpr.write(las, pointnpr.read(ply))
    back = pointnpr.read(las)
    assert back.num_points == src.num_points
    assert np.abs(back.positions - src.positions).max() <= 0.5e-4
    np.testing.assert_array_equal(back.attributes["colors"], src.attributes["colors"])
