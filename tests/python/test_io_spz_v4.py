"""SPZ version 4 (io/spz_reader.cpp): the plain NGSP container of zstd
attribute streams, read to the same splats as version 3 of the same
capture; extension records skipped; a clear ReadError for each kind of bad
file (fuzz_spz is seeded with tests/data/io/gaussians/synthetic_v4.spz)."""
import os
import struct

import numpy as np
import pytest

import pointnpr
from gaussian_reference import assert_read_error, random_splats, spz_streams, spz_v4_bytes, write_spz, zstd_compress

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DATA = os.path.join(ROOT, "tests", "data", "io", "gaussians")


def _read(tmp_path, data, name="a.spz"):
    path = tmp_path / name
    path.write_bytes(data)
    return pointnpr.read(str(path))


@pytest.mark.parametrize("degree", [0, 1, 3, 4])
def test_version_4_reads_the_splats_of_version_3(tmp_path, degree):
    means, q, scales, opacity, sh = random_splats(300, min(degree, 3), seed=degree + 20)
    if degree == 4:  # degree 4 bands (read past, degree 3 kept)
        sh = np.concatenate([sh, np.random.default_rng(1).uniform(-0.5, 0.5, (300, 9, 3))], axis=1)
    sh[:, 1:] = np.clip(sh[:, 1:], -0.99, 0.99)
    v3, v4 = str(tmp_path / "v3.spz"), str(tmp_path / "v4.spz")
    write_spz(v3, means, q, scales, opacity, sh, degree, version=3)
    write_spz(v4, means, q, scales, opacity, sh, degree, version=4)
    a, b = pointnpr.read(v3), pointnpr.read(v4)
    assert b.metadata["format"] == "spz" and b.metadata["version"] == "4"
    assert b.metadata["sh_degree"] == min(degree, 3) and b.num_points == 300
    assert np.array_equal(a.positions, b.positions)
    for name in ("opacity", "scales", "rotations", "sh", "colors"):
        assert np.array_equal(a.attributes[name], b.attributes[name]), name
    assert ("warning" in b.metadata) == (degree == 4)
    # The values are the splats' (within SPZ's quantisation), not zeros.
    assert np.abs(b.positions - means).max() <= 2.0 ** -12
    assert np.abs(b.attributes["opacity"] - opacity).max() <= 0.5 / 255 + 1e-6


def test_extensions_are_skipped_and_frames_without_their_size_read(tmp_path):
    means, q, scales, opacity, sh = random_splats(50, 1, seed=4)
    streams = spz_streams(means, q, scales, opacity, sh, 1, version=4)
    plain = _read(tmp_path, spz_v4_bytes(streams, 50, 1), "plain.spz")
    records = struct.pack("<II", 0xADBE0002, 12) + struct.pack("<fff", 0.1, 0.9, 2.0)
    ext = _read(tmp_path, spz_v4_bytes(streams, 50, 1, flags=2, extensions=records), "ext.spz")
    unsized = _read(tmp_path, spz_v4_bytes(streams, 50, 1, content_size=False), "unsized.spz")
    for d in (ext, unsized):
        assert np.array_equal(d.positions, plain.positions)
        assert np.array_equal(d.attributes["sh"], plain.attributes["sh"])
    assert ext.metadata["extension_bytes"] == len(records) and "extension_bytes" not in plain.metadata
    trailing = _read(tmp_path, spz_v4_bytes(streams, 50, 1) + b"tail", "tail.spz")
    assert trailing.metadata["trailing_bytes"] == 4


def test_no_points_is_no_streams(tmp_path):
    d = _read(tmp_path, spz_v4_bytes([b""] * 6, 0, 2))
    assert d.num_points == 0 and d.metadata["sh_degree"] == 2


def test_the_committed_synthetic_file_reads(tmp_path):
    d = pointnpr.read(os.path.join(DATA, "synthetic_v4.spz"))
    v3 = pointnpr.read(os.path.join(DATA, "synthetic_v3.spz"))
    assert d.metadata["version"] == "4" and d.num_points == 64
    assert np.array_equal(d.positions, v3.positions) and np.array_equal(d.attributes["sh"], v3.attributes["sh"])


def _good(n=20, degree=1, **kw):
    means, q, scales, opacity, sh = random_splats(n, degree, seed=5)
    return spz_v4_bytes(spz_streams(means, q, scales, opacity, sh, degree, version=4), n, degree, **kw)


def _patched(data, offset, fmt, value):
    b = bytearray(data)
    struct.pack_into(fmt, b, offset, value)
    return bytes(b)


def _toc(data, i):
    return struct.unpack_from("<I", data, 16)[0] + 16 * i


def _stream_start(data, i):
    toc, count = struct.unpack_from("<I", data, 16)[0], data[15]
    return toc + 16 * count + sum(struct.unpack_from("<Q", data, toc + 16 * j)[0] for j in range(i))


def _with_alphas(frame, n=20, degree=1):
    """_good() with its alphas stream's frame replaced (its declared size kept)."""
    means, q, scales, opacity, sh = random_splats(n, degree, seed=5)
    streams = spz_streams(means, q, scales, opacity, sh, degree, version=4)
    packed = [zstd_compress(x) for x in streams]
    packed[1] = frame
    header = struct.pack("<IIIBBBBI12x", 0x5053474E, 4, n, degree, 12, 0, 6, 32)
    toc = b"".join(struct.pack("<QQ", len(p), len(x)) for p, x in zip(packed, streams))
    return header + toc + b"".join(packed)


def _bad_cases():
    good = _good()
    alphas = _stream_start(good, 1)
    return {
        "short header": (good[:20], "32-byte SPZ version 4 header"),
        "version 5": (_patched(good, 4, "<I", 5), "unsupported SPZ version 5"),
        "degree 5": (_patched(good, 12, "<B", 5), "SH degree 5"),
        "fractional bits": (_patched(good, 13, "<B", 30), "fractional bits"),
        "too many points": (_patched(good, 8, "<I", 0xFFFFFFFF), "more than"),
        "reserved bytes": (_patched(good, 28, "<B", 1), "reserved"),
        "stream count": (_patched(good, 15, "<B", 5), "5 attribute streams"),
        "toc inside header": (_patched(good, 16, "<I", 8), "inside the header"),
        "toc past the end": (_patched(good, 16, "<I", len(good) - 8), "runs past the end"),
        "bytes before the toc": (_good(flags=0, extensions=bytes(8)), "without the extensions flag"),
        "declared size": (_patched(good, _toc(good, 1) + 8, "<Q", 21), "declares 21 bytes"),
        "stream past the end": (_patched(good, _toc(good, 5), "<Q", 10 ** 6), "runs past the end"),
        "expansion": (_patched(good, _toc(good, 0), "<Q", 0), "cannot hold"),
        "not zstd": (good[:alphas] + b"\x00" * 4 + good[alphas + 4:], "not zstd data"),
        "corrupt stream": (good[:-3] + bytes(x ^ 0x5A for x in good[-3:]), "corrupt"),
        "larger frame": (_with_alphas(zstd_compress(bytes(21))), "frame holds 21 bytes; 20 expected"),
        "shorter frame": (_with_alphas(zstd_compress(bytes(19), content_size=False)), "decompresses to 19 bytes"),
        "truncated": (good[:-5], "runs past the end"),
    }


@pytest.mark.parametrize("case", list(_bad_cases()))
def test_a_bad_version_4_file_is_a_clear_read_error(tmp_path, case):
    data, words = _bad_cases()[case]
    assert_read_error(tmp_path / "bad.spz", data, words)
