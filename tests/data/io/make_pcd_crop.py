"""Crops an organized binary_compressed PCD (e.g. PCL's
table_scene_mug_stereo_textured.pcd) to a small window, keeping it organized
and LZF-compressed (field-major), so tests exercise NaN dropping and real
LZF back-references. Usage: make_pcd_crop.py in.pcd out.pcd row0 col0 rows cols"""
import struct
import sys

import numpy as np


def lzf_decompress(src, out_len):
    out = bytearray()
    i = 0
    while i < len(src):
        ctrl = src[i]; i += 1
        if ctrl < 32:
            out += src[i:i + ctrl + 1]; i += ctrl + 1
        else:
            ln = ctrl >> 5
            if ln == 7:
                ln += src[i]; i += 1
            ref = len(out) - ((ctrl & 0x1f) << 8) - src[i] - 1; i += 1
            for k in range(ln + 2):
                out.append(out[ref + k])
    assert len(out) == out_len
    return bytes(out)


def lzf_compress(src):
    """Greedy LZF compressor (format-compatible with liblzf)."""
    out = bytearray()
    lit = bytearray()
    table = {}
    i, n = 0, len(src)

    def flush():
        nonlocal lit
        while lit:
            chunk = lit[:32]
            out.append(len(chunk) - 1); out.extend(chunk)
            lit = lit[32:]

    while i < n:
        if i + 2 < n:
            key = src[i:i + 3]
            cand = table.get(key)
            table[key] = i
            if cand is not None and i - cand - 1 < 8192:
                ln = 3
                maxlen = min(264, n - i)
                while ln < maxlen and src[cand + ln] == src[i + ln]:
                    ln += 1
                flush()
                off = i - cand - 1
                l2 = ln - 2
                if l2 < 7:
                    out.append((l2 << 5) | (off >> 8))
                else:
                    out.append((7 << 5) | (off >> 8)); out.append(l2 - 7)
                out.append(off & 0xff)
                for k in range(i + 1, min(i + ln, n - 2)):
                    table[src[k:k + 3]] = k
                i += ln
                continue
        lit.append(src[i]); i += 1
    flush()
    return bytes(out)


def main():
    src, dst = sys.argv[1], sys.argv[2]
    r0, c0, rows, cols = map(int, sys.argv[3:7])
    raw = open(src, "rb").read()
    hdr_end = raw.index(b"DATA binary_compressed\n") + len(b"DATA binary_compressed\n")
    header = raw[:hdr_end].decode()
    fields = dict(l.split(" ", 1) for l in header.splitlines() if l and not l.startswith("#"))
    w, h = int(fields["WIDTH"]), int(fields["HEIGHT"])
    sizes = [int(s) for s in fields["SIZE"].split()]
    csize, usize = struct.unpack_from("<II", raw, hdr_end)
    data = lzf_decompress(raw[hdr_end + 8:hdr_end + 8 + csize], usize)
    parts, off = [], 0
    for s in sizes:
        a = np.frombuffer(data, np.uint8, count=w * h * s, offset=off).reshape(h, w, s)
        parts.append(a[r0:r0 + rows, c0:c0 + cols].tobytes())
        off += w * h * s
    body = b"".join(parts)
    comp = lzf_compress(body)
    assert lzf_decompress(comp, len(body)) == body
    header = header.replace("WIDTH %d\n" % w, "WIDTH %d\n" % cols).replace("HEIGHT %d\n" % h, "HEIGHT %d\n" % rows)
    header = header.replace("POINTS %d\n" % (w * h), "POINTS %d\n" % (rows * cols))
    open(dst, "wb").write(header.encode() + struct.pack("<II", len(comp), len(body)) + comp)
    print(dst, rows * cols, "points,", len(comp), "compressed bytes of", len(body))


if __name__ == "__main__":
    main()
