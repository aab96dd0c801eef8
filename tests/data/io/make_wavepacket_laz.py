"""Writes laz/lazrs_wavepacket5.laz and its uncompressed twin wavepacket5.las:
the 3,000 points of warsaw_small.las as LAS 1.3 point format 5 (GPS time,
RGB, wave packets) with two extra bytes, and seeded wave packet descriptors
that take every way LASzip codes a waveform's offset (the last packet's,
right after it, a 32-bit difference, raw 64 bits). No real LAZ of formats
4/5 was at hand; the points are real, the packets made up. LAZ written by
lazrs through laspy (the test oracles), so the decoder is checked against
another implementation's encoder.

    .venv-test/bin/python tests/data/io/make_wavepacket_laz.py
"""
import pathlib

import laspy
import numpy as np

HERE = pathlib.Path(__file__).resolve().parent


def add_wave_packets(las, rng):
    """Seeded wave packet descriptors for every point of ``las`` (format 4,
    5, 9 or 10): each waveform offset the last packet's, right after it, a
    32-bit difference or raw; arbitrary float fields. Returns the offsets."""
    n = len(las.points)
    size = rng.choice([128, 256, 512], n).astype(np.uint32)
    how = rng.integers(0, 4, n)
    offset = np.zeros(n, np.uint64)
    for i in range(1, n):
        prev = int(offset[i - 1])
        offset[i] = [prev, prev + int(size[i - 1]), (prev + int(rng.integers(-5000, 5000))) % 2**40,
                     int(rng.integers(0, 2**62))][how[i]]
    las.wavepacket_index = rng.integers(0, 255, n)
    las.wavepacket_offset = offset
    las.wavepacket_size = size
    las.return_point_wave_location = rng.normal(0, 1000, n).astype(np.float32)
    for axis in ("x_t", "y_t", "z_t"):
        las[axis] = rng.normal(0, 1e-3, n).astype(np.float32)
    return offset


def main():
    src = laspy.read(str(HERE / "warsaw_small.las"))
    n = len(src.points)
    rng = np.random.default_rng(2026)
    header = laspy.LasHeader(point_format=5, version="1.3")
    header.scales, header.offsets = src.header.scales, src.header.offsets
    header.add_extra_dim(laspy.ExtraBytesParams(name="tag", type=np.uint16))
    las = laspy.LasData(header)
    las.X, las.Y, las.Z = src.X, src.Y, src.Z
    las.intensity, las.classification = src.intensity, src.classification
    las.return_number, las.number_of_returns = src.return_number, src.number_of_returns
    las.gps_time = np.cumsum(rng.exponential(1e-5, n)) + 3e8
    las.red, las.green, las.blue = (rng.integers(0, 65535, n) for _ in range(3))
    add_wave_packets(las, rng)
    las.tag = rng.integers(0, 65535, n)
    las.write(str(HERE / "laz" / "lazrs_wavepacket5.laz"), laz_backend=laspy.LazBackend.Lazrs)
    las.write(str(HERE / "wavepacket5.las"))


if __name__ == "__main__":
    main()
