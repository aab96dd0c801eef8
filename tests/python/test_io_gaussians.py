"""3D Gaussian splat files (io/gaussians.h): a 3DGS PLY recognised by its
properties in the PLY reader, and SPZ (io/spz_reader.cpp), both giving the
splats' parameters with their meaning; a clear ReadError for each kind of
bad file (fuzz/fuzz_spz.cpp fuzzes the SPZ reader)."""
import gzip
import os
import struct

import numpy as np
import pytest

import pointnpr
from gaussian_reference import assert_read_error, SH_C0, quat_matrix, random_splats, write_3dgs_ply, write_spz

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DATA = os.path.join(ROOT, "tests", "data", "io", "gaussians")


@pytest.mark.parametrize("degree", [0, 1, 2, 3])
def test_a_3dgs_ply_is_read_as_splats_with_their_meaning(tmp_path, degree):
    means, q, scales, opacity, sh = random_splats(200, degree, seed=degree)
    path = str(tmp_path / "splats.ply")
    write_3dgs_ply(path, means, q * 3.0, scales, opacity, sh, degree)  # quaternions not unit in the file
    d = pointnpr.read(path)
    a = d.attributes
    assert d.metadata["gaussian_splats"] == 1 and d.metadata["sh_degree"] == degree
    assert np.allclose(d.positions, means.astype(np.float32), atol=1e-6)
    assert np.allclose(a["opacity"], opacity, atol=1e-6)
    assert np.allclose(a["scales"], scales, rtol=1e-5)
    assert np.allclose(a["rotations"], q, atol=1e-6)  # normalised, w first
    K = (degree + 1) ** 2
    assert a["sh"].shape == (200, 3 * K)
    assert np.allclose(a["sh"].reshape(200, K, 3), sh, atol=1e-6)  # f_rest_* reordered coefficient-major
    expected = np.rint(np.clip(0.5 + SH_C0 * sh[:, 0], 0, 1) * 255)
    assert np.abs(a["colors"].astype(int) - expected).max() <= 1
    # The raw columns and 3DGS's all-zero normals are gone.
    for gone in ("f_dc_0", "f_rest_0", "rot_0", "scale_0", "normals", "nx"):
        assert gone not in a
    cloud = d.to_cloud()
    assert cloud.sh_degree == degree and cloud.num_points == 200


@pytest.mark.parametrize("version", [2, 3])
def test_spz_and_ply_of_one_capture_coincide_within_the_quantisation(tmp_path, version):
    degree = 3
    means, q, scales, opacity, sh = random_splats(300, degree, seed=7)
    sh[:, 1:] = np.clip(sh[:, 1:], -0.99, 0.99)
    ply, spz = str(tmp_path / "a.ply"), str(tmp_path / "a.spz")
    write_3dgs_ply(ply, means, q, scales, opacity, sh, degree)
    write_spz(spz, means, q, scales, opacity, sh, degree, version=version)
    a, b = pointnpr.read(ply), pointnpr.read(spz)
    assert b.metadata["format"] == "spz" and b.metadata["version"] == str(version)
    assert b.metadata["sh_degree"] == degree and b.metadata["gaussian_splats"] == 1
    assert np.abs(a.positions - b.positions).max() <= 2.0 ** -12
    A, B = a.attributes, b.attributes
    assert np.abs(A["opacity"] - B["opacity"]).max() <= 0.5 / 255 + 1e-6
    assert np.abs(np.log(A["scales"]) - np.log(B["scales"])).max() <= 1 / 32 + 1e-5
    dc_step = 1.0 / (0.15 * 255.0)
    sa, sb = A["sh"].reshape(-1, 16, 3), B["sh"].reshape(-1, 16, 3)
    assert np.abs(sa[:, 0] - sb[:, 0]).max() <= 0.5 * dc_step + 1e-5
    assert np.abs(sa[:, 1:] - sb[:, 1:]).max() <= 0.5 / 128 + 1e-5  # SH signs turned back with the axes
    # Rotations as matrices (q and -q are one rotation). v2 keeps x, y, z
    # in 8 bits and derives w, which is coarse where w is small; v3 keeps
    # the smallest three in 9 bits.
    err = np.array([np.abs(quat_matrix(qa) - quat_matrix(qb)).max() for qa, qb in zip(A["rotations"], B["rotations"])])
    assert err.max() <= (0.25 if version == 2 else 0.005)
    assert np.median(err) <= (0.01 if version == 2 else 0.002)
    assert np.allclose(np.linalg.norm(B["rotations"], axis=1), 1.0, atol=1e-6)


def test_the_committed_synthetic_files_read(tmp_path):
    for name in ("synthetic_v2.spz", "synthetic_v3.spz", "synthetic_3dgs.ply"):
        d = pointnpr.read(os.path.join(DATA, name))
        assert d.metadata["gaussian_splats"] == 1 and d.num_points == 64, name


