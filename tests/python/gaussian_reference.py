"""An independent reference for the gaussians mark: the 3DGS forward pass
(Kerbl et al. 2023, sections 4 and 6, and the reference CUDA rasterizer's
rules) written plainly in numpy, float64, Gaussian after Gaussian over the
whole image rather than in tiles, from a pinhole camera's focal lengths
rather than a projection matrix.

Also the synthetic splats and the SPZ writer the tests use (written from
the format's description, the inverse of what the reader does)."""
import gzip
import struct
import subprocess

import numpy as np

SH_C0 = 0.28209479177387814
SH_C1 = 0.4886025119029199
SH_C2 = (1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792, 0.5462742152960396)
SH_C3 = (-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154, -0.4570457994644658,
         1.445305721320277, -0.5900435899266435)


def perspective(fx_ndc, fy_ndc, near, far):
    """A symmetric OpenGL projection (P00, P11 the NDC focal lengths)."""
    p = np.zeros((4, 4))
    p[0, 0], p[1, 1] = fx_ndc, fy_ndc
    p[2, 2], p[2, 3] = -(far + near) / (far - near), -2.0 * far * near / (far - near)
    p[3, 2] = -1.0
    return p


def view_matrix(eye, target, up=(0.0, 0.0, 1.0)):
    eye, target, up = (np.asarray(v, float) for v in (eye, target, up))
    f = target - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    v = np.eye(4)
    v[0, :3], v[1, :3], v[2, :3] = s, u, -f
    v[:3, 3] = -v[:3, :3] @ eye
    return v


def quat_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def sh_color(sh, degree, d):
    """sh: (K, 3) coefficients; d: unit direction camera -> splat."""
    x, y, z = d
    c = SH_C0 * sh[0]
    if degree > 0:
        c = c - SH_C1 * y * sh[1] + SH_C1 * z * sh[2] - SH_C1 * x * sh[3]
    if degree > 1:
        xx, yy, zz = x * x, y * y, z * z
        c = (c + SH_C2[0] * x * y * sh[4] + SH_C2[1] * y * z * sh[5] + SH_C2[2] * (2 * zz - xx - yy) * sh[6]
             + SH_C2[3] * x * z * sh[7] + SH_C2[4] * (xx - yy) * sh[8])
    if degree > 2:
        c = (c + SH_C3[0] * y * (3 * xx - yy) * sh[9] + SH_C3[1] * x * y * z * sh[10]
             + SH_C3[2] * y * (4 * zz - xx - yy) * sh[11] + SH_C3[3] * z * (2 * zz - 3 * xx - 3 * yy) * sh[12]
             + SH_C3[4] * x * (4 * zz - xx - yy) * sh[13] + SH_C3[5] * z * (xx - yy) * sh[14]
             + SH_C3[6] * x * (xx - 3 * yy) * sh[15])
    return np.maximum(c + 0.5, 0.0)


def project(mean, q, scale, view, fx, fy, cx, cy, width, height):
    """(centre px, 2D covariance incl. the 0.3 px dilation, view depth) or None."""
    t = view[:3, :3] @ mean + view[:3, 3]
    depth = -t[2]
    rs = quat_matrix(q) @ np.diag(scale)
    cov3 = view[:3, :3] @ rs @ rs.T @ view[:3, :3].T
    # Image coordinates u = fx * t.x / depth + cx (y up, rows bottom first).
    lim_x, lim_y = 1.3 * cx / fx, 1.3 * cy / fy
    tx = np.clip(t[0] / depth, -lim_x, lim_x) * depth
    ty = np.clip(t[1] / depth, -lim_y, lim_y) * depth
    jac = np.array([[fx / depth, 0.0, fx * tx / depth ** 2], [0.0, fy / depth, fy * ty / depth ** 2]])
    cov2 = jac @ cov3 @ jac.T + 0.3 * np.eye(2)
    center = np.array([fx * t[0] / depth + cx, fy * t[1] / depth + cy])
    return center, cov2, depth


