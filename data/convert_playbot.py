"""Makes tests/data/io/gaussians/playbot_lod3.spz, the real splat capture
the tests render, from PLAYBOT (Stephane Agullo, https://sa3d.fr,
https://superspl.at/view?id=ee6d8bc4, CC-BY-4.0) as the PlayCanvas engine's
examples ship it: level of detail 3 (31,000 splats, SH degree 2) of its SOG
files (examples/assets/splats/playbot/3_0 of github.com/playcanvas/engine).

SOG version 2 is decoded from its published specification (PlayCanvas
developer site, "The SOG Format"): positions as 16-bit log-domain values,
scales and SH through 256-entry codebooks (logs of standard deviations, SH
coefficients), opacity as alpha / 255, quaternions as 8-bit smallest-three,
the AC SH bands through a palette of centroids. SOG's axes are right-up-back
like SPZ's, so the splats are written to SPZ version 3 unchanged in axis
(tests/python/gaussian_reference.write_spz takes the PLY's right-down-front
axes and negates y and z, so they are negated here first).

    PYTHONPATH=build:tests/python python3 data/convert_playbot.py SOG_DIR OUT.spz
"""
import json
import os
import sys

import numpy as np

import pointnpr
from gaussian_reference import write_spz


def image(folder, name):
    # load_image gives float [0, 1], bottom row first; SOG indexes from the top.
    return np.rint(pointnpr.load_image(os.path.join(folder, name))[::-1] * 255.0).astype(np.int64)


def main(folder, out):
    meta = json.load(open(os.path.join(folder, "meta.json")))
    assert meta["version"] == 2
    n = meta["count"]
    lo, up = (image(folder, f).reshape(-1, image(folder, f).shape[-1]) for f in meta["means"]["files"])
    q16 = (up[:n, :3] << 8) | lo[:n, :3]
    mins, maxs = np.array(meta["means"]["mins"]), np.array(meta["means"]["maxs"])
    logp = mins + (maxs - mins) * q16 / 65535.0
    pos = np.sign(logp) * (np.exp(np.abs(logp)) - 1.0)
    scales = np.exp(np.array(meta["scales"]["codebook"])[image(folder, meta["scales"]["files"][0]).reshape(-1, 4)[:n, :3]])
    quat = image(folder, meta["quats"]["files"][0]).reshape(-1, 4)[:n]
    abc = (quat[:, :3] / 255.0 - 0.5) * 2.0 / np.sqrt(2.0)
    d = np.sqrt(np.maximum(0.0, 1.0 - (abc ** 2).sum(1)))
    mode = quat[:, 3] - 252
    assert ((mode >= 0) & (mode <= 3)).all()
    xyzw = np.zeros((n, 4))
    for m in range(4):
        rows = mode == m
        kept = [k for k in range(4) if k != m]
        xyzw[rows, m] = d[rows]
        xyzw[np.ix_(rows, kept)] = abc[rows]
    wxyz = xyzw[:, [3, 0, 1, 2]]
    sh0 = image(folder, meta["sh0"]["files"][0]).reshape(-1, 4)[:n]
    dc = np.array(meta["sh0"]["codebook"])[sh0[:, :3]]
    opacity = sh0[:, 3] / 255.0
    bands = meta["shN"]["bands"]
    coeffs = (bands + 1) ** 2 - 1
    cent = image(folder, meta["shN"]["files"][0])
    labels = image(folder, meta["shN"]["files"][1]).reshape(-1, 4)[:n]
    index = labels[:, 0] + (labels[:, 1] << 8)
    book = np.array(meta["shN"]["codebook"])
    sh = np.zeros((n, coeffs + 1, 3))
    sh[:, 0] = dc
    for c in range(coeffs):
        u = (index % 64) * coeffs + c
        v = index // 64
        sh[:, c + 1] = book[cent[v, u, :3]]
    # To the PLY's axes (the writer turns them back to SPZ's).
    flip = np.array([1.0, -1.0, -1.0])
    odd = [False, True, True, False, True, False, False, True, False]
    sh[:, [k for k in range(coeffs + 1) if odd[k]]] *= -1.0
    wxyz[:, 2:] *= -1.0
    write_spz(out, pos * flip, wxyz, scales, opacity, sh, bands, version=3)
    print(out, n, "splats, SH degree", bands, os.path.getsize(out), "bytes")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