def _spz_bytes(header, body=b"", compress=True):
    raw = header + body
    return gzip.compress(raw, mtime=0) if compress else raw


def _bad_crc():
    good = gzip.compress(_header() + bytes(20), mtime=0)
    return good[:-8] + bytes(x ^ 0xFF for x in good[-8:-4]) + good[-4:]


_NOISE = np.random.default_rng(3).integers(0, 256, 4000, dtype=np.uint8).tobytes()


def _header(version=3, n=1, degree=0, fractional=12, flags=0, magic=0x5053474E):
    return struct.pack("<IIIBBBB", magic, version, n, degree, fractional, flags, 0)


BAD_SPZ = {
    "empty": (b"", "empty"),
    "not gzip": (b"hello world", "gzip header"),
    "ngsp of version 5": (b"NGSP" + struct.pack("<I", 5) + bytes(24), "unsupported SPZ version 5"),
    "corrupt gzip (CRC)": (None, "gzip stream is corrupt"),
    "truncated gzip": (None, "truncated"),
    "truncated gzip after the data": (gzip.compress(_header() + bytes(20) + _NOISE, mtime=0)[:-100], "truncated"),
    "short header": (_spz_bytes(b"\x4e\x47\x53\x50\x03\x00"), "header"),
    "bad magic": (_spz_bytes(_header(magic=0x12345678) + bytes(20)), "magic"),
    "version 1": (_spz_bytes(_header(version=1) + bytes(20)), "version 1"),
    "version 9": (_spz_bytes(_header(version=9) + bytes(20)), "unsupported SPZ version 9"),
    "degree 7": (_spz_bytes(_header(degree=7) + bytes(20)), "SH degree 7"),
    "fractional bits": (_spz_bytes(_header(fractional=40) + bytes(20)), "fractional bits"),
    "extensions": (_spz_bytes(_header(flags=2) + bytes(20)), "extensions"),
    "too many points": (_spz_bytes(_header(n=0xFFFFFFFF)), "more than"),
    "fewer bytes than points": (_spz_bytes(_header(n=1000) + bytes(100)), "truncated"),
}


@pytest.mark.parametrize("case", list(BAD_SPZ))
def test_a_bad_spz_file_is_a_clear_read_error(tmp_path, case):
    data, words = BAD_SPZ[case]
    if case == "corrupt gzip (CRC)":
        data = _bad_crc()
    elif case == "truncated gzip":
        data = gzip.compress(_header(n=150) + _NOISE, mtime=0)[:-1500]
    assert_read_error(tmp_path / "bad.spz", data, words)


def _ply_with(tmp_path, names, rows):
    header = "ply\nformat ascii 1.0\nelement vertex %d\n" % len(rows)
    header += "".join(f"property float {n}\n" for n in names) + "end_header\n"
    path = tmp_path / "bad.ply"
    path.write_text(header + "".join(" ".join(str(v) for v in r) + "\n" for r in rows))
    return str(path)


FULL = ["x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2",
        "rot_0", "rot_1", "rot_2", "rot_3"]


@pytest.mark.parametrize("case", ["missing rot_3", "ten f_rest", "gap in f_rest", "nan opacity", "huge scale"])
def test_a_bad_3dgs_ply_is_a_clear_read_error(tmp_path, case):
    names, row = list(FULL), [0.0] * len(FULL)
    row[10] = 1.0
    words = {"missing rot_3": "rot_3", "ten f_rest": "10 f_rest_", "gap in f_rest": "without gaps",
             "nan opacity": "non-finite opacity", "huge scale": "scale too large"}[case]
    if case == "missing rot_3":
        names, row = names[:-1], row[:-1]
    elif case == "ten f_rest":
        names += [f"f_rest_{j}" for j in range(10)]
        row += [0.0] * 10
    elif case == "gap in f_rest":
        names += [f"f_rest_{j}" for j in range(9)] + ["f_rest_12"]
        row += [0.0] * 10
    elif case == "nan opacity":
        row[6] = float("nan")
    else:
        row[7] = 1e6
    with pytest.raises(pointnpr.ReadError) as e:
        pointnpr.read(_ply_with(tmp_path, names, [row]))
    assert words in str(e.value), str(e.value)


def test_a_zero_quaternion_becomes_the_identity_and_a_plain_ply_stays_plain(tmp_path):
    row = [0.0] * len(FULL)
    d = pointnpr.read(_ply_with(tmp_path, FULL, [row]))
    assert np.array_equal(d.attributes["rotations"], [[1, 0, 0, 0]])
    plain = pointnpr.read(_ply_with(tmp_path, ["x", "y", "z", "opacity"], [[0, 0, 0, 0.5]]))
    assert "gaussian_splats" not in plain.metadata and "opacity" in plain.attributes
