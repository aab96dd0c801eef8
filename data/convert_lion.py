"""Provenance of data/lion_takanawa.ply (run once by hand, not at run time):
converts ../shared/data/scans/lion_takanawa.las (342k points, 14 MB LAS 1.4)
to a 5 MB binary PLY (float32 x y z, uint8 red green blue): the coordinates
are small local metres, so float32 loses nothing that matters.

    PYTHONPATH=build python3 data/convert_lion.py ../shared/data/scans/lion_takanawa.las data/lion_takanawa.ply
"""
import sys

import numpy as np

import pointnpr

src, dst = sys.argv[1], sys.argv[2]
data = pointnpr.read(src)
n = data.num_points
rec = np.zeros(n, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("red", "u1"), ("green", "u1"), ("blue", "u1")])
for i, axis in enumerate("xyz"):
    rec[axis] = data.positions[:, i]
for i, channel in enumerate(("red", "green", "blue")):
    rec[channel] = data.attributes["colors"][:, i]
header = (
    "ply\nformat binary_little_endian 1.0\n"
    "comment lion_takanawa from potree/potree pointclouds (BSD-2 repository, data provenance unstated)\n"
    f"element vertex {n}\nproperty float x\nproperty float y\nproperty float z\n"
    "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
)
with open(dst, "wb") as f:
    f.write(header.encode("ascii"))
    f.write(rec.tobytes())
print(f"wrote {n} points to {dst}")
