// SPZ reader (Niantic's compressed 3D Gaussian splats, versions 2, 3 and 4).
//
// Written from the format's published description (the spz repository's
// README). Versions 2 and 3 are one gzip stream holding a 16-byte
// little-endian header (magic 0x5053474e "NGSP", version, number of points,
// SH degree, fractional bits, flags, reserved) and then, attribute after
// attribute: positions (3 x 24-bit signed fixed point per point,
// 2^-fractionalBits units), alphas (8 bits: the sigmoid of the opacity),
// colours (8 bits a channel: 0.5 + 0.15 * SH DC), scales (8 bits:
// (ln s + 10) * 16), rotations (version 2: x, y, z as 8 bits each,
// (b / 127.5) - 1, w >= 0 derived; version 3 and 4: "smallest three": a
// 32-bit word holding the index of the largest component in its top 2 bits
// and the other three, last first, as a sign bit and 9 bits of magnitude
// scaled by 1/sqrt(2)), then the SH bands (8 bits: (b - 128) / 128,
// coefficient-major, r g b inner).
// Version 4 is not compressed as a whole: a 32-byte plaintext header (magic,
// version, points, SH degree, fractional bits, flags, number of streams, the
// table of contents' offset, 12 reserved zero bytes), extension records up
// to that offset (flag 0x2; skipped: they carry no splat data), the table
// (per stream its compressed and decompressed size, u64 each), then each
// attribute above as its own zstd data, in the same order, the empty ones
// (SH of degree 0; every one of 0 points) left out.
// SPZ stores right-up-back (OpenGL) axes; 3DGS PLY files are right-down-
// front (COLMAP), so the reader turns SPZ into the PLY's axes (a half turn
// about x: y and z negated, in positions, quaternions and the SH bands
// odd in y and z), and the two formats of one capture coincide.
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/gaussians.h"
#include "io/mapped_file.h"
#include "io/readers.h"

namespace pointnpr {
namespace {

constexpr uint32_t kMagic = 0x5053474e;
constexpr uint32_t kMaxPoints = 100'000'000;
constexpr int kMaxDegree = 3;  // degree 4 bands are read past, not kept

// SH coefficients 1..15 (3DGS order) that change sign when y and z do.
constexpr bool kOddInYZ[16] = {false, true, true, false, true, false, false, true, false,
                               true,  false, true, true, false, true, false};

int dim_for_degree(int d) { return (d + 1) * (d + 1) - 1; }

class SpzReader : private io::ReaderBase {
 public:
  using ReaderBase::ReaderBase;
  PointData read();

 private:
  // What both containers say of the points, and where each attribute's bytes are.
  struct Header {
    uint32_t version = 0, n = 0;
    int degree = 0, fractional = 0, flags = 0;
  };
  struct Attributes {
    const uint8_t *pos = nullptr, *alpha = nullptr, *color = nullptr, *scale = nullptr, *rot = nullptr,
                  *sh = nullptr;
  };
  PointData read_gzip();
  PointData read_v4();
  void check(const Header& h) const;
  static size_t stream_bytes(const Header& h, int stream);  // positions, alphas, colours, scales, rotations, SH
  PointData decode(const Header& h, const Attributes& a) const;

  bool inflate_more(size_t want);
  size_t drain();  // inflates the rest of the stream (checking its CRC); how many bytes it held

