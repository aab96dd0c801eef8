"""Noisy synthetic shapes with their true normals, and the angular error of
estimated normals: shared by bench/bench_geometry.py and bench/speed_vs_error.py."""
import numpy as np


def angles(n, truth):
    n = np.asarray(n, np.float64)
    cos = np.abs(np.sum(n * truth, axis=1)) / np.maximum(np.linalg.norm(n, axis=1), 1e-300)
    return np.degrees(np.arccos(np.clip(cos, 0.0, 1.0)))


def shapes(n, rng):
    """Noisy shapes of unit size, Gaussian noise along the normal of 0.05% of the size."""
    out = {}
    noise = 0.0005
    # Plane, tilted.
    nrm = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    t1 = np.cross(nrm, [1.0, 0, 0]); t1 /= np.linalg.norm(t1)
    t2 = np.cross(nrm, t1)
    uv = rng.uniform(-1, 1, (n, 2))
    out["plane"] = (uv[:, :1] * t1 + uv[:, 1:] * t2 + noise * rng.normal(size=(n, 1)) * nrm, np.tile(nrm, (n, 1)))
    # Sphere.
    d = rng.normal(size=(n, 3)); d /= np.linalg.norm(d, axis=1, keepdims=True)
    out["sphere"] = (d * (1 + noise * rng.normal(size=(n, 1))), d)
    # Cylinder.
    a = rng.uniform(0, 2 * np.pi, n)
    d = np.column_stack([np.cos(a), np.sin(a), np.zeros(n)])
    out["cylinder"] = (d * (1 + noise * rng.normal(size=(n, 1))) + np.outer(rng.uniform(-2, 2, n), [0, 0, 1]), d)
    # Sharp edge: two faces of a box.
    u = rng.uniform(0, 1, (n, 2))
    half = n // 2
    p = np.zeros((n, 3)); t = np.zeros((n, 3))
    p[:half] = np.column_stack([u[:half, 0], 2 * u[:half, 1] - 1, noise * rng.normal(size=half)]); t[:half] = [0, 0, 1]
    p[half:] = np.column_stack([noise * rng.normal(size=n - half), 2 * u[half:, 1] - 1, u[half:, 0]]); t[half:] = [1, 0, 0]
    out["edge"] = (p, t)
    return out