def render(means, quats, scales, opacity, sh, degree, view, proj, width, height, near=0.1, far=100.0):
    """Premultiplied display-sRGB colour (H, W, 3), opacity (H, W): the
    Gaussians in depth order, each over its 3-sigma square, composited front
    to back with the reference rasterizer's rules."""
    fx, fy = 0.5 * width * proj[0, 0], 0.5 * height * proj[1, 1]
    cx, cy = 0.5 * width, 0.5 * height
    cam = -view[:3, :3].T @ view[:3, 3]
    projected = []
    for i in range(len(means)):
        center, cov2, depth = project(means[i], quats[i], scales[i], view, fx, fy, cx, cy, width, height)
        if not near <= depth <= far or np.linalg.det(cov2) <= 0:
            continue
        projected.append((depth, i, center, cov2))
    projected.sort(key=lambda e: (e[0], e[1]))
    color = np.zeros((height, width, 3))
    T = np.ones((height, width))
    done = np.zeros((height, width), bool)
    ys, xs = np.mgrid[0:height, 0:width] + 0.5
    for depth, i, center, cov2 in projected:
        a, b, c = cov2[0, 0], cov2[0, 1], cov2[1, 1]
        mid = 0.5 * (a + c)
        lam = mid + np.sqrt(max(0.1, mid * mid - (a * c - b * b)))
        r = np.ceil(3.0 * np.sqrt(lam))
        x0, x1 = int(max(np.floor(center[0] - r), 0)), int(min(np.ceil(center[0] + r), width - 1))
        y0, y1 = int(max(np.floor(center[1] - r), 0)), int(min(np.ceil(center[1] + r), height - 1))
        if x1 < x0 or y1 < y0:
            continue
        conic = np.linalg.inv(cov2)
        dx = xs[y0:y1 + 1, x0:x1 + 1] - center[0]
        dy = ys[y0:y1 + 1, x0:x1 + 1] - center[1]
        power = -0.5 * (conic[0, 0] * dx * dx + conic[1, 1] * dy * dy) - conic[0, 1] * dx * dy
        alpha = np.minimum(0.99, opacity[i] * np.exp(power))
        use = (power <= 0) & (alpha >= 1.0 / 255.0) & ~done[y0:y1 + 1, x0:x1 + 1]
        Tw = T[y0:y1 + 1, x0:x1 + 1]
        test = Tw * (1.0 - alpha)
        finish = use & (test < 1e-4)
        done[y0:y1 + 1, x0:x1 + 1] |= finish
        use &= ~finish
        d = means[i] - cam
        rgb = sh_color(sh[i], degree, d / np.linalg.norm(d))
        color[y0:y1 + 1, x0:x1 + 1] += np.where(use[..., None], (alpha * Tw)[..., None] * rgb, 0.0)
        T[y0:y1 + 1, x0:x1 + 1] = np.where(use, test, Tw)
    return color, 1.0 - T


def srgb_from_linear(c):
    c = np.clip(c, 0.0, None)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def premultiplied_srgb(result_color):
    """A RenderResult's premultiplied scene-linear colour back to what the
    mark blended: premultiplied display sRGB (H, W, 3), and opacity."""
    c = np.asarray(result_color, np.float64)
    a = c[..., 3]
    straight = np.where(a[..., None] > 0, c[..., :3] / np.maximum(a, 1e-30)[..., None], 0.0)
    return srgb_from_linear(straight) * a[..., None], a


def psnr(a, b):
    mse = np.mean((np.clip(a, 0, 1) - np.clip(b, 0, 1)) ** 2)
    return float("inf") if mse == 0 else 10.0 * np.log10(1.0 / mse)


def random_splats(n, degree, seed=1, extent=1.0, scale=(0.01, 0.08)):
    rng = np.random.default_rng(seed)
    means = rng.uniform(-extent, extent, (n, 3))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    scales = np.exp(rng.uniform(np.log(scale[0]), np.log(scale[1]), (n, 3)))
    opacity = rng.uniform(0.2, 1.0, n)
    K = (degree + 1) ** 2
    sh = rng.normal(0.0, 0.3, (n, K, 3))
    sh[:, 0] = rng.uniform(-1.5, 1.5, (n, 3))
    return means, q, scales, opacity, sh


def spz_streams(means, quats, scales, opacity, sh, degree, version=3, fractional_bits=12):
    """The six attribute byte strings of an SPZ file of these splats (given
    in the PLY's right-down-front axes; SPZ stores right-up-back, so y and z
    are negated), from the format's description: positions, alphas,
    colours, scales, rotations, SH."""
    flip = np.array([1.0, -1.0, -1.0])
    odd = [False, True, True, False, True, False, False, True, False, True, False, True, True, False, True, False]
    fixed = np.round(means * flip * (1 << fractional_bits)).astype(np.int64)
    positions = b"".join(int(v & 0xFFFFFF).to_bytes(3, "little") for v in fixed.ravel())
    alphas = bytes(np.clip(np.round(opacity * 255.0), 0, 255).astype(np.uint8))
    colors = bytes(np.clip(np.round(sh[:, 0] * (0.15 * 255.0) + 127.5), 0, 255).astype(np.uint8).ravel())
    scale_bytes = bytes(np.clip(np.round((np.log(scales) + 10.0) * 16.0), 0, 255).astype(np.uint8).ravel())
    rotations = bytearray()
    for w, x, y, z in quats:
        q = np.array([x, -y, -z, w])  # SPZ's order x, y, z, w, in its axes
        q /= np.linalg.norm(q)
        if version >= 3:
            largest = int(np.argmax(np.abs(q)))
            if q[largest] < 0:
                q = -q
            word = largest
            for k in range(4):
                if k != largest:
                    mag = int(511 * abs(q[k]) / np.sqrt(0.5) + 0.5)
                    word = (word << 10) | (int(q[k] < 0) << 9) | mag
            rotations += struct.pack("<I", word)
        else:
            if q[3] < 0:
                q = -q
            rotations += bytes(np.clip(np.round(q[:3] * 127.5 + 127.5), 0, 255).astype(np.uint8))
    K = (degree + 1) ** 2
    bands = bytearray()
    for i in range(len(means)):
        for k in range(1, K):
            v = -sh[i, k] if k < 16 and odd[k] else sh[i, k]  # (degree 4: read past, written unturned)
            bands += bytes(np.clip(np.round(v * 128.0 + 128.0), 0, 255).astype(np.uint8))
    return [positions, alphas, colors, scale_bytes, bytes(rotations), bytes(bands)]


