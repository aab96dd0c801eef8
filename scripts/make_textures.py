"""Generates the paper textures and colour look-up tables shipped with the
add-on (python_addon/pointnpr/papers, python_addon/pointnpr/luts). They are
made here, procedurally, so the project owns them; the PNGs are committed
and this script documents (and reproduces) how:

    PYTHONPATH=build /usr/bin/python3 scripts/make_textures.py

Papers are tileable height maps (white = paper peaks): spectral synthesis
of noise (periodic by construction), plus bumps and fibres drawn with
wrap-around. LUTs are Hald CLUTs of level 8 (512x512, 64 entries per axis).
"""
import os
import sys

import numpy as np

import pointnpr

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python_addon", "pointnpr")
SIZE = 512


def spectral_noise(rng, beta, low, high):
    """Tileable noise with power spectrum 1/f^beta between `low` and `high`
    cycles per image, normalised to zero mean and unit deviation."""
    white = rng.standard_normal((SIZE, SIZE))
    fy = np.fft.fftfreq(SIZE)[:, None] * SIZE
    fx = np.fft.rfftfreq(SIZE)[None, :] * SIZE
    f = np.sqrt(fx * fx + fy * fy)
    gain = np.where((f >= low) & (f <= high), np.power(np.maximum(f, 1.0), -beta / 2.0), 0.0)
    out = np.fft.irfft2(np.fft.rfft2(white) * gain, s=(SIZE, SIZE))
    return (out - out.mean()) / (out.std() + 1e-12)


def bumps(rng, count, radius):
    """Tileable field of Gaussian bumps of about `radius` px (cold-press tooth)."""
    impulses = np.zeros((SIZE, SIZE))
    ys, xs = rng.integers(0, SIZE, count), rng.integers(0, SIZE, count)
    np.add.at(impulses, (ys, xs), rng.uniform(0.5, 1.0, count))
    fy = np.fft.fftfreq(SIZE)[:, None]
    fx = np.fft.rfftfreq(SIZE)[None, :]
    kernel = np.exp(-2.0 * (np.pi * radius) ** 2 * (fx * fx + fy * fy))
    out = np.fft.irfft2(np.fft.rfft2(impulses) * kernel, s=(SIZE, SIZE))
    return (out - out.mean()) / (out.std() + 1e-12)


def fibres(rng, count, length):
    """Thin slightly curved fibres, drawn with wrap-around."""
    out = np.zeros((SIZE, SIZE))
    for _ in range(count):
        x, y = rng.uniform(0, SIZE, 2)
        angle = rng.uniform(0, np.pi)
        bend = rng.normal(0, 0.02)
        for step in range(int(rng.uniform(0.5, 1.0) * length)):
            angle += bend
            x, y = x + np.cos(angle), y + np.sin(angle)
            out[int(y) % SIZE, int(x) % SIZE] += 1.0
    return out


def normalise(h):
    lo, hi = np.percentile(h, 0.5), np.percentile(h, 99.5)
    return np.clip((h - lo) / (hi - lo), 0.0, 1.0)


def papers():
    rng = np.random.default_rng(20261122)
    cold = 0.55 * spectral_noise(rng, 1.2, 8, 160) + 0.7 * bumps(rng, 9000, 2.2) + 0.25 * fibres(rng, 300, 40)
    rough = 0.5 * spectral_noise(rng, 1.0, 4, 96) + 1.0 * bumps(rng, 3500, 4.0) + 0.2 * fibres(rng, 200, 60)
    hot = 0.8 * spectral_noise(rng, 0.6, 24, 256) + 0.1 * fibres(rng, 500, 30)
    hot = 0.5 + 0.35 * (normalise(hot) - 0.5)  # hot-pressed paper is smooth: less relief
    return {"cold_press": normalise(cold), "rough": normalise(rough), "hot_press": hot}


def hald(level, transform):
    """A Hald CLUT image (top row first) of `transform` on display sRGB."""
    n = level * level
    i = np.arange(n ** 3)
    rgb = np.stack([i % n, (i // n) % n, i // (n * n)], axis=1) / (n - 1.0)
    out = np.clip(transform(rgb), 0.0, 1.0)
    return out.reshape(level ** 3, level ** 3, 3)


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722])


def warm_film(rgb):
    """Lifted blacks, warm highlights, slightly muted: a soft print look."""
    s = 0.85 * rgb + 0.15 * luminance(rgb)[:, None]
    s = 0.04 + 0.94 * s
    return s * np.array([1.06, 1.0, 0.88]) + np.array([0.0, 0.0, 0.03]) * (1 - s)


def cool_night(rgb):
    """Darker, blue shadows, desaturated: a night map look."""
    lum = luminance(rgb)[:, None]
    s = 0.6 * rgb + 0.4 * lum
    return np.power(s, 1.25) * np.array([0.85, 0.95, 1.15])


def main():
    for name, height in papers().items():
        path = os.path.join(ROOT, "papers", name + ".png")
        pointnpr.save_image(path, np.ascontiguousarray(height[::-1].astype(np.float32)), srgb=False)
        print(path)
    for name, transform in {"identity": lambda c: c, "warm_film": warm_film, "cool_night": cool_night}.items():
        path = os.path.join(ROOT, "luts", name + ".png")
        pointnpr.save_image(path, np.ascontiguousarray(hald(8, transform)[::-1].astype(np.float32)), srgb=False)
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
