"""Makes a small valid LAS from a big one: keeps the header and the chosen
VLRs, every k-th point (up to M), and recomputes counts and bounds."""
import struct, sys
src, dst, M = sys.argv[1], sys.argv[2], int(sys.argv[3])
keep_users = sys.argv[4].split(',') if len(sys.argv) > 4 else None
d = bytearray(open(src, 'rb').read())
hs, = struct.unpack_from('<H', d, 94); off, = struct.unpack_from('<I', d, 96); nv, = struct.unpack_from('<I', d, 100)
pf = d[104]; rl, = struct.unpack_from('<H', d, 105); leg, = struct.unpack_from('<I', d, 107)
vminor = d[25]
n = struct.unpack_from('<Q', d, 247)[0] if vminor >= 4 and struct.unpack_from('<Q', d, 247)[0] else leg
vlrs = []; pos = hs
for i in range(nv):
    user = bytes(d[pos+2:pos+18]).rstrip(b'\0').decode('latin1'); ln, = struct.unpack_from('<H', d, pos+20)
    if keep_users is None or user in keep_users: vlrs.append(bytes(d[pos:pos+54+ln]))
    pos += 54 + ln
k = max(1, n // M)
idx = list(range(0, n, k))[:M]
pts = b''.join(bytes(d[off+i*rl: off+(i+1)*rl]) for i in idx)
head = bytearray(d[:hs])
newoff = hs + sum(len(v) for v in vlrs)
struct.pack_into('<I', head, 96, newoff); struct.pack_into('<I', head, 100, len(vlrs))
cnt = len(idx)
ext = pf >= 6
struct.pack_into('<I', head, 107, 0 if (ext and vminor >= 4) else cnt)
byret = [0]*15
sc = struct.unpack_from('<3d', d, 131); of = struct.unpack_from('<3d', d, 155)
mins = [1e300]*3; maxs = [-1e300]*3
for j in range(cnt):
    r = pts[j*rl:(j+1)*rl]
    xyz = struct.unpack_from('<3i', r, 0)
    for c in range(3):
        v = xyz[c]*sc[c]+of[c]; mins[c] = min(mins[c], v); maxs[c] = max(maxs[c], v)
    rn = (r[14] & 15) if ext else (r[14] & 7)
    if 1 <= rn <= 15: byret[rn-1] += 1
for i in range(5): struct.pack_into('<I', head, 111+4*i, 0 if (ext and vminor >= 4) else byret[i])
struct.pack_into('<6d', head, 179, maxs[0], mins[0], maxs[1], mins[1], maxs[2], mins[2])
if vminor >= 4:
    struct.pack_into('<QI', head, 235, 0, 0)
    struct.pack_into('<Q', head, 247, cnt)
    for i in range(15): struct.pack_into('<Q', head, 255+8*i, byret[i])
open(dst, 'wb').write(bytes(head) + b''.join(vlrs) + pts)
print(dst, cnt, 'points, k =', k)
