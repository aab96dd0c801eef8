// SPZ reader (Niantic's compressed 3D Gaussian splats, versions 2 and 3).
//
// Written from the format's published description (the spz repository's
// README): the file is one gzip stream holding a 16-byte little-endian
// header (magic 0x5053474e "NGSP", version, number of points, SH degree,
// fractional bits, flags, reserved) and then, attribute after attribute:
// positions (3 x 24-bit signed fixed point per point, 2^-fractionalBits
// units), alphas (8 bits: the sigmoid of the opacity), colours (8 bits a
// channel: 0.5 + 0.15 * SH DC), scales (8 bits: (ln s + 10) * 16),
// rotations (version 2: x, y, z as 8 bits each, (b / 127.5) - 1, w >= 0
// derived; version 3: "smallest three": a 32-bit word holding the index of
// the largest component in its top 2 bits and the other three, last first,
// as a sign bit and 9 bits of magnitude scaled by 1/sqrt(2)), then the SH
// bands (8 bits: (b - 128) / 128, coefficient-major, r g b inner).
// SPZ stores right-up-back (OpenGL) axes; 3DGS PLY files are right-down-
// front (COLMAP), so the reader turns SPZ into the PLY's axes (a half turn
// about x: y and z negated, in positions, quaternions and the SH bands
// odd in y and z), and the two formats of one capture coincide.
#include <zlib.h>

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
  if (size_ >= 4 && std::memcmp(d_, "NGSP", 4) == 0)
    fail("SPZ version " + std::to_string(size_ >= 8 ? io::load_le<uint32_t>(d_ + 4) : 0) +
         " (the uncompressed NGSP container) is not supported; SPZ versions 2 and 3 (a gzip stream) are", 0);
  if (size_ < 2 || d_[0] != 0x1f || d_[1] != 0x8b)
    fail("not an SPZ file: it does not start with a gzip header (1f 8b)", 0);
  z_.next_in = const_cast<Bytef*>(d_);
  z_.avail_in = uInt(std::min<size_t>(size_, 0xffffffffu));
  if (size_ > 0xffffffffu) fail("file too large for an SPZ file (over 4 GiB compressed)");
  if (inflateInit2(&z_, 16 + MAX_WBITS) != Z_OK) fail("cannot start the gzip decoder");
  z_open_ = true;
  ZGuard guard{&z_, &z_open_};
  if (!inflate_more(16)) fail("the decompressed data ends inside the 16-byte SPZ header");
  const uint8_t* h = raw_.data();
  const uint32_t magic = io::load_le<uint32_t>(h), version = io::load_le<uint32_t>(h + 4);
  const uint32_t n = io::load_le<uint32_t>(h + 8);
  const int degree = h[12], fractional = h[13], flags = h[14];
  if (magic != kMagic) fail("not an SPZ file: the decompressed header's magic is not 'NGSP' (0x5053474e)", 0);
  if (version == 1) fail("SPZ version 1 (float16 positions, never released) is not supported; versions 2 and 3 are");
  if (version < 2 || version > 3)
    fail("unsupported SPZ version " + std::to_string(version) + " (versions 2 and 3 are supported)");
  if (n > kMaxPoints) fail("the header declares " + std::to_string(n) + " points, more than the supported 10^8");
  if (degree > 4) fail("unsupported SH degree " + std::to_string(degree) + " (SPZ has 0 to 4)");
  if (fractional > 24) fail("fractional bits " + std::to_string(fractional) + " exceed the 24-bit positions");
  if (flags & 0x2) fail("the file has SPZ extensions (flag 0x2), which this reader does not support");
  const size_t rot_bytes = version >= 3 ? 4 : 3;
  const size_t sh_dim = size_t(dim_for_degree(degree));
  const size_t per_point = 9 + 1 + 3 + 3 + rot_bytes + sh_dim * 3;
  const size_t expected = 16 + size_t(n) * per_point;
  if (!inflate_more(expected))
    fail("the data is truncated: the header declares " + std::to_string(n) + " points (" +
         std::to_string(expected) + " decompressed bytes) but the stream holds " + std::to_string(raw_.size()));

  PointData out;
  io::resize_fresh(out.positions, size_t(n) * 3);
  const uint8_t* pos = raw_.data() + 16;
  const uint8_t* alpha = pos + size_t(n) * 9;
  const uint8_t* color = alpha + n;
  const uint8_t* scale = color + size_t(n) * 3;
  const uint8_t* rot = scale + size_t(n) * 3;
  const uint8_t* shb = rot + size_t(n) * rot_bytes;
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
  const size_t trailing = raw_.size() - expected + drain();  // the whole stream is checked (CRC-32)
  if (trailing > 0) md["trailing_bytes"] = int64_t(trailing);  // decompressed bytes after the last band
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