  z_stream z_{};
  bool z_open_ = false, z_end_ = false;
  std::vector<uint8_t> raw_;
  friend struct ZGuard;
};

struct ZGuard {
  z_stream* z;
  bool* open;
  ~ZGuard() {
    if (*open) inflateEnd(z);
  }
};

// Inflates until raw_ holds `want` bytes or the stream ends; the bytes
// beyond `want` that a block gives are kept (they tell of trailing data).
bool SpzReader::inflate_more(size_t want) {
  while (raw_.size() < want && !z_end_) {
    const size_t have = raw_.size();
    const size_t step = std::min<size_t>(std::max<size_t>(want - have, 4096), size_t{8} << 20);
    raw_.resize(have + step);
    z_.next_out = raw_.data() + have;
    z_.avail_out = uInt(step);
    const int r = inflate(&z_, Z_NO_FLUSH);
    raw_.resize(have + (step - z_.avail_out));
    if (r == Z_STREAM_END) {
      z_end_ = true;
    } else if (r == Z_BUF_ERROR && z_.avail_in == 0) {
      fail("the gzip stream is truncated (after " + std::to_string(raw_.size()) + " decompressed bytes)");
    } else if (r != Z_OK) {
      fail(std::string("the gzip stream is corrupt: ") + (z_.msg ? z_.msg : "zlib error " + std::to_string(r)));
    }
  }
  return raw_.size() >= want;
}

size_t SpzReader::drain() {
  size_t extra = 0;
  uint8_t scratch[16384];
  while (!z_end_) {
    z_.next_out = scratch;
    z_.avail_out = sizeof(scratch);
    const int r = inflate(&z_, Z_NO_FLUSH);
    extra += sizeof(scratch) - z_.avail_out;
    if (r == Z_STREAM_END) {
      z_end_ = true;
    } else if (r == Z_BUF_ERROR && z_.avail_in == 0) {
      fail("the gzip stream is truncated (after " + std::to_string(raw_.size() + extra) + " decompressed bytes)");
    } else if (r != Z_OK) {
      fail(std::string("the gzip stream is corrupt: ") + (z_.msg ? z_.msg : "zlib error " + std::to_string(r)));
    }
  }
  return extra;
}

PointData SpzReader::read() {
  if (size_ == 0) fail("file is empty (0 bytes)");
  if (size_ >= 4 && std::memcmp(d_, "NGSP", 4) == 0) return read_v4();
  if (size_ < 2 || d_[0] != 0x1f || d_[1] != 0x8b)
    fail("not an SPZ file: it starts with neither a gzip header (1f 8b, versions 2 and 3) nor 'NGSP' (version 4)", 0);
  return read_gzip();
}

void SpzReader::check(const Header& h) const {
  if (h.n > kMaxPoints) fail("the header declares " + std::to_string(h.n) + " points, more than the supported 10^8");
  if (h.degree > 4) fail("unsupported SH degree " + std::to_string(h.degree) + " (SPZ has 0 to 4)");
  if (h.fractional > 24) fail("fractional bits " + std::to_string(h.fractional) + " exceed the 24-bit positions");
}

size_t SpzReader::stream_bytes(const Header& h, int stream) {
  const size_t n = h.n;
  switch (stream) {
    case 0: return n * 9;
    case 1: return n;
    case 2:
    case 3: return n * 3;
    case 4: return n * (h.version >= 3 ? 4 : 3);
    default: return n * size_t(dim_for_degree(h.degree)) * 3;
  }
}

PointData SpzReader::read_gzip() {
  z_.next_in = const_cast<Bytef*>(d_);
  z_.avail_in = uInt(std::min<size_t>(size_, 0xffffffffu));
  if (size_ > 0xffffffffu) fail("file too large for an SPZ file (over 4 GiB compressed)");
  if (inflateInit2(&z_, 16 + MAX_WBITS) != Z_OK) fail("cannot start the gzip decoder");
  z_open_ = true;
  ZGuard guard{&z_, &z_open_};
  if (!inflate_more(16)) fail("the decompressed data ends inside the 16-byte SPZ header");
  const uint8_t* p = raw_.data();
  Header h;
  h.version = io::load_le<uint32_t>(p + 4);
  h.n = io::load_le<uint32_t>(p + 8);
  h.degree = p[12], h.fractional = p[13], h.flags = p[14];
  if (io::load_le<uint32_t>(p) != kMagic)
    fail("not an SPZ file: the decompressed header's magic is not 'NGSP' (0x5053474e)", 0);
  if (h.version == 1) fail("SPZ version 1 (float16 positions, never released) is not supported; versions 2 to 4 are");
  if (h.version < 2 || h.version > 3)
    fail("unsupported SPZ version " + std::to_string(h.version) +
         " in a gzip stream (versions 2 and 3 are gzip streams; version 4 starts with 'NGSP')");
  check(h);
  if (h.flags & 0x2) fail("the file has SPZ extensions (flag 0x2), which versions 2 and 3 do not define");
  size_t expected = 16;
  for (int stream = 0; stream < 6; ++stream) expected += stream_bytes(h, stream);
  if (!inflate_more(expected))
    fail("the data is truncated: the header declares " + std::to_string(h.n) + " points (" +
         std::to_string(expected) + " decompressed bytes) but the stream holds " + std::to_string(raw_.size()));
  Attributes a;
  const uint8_t** at[6] = {&a.pos, &a.alpha, &a.color, &a.scale, &a.rot, &a.sh};
  const uint8_t* next = raw_.data() + 16;
  for (int stream = 0; stream < 6; ++stream) {
    *at[stream] = next;
    next += stream_bytes(h, stream);
  }
  PointData out = decode(h, a);
  const size_t trailing = raw_.size() - expected + drain();  // the whole stream is checked (CRC-32)
  if (trailing > 0) out.metadata["trailing_bytes"] = int64_t(trailing);  // decompressed bytes after the last band
  return out;
}

PointData SpzReader::read_v4() {
  static const char* const kStreams[6] = {"positions", "alphas", "colours", "scales", "rotations", "SH"};
  if (size_ < 32) fail("the file ends inside the 32-byte SPZ version 4 header (" + std::to_string(size_) + " bytes)");
  Header h;
  h.version = io::load_le<uint32_t>(d_ + 4);
  h.n = io::load_le<uint32_t>(d_ + 8);
  h.degree = d_[12], h.fractional = d_[13], h.flags = d_[14];
  const int streams = d_[15];
  const uint32_t toc = io::load_le<uint32_t>(d_ + 16);
  if (h.version != 4)
    fail("unsupported SPZ version " + std::to_string(h.version) + " after 'NGSP' (the plain container is version 4)",
         4);
  check(h);
  for (int i = 20; i < 32; ++i)
    if (d_[i] != 0) fail("the version 4 header's reserved bytes are not zero", i);
  // The streams the file must hold: those of the six that are not empty.
  int present[6], count = 0;
  for (int stream = 0; stream < 6; ++stream)
    if (stream_bytes(h, stream) > 0) present[count++] = stream;
  if (streams != count)
    fail("the header declares " + std::to_string(streams) + " attribute streams; " + std::to_string(h.n) +
             " points of SH degree " + std::to_string(h.degree) + " have " + std::to_string(count),
         15);
  if (toc < 32) fail("the table of contents' offset " + std::to_string(toc) + " lies inside the header", 16);
  if (toc > size_ || size_t(count) * 16 > size_ - toc)
    fail("the table of contents (" + std::to_string(count) + " x 16 bytes at " + std::to_string(toc) +
             ") runs past the end of the file",
         16);
  if (toc > 32 && !(h.flags & 0x2))
    fail("bytes between the header and the table of contents without the extensions flag (0x2)", 32);
  // Every stream's entry, checked before anything is allocated: its size
  // the points', its bytes within the file, its zstd frame of that size.
  size_t start[6] = {}, packed[6] = {};
  size_t offset = size_t(toc) + size_t(count) * 16, total = 0;
  for (int i = 0; i < count; ++i) {
    const int stream = present[i];
    const std::string name = std::string("the ") + kStreams[stream] + " stream";
    const uint64_t in = io::load_le<uint64_t>(d_ + toc + 16 * size_t(i));
    const uint64_t unpacked = io::load_le<uint64_t>(d_ + toc + 16 * size_t(i) + 8);
    const size_t want = stream_bytes(h, stream);
    if (unpacked != want)
      fail(name + " declares " + std::to_string(unpacked) + " bytes; " + std::to_string(h.n) + " points need " +
               std::to_string(want),
           int64_t(toc) + 16 * i + 8);
    if (in > size_ - offset)
      fail(name + " (" + std::to_string(in) + " bytes at " + std::to_string(offset) + ") runs past the end of the file",
           int64_t(toc) + 16 * i);
    // A zstd block of 3 header bytes and 1 repeated byte is at most 128 KiB.
    if (uint64_t(want) > in * 32768)
      fail(name + "'s " + std::to_string(in) + " bytes cannot hold " + std::to_string(want) +
               " (zstd expands at most 32768-fold)",
           int64_t(toc) + 16 * i);
    const unsigned long long framed = ZSTD_getFrameContentSize(d_ + offset, size_t(in));
    if (framed == ZSTD_CONTENTSIZE_ERROR) fail(name + " is not zstd data", int64_t(offset));
    if (framed != ZSTD_CONTENTSIZE_UNKNOWN && framed > want)
      fail(name + "'s zstd frame holds " + std::to_string(framed) + " bytes; " + std::to_string(want) + " expected",
           int64_t(offset));
    start[stream] = offset;
    packed[stream] = size_t(in);
    offset += size_t(in);
    total += want;
  }
  raw_.resize(total);
  Attributes a;
  const uint8_t** at[6] = {&a.pos, &a.alpha, &a.color, &a.scale, &a.rot, &a.sh};
  size_t placed = 0;
  for (int stream = 0; stream < 6; ++stream) {
    const size_t want = stream_bytes(h, stream);
    *at[stream] = raw_.data() + placed;
    if (want > 0) {
      const std::string name = std::string("the ") + kStreams[stream] + " stream";
      const size_t got = ZSTD_decompress(raw_.data() + placed, want, d_ + start[stream], packed[stream]);
      if (ZSTD_isError(got)) fail(name + " is corrupt: " + ZSTD_getErrorName(got), int64_t(start[stream]));
      if (got != want)
        fail(name + " decompresses to " + std::to_string(got) + " bytes; " + std::to_string(want) + " expected",
             int64_t(start[stream]));
    }
    placed += want;
  }
  PointData out = decode(h, a);
  if (h.flags & 0x2) out.metadata["extension_bytes"] = int64_t(toc - 32);  // vendor records, skipped
  if (offset < size_) out.metadata["trailing_bytes"] = int64_t(size_ - offset);
  return out;
}

PointData SpzReader::decode(const Header& h, const Attributes& a) const {
  const uint32_t n = h.n, version = h.version;
  const int degree = h.degree, fractional = h.fractional, flags = h.flags;
  const size_t sh_dim = size_t(dim_for_degree(degree));
  PointData out;
  io::resize_fresh(out.positions, size_t(n) * 3);
  const uint8_t *pos = a.pos, *alpha = a.alpha, *color = a.color, *scale = a.scale, *rot = a.rot, *shb = a.sh;
  const double unit = 1.0 / double(uint32_t{1} << fractional);
  const double flip[3] = {1.0, -1.0, -1.0};  // RUB -> RDF
  for (size_t i = 0; i < size_t(n) * 3; ++i) {
    const uint8_t* b = pos + 3 * i;
    int32_t v = int32_t(uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16);
    if (v & 0x800000) v -= 0x1000000;  // sign of the 24-bit integer
    out.positions[i] = flip[i % 3] * double(v) * unit;
  }
  const int kept = std::min(degree, kMaxDegree);
  const size_t K = size_t(kept + 1) * size_t(kept + 1);
  std::vector<float> opacity(n), scales(size_t(n) * 3), rotations(size_t(n) * 4), sh(size_t(n) * 3 * K);
  for (size_t i = 0; i < n; ++i) {
    opacity[i] = float(alpha[i]) / 255.0f;
    for (int c = 0; c < 3; ++c) {
      sh[i * 3 * K + size_t(c)] = (float(color[3 * i + size_t(c)]) / 255.0f - 0.5f) / 0.15f;
      scales[3 * i + size_t(c)] = std::exp(float(scale[3 * i + size_t(c)]) / 16.0f - 10.0f);
    }
    float q[4];  // x, y, z, w as SPZ orders them
    if (version >= 3) {
      const uint8_t* r = rot + 4 * i;
      uint32_t word = uint32_t(r[0]) | uint32_t(r[1]) << 8 | uint32_t(r[2]) << 16 | uint32_t(r[3]) << 24;
      const int largest = int(word >> 30);
      float sum = 0.0f;
      for (int k = 3; k >= 0; --k) {
        if (k == largest) continue;
        const float mag = float(word & 511u) / 511.0f * 0.70710678118654752f;
        q[k] = (word >> 9) & 1u ? -mag : mag;
        sum += q[k] * q[k];
        word >>= 10;
      }
      q[largest] = std::sqrt(std::max(0.0f, 1.0f - sum));
    } else {
      const uint8_t* r = rot + 3 * i;
      float sum = 0.0f;
      for (int k = 0; k < 3; ++k) {
        q[k] = float(r[k]) / 127.5f - 1.0f;
        sum += q[k] * q[k];
      }
      q[3] = std::sqrt(std::max(0.0f, 1.0f - sum));
    }
    // w, x, y, z in the PLY's axes, normalised (8-bit components are not quite unit).
    const float w = q[3], x = q[0], y = -q[1], z = -q[2];
    const float len = std::sqrt(w * w + x * x + y * y + z * z);
    float* o = &rotations[4 * i];
    if (len > 0.0f) {
      o[0] = w / len, o[1] = x / len, o[2] = y / len, o[3] = z / len;
    } else {
      o[0] = 1.0f, o[1] = o[2] = o[3] = 0.0f;
    }
    const uint8_t* s = shb + i * sh_dim * 3;
    for (size_t k = 1; k < K; ++k)
      for (int c = 0; c < 3; ++c) {
        const float v = (float(s[(k - 1) * 3 + size_t(c)]) - 128.0f) / 128.0f;
        sh[(i * K + k) * 3 + size_t(c)] = kOddInYZ[k] ? -v : v;
      }
  }
  out.set("opacity", 1, std::move(opacity));
  out.set("scales", 3, std::move(scales));
  out.set("rotations", 4, std::move(rotations));
  out.set("sh", int(3 * K), std::move(sh));
  io::colors_from_sh_dc(out, int(K));
  auto& md = out.metadata;
  md["format"] = std::string("spz");
  md["version"] = std::to_string(version);
  md["point_count"] = int64_t{n};
  md["gaussian_splats"] = int64_t{1};
  md["sh_degree"] = int64_t{kept};
  md["fractional_bits"] = int64_t{fractional};
  md["antialiased"] = int64_t{flags & 1};
  md["coordinate_system"] = std::string("RDF (SPZ's RUB turned to the axes of 3DGS PLY files)");
  if (degree > kMaxDegree) md["warning"] = std::string("SH degree 4 bands were read past: degree 3 is kept");
  return out;
}

}  // namespace

PointData read_spz(const std::string& path) {
  SpzReader reader(path);
  return reader.read();
}

PointData read_spz_memory(const uint8_t* data, size_t size, const std::string& name) {
  SpzReader reader(name, data, size);
  return reader.read();
}

}  // namespace pointnpr