def zstd_compress(data, content_size=True):
    """One zstd frame of ``data`` by the zstd tool (Debian's zstd package);
    ``content_size`` False leaves the frame's size out, as streaming writers do."""
    args = ["zstd", "-q", "-c", "-3"] + (["--stream-size=%d" % len(data)] if content_size and data else [])
    return subprocess.run(args, input=data, capture_output=True, check=True).stdout


def spz_v4_bytes(streams, n, degree, fractional_bits=12, flags=0, extensions=b"", content_size=True):
    """A version 4 SPZ file of the attribute streams: the 32-byte NGSP
    header, ``extensions`` (flag 0x2's records), the table of contents and
    each non-empty stream as its own zstd frame."""
    present = [s for s in streams if s]
    packed = [zstd_compress(s, content_size) for s in present]
    toc_offset = 32 + len(extensions)
    header = struct.pack("<IIIBBBBI12x", 0x5053474E, 4, n, degree, fractional_bits, flags, len(present), toc_offset)
    toc = b"".join(struct.pack("<QQ", len(p), len(s)) for p, s in zip(packed, present))
    return header + extensions + toc + b"".join(packed)


def write_spz(path, means, quats, scales, opacity, sh, degree, version=3, fractional_bits=12, flags=0):
    """An SPZ file of these splats: versions 2 and 3 one gzip stream,
    version 4 the NGSP container of zstd streams."""
    n = len(means)
    streams = spz_streams(means, quats, scales, opacity, sh, degree, version, fractional_bits)
    if version >= 4:
        data = spz_v4_bytes(streams, n, degree, fractional_bits, flags)
    else:
        header = struct.pack("<IIIBBBB", 0x5053474E, version, n, degree, fractional_bits, flags, 0)
        data = gzip.compress(header + b"".join(streams), mtime=0)
    with open(path, "wb") as f:
        f.write(data)


def write_3dgs_ply(path, means, quats, scales, opacity, sh, degree):
    """A binary 3DGS PLY (the reference implementation's layout)."""
    n = len(means)
    K = (degree + 1) ** 2
    rest = 3 * (K - 1)
    names = (["x", "y", "z", "nx", "ny", "nz", "f_dc_0", "f_dc_1", "f_dc_2"] + [f"f_rest_{j}" for j in range(rest)]
             + ["opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"])
    cols = [means[:, 0], means[:, 1], means[:, 2], np.zeros(n), np.zeros(n), np.zeros(n),
            sh[:, 0, 0], sh[:, 0, 1], sh[:, 0, 2]]
    for j in range(rest):  # channel-major: f_rest_j = channel j // (K-1), coefficient j % (K-1) + 1
        cols.append(sh[:, j % (K - 1) + 1, j // (K - 1)])
    logit = np.log(opacity / (1.0 - opacity))
    cols += [logit, np.log(scales[:, 0]), np.log(scales[:, 1]), np.log(scales[:, 2])]
    cols += [quats[:, 0], quats[:, 1], quats[:, 2], quats[:, 3]]
    data = np.column_stack(cols).astype("<f4")
    header = "ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % n
    header += "".join(f"property float {name}\n" for name in names) + "end_header\n"
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(data.tobytes())


def assert_read_error(path, data, words):
    """Reading `data` written at `path` raises a ReadError that names the
    file and says `words`."""
    import pytest
    import pointnpr
    path.write_bytes(data)
    with pytest.raises(pointnpr.ReadError) as e:
        pointnpr.read(str(path))
    assert words in str(e.value), str(e.value)
    assert e.value.file == str(path)
