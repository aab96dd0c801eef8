#pragma once
// A test-side LASzip encoder, just large enough to write what no real file
// in the test data holds: LASzip 1.x point-wise streams of items POINT10 v1
// and BYTE v1 (extra bytes). Written from LASzip's published description of
// its entropy coder (Isenburg 2013; the 32-bit range coder with carry
// propagation, adaptive bit and symbol models, the integer compressor's
// k-bit correctors). The models are written here again on purpose instead
// of reusing cpp/io/laz_arithmetic.h: an encoder sharing the decoder's
// model code would agree with it even where both are wrong. Its arithmetic
// is checked against an independent decoder too (lazrs reads a POINT10 v1
// file it writes: tests/python/test_io_laz.py).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/laz_items.h"

namespace pointnpr::laz_test {

struct EncBitModel {
  uint32_t bit_0_count = 1, bit_count = 2, bit_0_prob = 1u << 12;
  uint32_t update_cycle = 4, bits_until_update = 4;
  void update() {
    if ((bit_count += update_cycle) > (1u << 13)) {
      bit_count = (bit_count + 1) >> 1;
      bit_0_count = (bit_0_count + 1) >> 1;
      if (bit_0_count == bit_count) ++bit_count;
    }
    bit_0_prob = (bit_0_count * (0x80000000u / bit_count)) >> 18;
    update_cycle = std::min<uint32_t>((5 * update_cycle) >> 2, 64);
    bits_until_update = update_cycle;
  }
};

struct EncSymbolModel {
  uint32_t symbols = 0, total = 0, update_cycle = 0, until_update = 0;
  std::vector<uint32_t> dist, count;
  explicit EncSymbolModel(uint32_t n = 2) { init(n); }
  void init(uint32_t n) {
    symbols = n;
    dist.assign(n, 0);
    count.assign(n, 1);
    total = 0;
    update_cycle = n;
    update();
    until_update = update_cycle = (n + 6) >> 1;
  }
  void update() {
    if ((total += update_cycle) > (1u << 15)) {
      total = 0;
      for (uint32_t& c : count) total += (c = (c + 1) >> 1);
    }
    const uint32_t scale = 0x80000000u / total;
    uint32_t sum = 0;
    for (uint32_t k = 0; k < symbols; ++k) {
      dist[k] = (scale * sum) >> 16;
      sum += count[k];
    }
    update_cycle = std::min((5 * update_cycle) >> 2, (symbols + 6) << 3);
    until_update = update_cycle;
  }
};

class Encoder {
 public:
  static constexpr uint32_t kMinLength = 0x01000000u;

  void bit(EncBitModel& m, uint32_t sym) {
    const uint32_t x = m.bit_0_prob * (length_ >> 13);
    if (sym == 0) {
      length_ = x;
      ++m.bit_0_count;
    } else {
      add(x);
      length_ -= x;
    }
    if (length_ < kMinLength) renormalize();
    if (--m.bits_until_update == 0) m.update();
  }
  void symbol(EncSymbolModel& m, uint32_t sym) {
    const uint32_t unit = length_ >> 15;
    const uint32_t x = m.dist[sym] * unit;
    add(x);
    // The last symbol takes the rest of the interval (rounding included).
    length_ = sym + 1 == m.symbols ? length_ - x : m.dist[sym + 1] * unit - x;
    if (length_ < kMinLength) renormalize();
    ++m.count[sym];
    if (--m.until_update == 0) m.update();
  }
  void bits(uint32_t n, uint32_t value) {
    if (n > 19) {
      raw(16, value & 0xFFFF);
      value >>= 16;
      n -= 16;
    }
    raw(n, value);
  }
  // Flushes the interval and the bytes the decoder reads ahead.
  std::vector<uint8_t> done() {
    const bool another_byte = length_ > 2 * kMinLength;
    if (another_byte) {
      add(kMinLength);
      length_ = kMinLength >> 1;
    } else {
      add(kMinLength >> 1);
      length_ = kMinLength >> 9;
    }
    renormalize();
    out_.insert(out_.end(), another_byte ? 3 : 2, 0);
    return std::move(out_);
  }

 private:
  void raw(uint32_t n, uint32_t value) {
    length_ >>= n;
    add(value * length_);
    if (length_ < kMinLength) renormalize();
  }
  // base += x, carrying into the bytes already written.
  void add(uint32_t x) {
    const uint32_t before = base_;
    base_ += x;
    if (base_ < before) {
      size_t i = out_.size();
      while (out_[--i] == 0xFF) out_[i] = 0;
      ++out_[i];
    }
  }
  void renormalize() {
    do {
      out_.push_back(static_cast<uint8_t>(base_ >> 24));
      base_ <<= 8;
    } while ((length_ <<= 8) < kMinLength);
  }

  uint32_t base_ = 0, length_ = 0xFFFFFFFFu;
  std::vector<uint8_t> out_;
};

// real = pred + corrector; the corrector's bit length k is coded in the
// context's model, then its value (high bits by model, low bits raw).
class IntegerCompressor {
 public:
  IntegerCompressor(uint32_t bits, uint32_t contexts) {
    corr_bits_ = bits;
    range_ = bits < 32 ? (1u << bits) : 0;
    for (uint32_t i = 0; i < contexts; ++i) k_models_.emplace_back(corr_bits_ + 1);
    for (uint32_t k = 1; k <= corr_bits_; ++k) corr_.emplace_back(1u << std::min(k, kBitsHigh));
  }
  void compress(Encoder& enc, int32_t pred, int32_t real, uint32_t context) {
    int32_t c = static_cast<int32_t>(static_cast<uint32_t>(real) - static_cast<uint32_t>(pred));
    if (range_) {  // fold into [-range/2, range/2)
      const int32_t half = static_cast<int32_t>(range_ / 2);
      if (c < -half) c += static_cast<int32_t>(range_);
      else if (c >= half) c -= static_cast<int32_t>(range_);
    }
    const uint32_t mag = c <= 0 ? 0u - static_cast<uint32_t>(c) : static_cast<uint32_t>(c) - 1;
    k_ = 0;
    for (uint32_t m = mag; m; m >>= 1) ++k_;
    enc.symbol(k_models_[context], k_);
    if (k_ == 0) {
      enc.bit(corr0_, static_cast<uint32_t>(c));
      return;
    }
    // [-(2^k - 1), -2^(k-1)] -> [0, 2^(k-1)); [2^(k-1) + 1, 2^k] -> [2^(k-1), 2^k).
    const uint32_t v = c < 0 ? static_cast<uint32_t>(c) + ((1u << k_) - 1) : static_cast<uint32_t>(c) - 1;
    if (k_ <= kBitsHigh) {
      enc.symbol(corr_[k_ - 1], v);
    } else {
      const uint32_t low_bits = k_ - kBitsHigh;
      enc.symbol(corr_[k_ - 1], v >> low_bits);
      enc.bits(low_bits, v & ((1u << low_bits) - 1));
    }
  }
  uint32_t k() const { return k_; }

 private:
  static constexpr uint32_t kBitsHigh = 8;
  uint32_t corr_bits_, range_, k_ = 0;
  std::vector<EncSymbolModel> k_models_;
  EncBitModel corr0_;
  std::vector<EncSymbolModel> corr_;
};

using laz::get;  // little-endian fields of a record

inline int32_t median3(const int32_t d[3]) {
  const int32_t lo = std::min(d[0], d[1]), hi = std::max(d[0], d[1]);
  return std::max(lo, std::min(hi, d[2]));
}

// POINT10 version 1: x/y from the median of the last three differences,
// z from the last z, the other fields only when they change.
class Point10V1Encoder {
 public:
  explicit Point10V1Encoder(const uint8_t* first) { std::memcpy(last_, first, 20); }
  void write(Encoder& enc, const uint8_t* p) {
    const int32_t dx = static_cast<int32_t>(get<uint32_t>(p) - get<uint32_t>(last_));
    const int32_t dy = static_cast<int32_t>(get<uint32_t>(p + 4) - get<uint32_t>(last_ + 4));
    dx_.compress(enc, median3(last_dx_), dx, 0);
    uint32_t k = dx_.k();
    dy_.compress(enc, median3(last_dy_), dy, std::min(k, 19u));
    k = (k + dy_.k()) / 2;
    z_.compress(enc, get<int32_t>(last_ + 8), get<int32_t>(p + 8), std::min(k, 19u));
    const uint32_t changed = (get<uint16_t>(p + 12) != get<uint16_t>(last_ + 12)) << 5 |
                             (p[14] != last_[14]) << 4 | (p[15] != last_[15]) << 3 |
                             (p[16] != last_[16]) << 2 | (p[17] != last_[17]) << 1 |
                             (get<uint16_t>(p + 18) != get<uint16_t>(last_ + 18));
    enc.symbol(changed_, changed);
    if (changed & 32) intensity_.compress(enc, get<uint16_t>(last_ + 12), get<uint16_t>(p + 12), 0);
    if (changed & 16) enc.symbol(byte_model(bit_byte_, last_[14]), p[14]);
    if (changed & 8) enc.symbol(byte_model(classification_, last_[15]), p[15]);
    if (changed & 4)
      scan_angle_.compress(enc, static_cast<int8_t>(last_[16]), static_cast<int8_t>(p[16]),
                           k < 3 ? 1 : 0);
    if (changed & 2) enc.symbol(byte_model(user_data_, last_[17]), p[17]);
    if (changed & 1) point_source_.compress(enc, get<uint16_t>(last_ + 18), get<uint16_t>(p + 18), 0);
    last_dx_[incr_] = dx;
    last_dy_[incr_] = dy;
    incr_ = (incr_ + 1) % 3;
    std::memcpy(last_, p, 20);
  }

 private:
  static EncSymbolModel& byte_model(std::vector<EncSymbolModel>& v, uint8_t context) {
    if (v.empty()) v.assign(256, EncSymbolModel(256));
    return v[context];
  }
  uint8_t last_[20];
  int32_t last_dx_[3] = {0, 0, 0}, last_dy_[3] = {0, 0, 0};
  int incr_ = 0;
  EncSymbolModel changed_{64};
  std::vector<EncSymbolModel> bit_byte_, classification_, user_data_;
  IntegerCompressor dx_{32, 1}, dy_{32, 20}, z_{32, 20}, intensity_{16, 1}, scan_angle_{8, 2},
      point_source_{16, 1};
};

// BYTE version 1: each extra byte against the same byte of the last point.
class BytesV1Encoder {
 public:
  BytesV1Encoder(const uint8_t* first, uint32_t count)
      : last_(first, first + count), ic_(8, count) {}
  void write(Encoder& enc, const uint8_t* p) {
    for (uint32_t i = 0; i < last_.size(); ++i) ic_.compress(enc, last_[i], p[i], i);
    std::memcpy(last_.data(), p, last_.size());
  }

 private:
  std::vector<uint8_t> last_;
  IntegerCompressor ic_;
};

// One stream of POINT10 v1 (+ BYTE v1 when rl > 20) records: the first
// record raw, then the arithmetic-coded rest.
inline std::string encode_stream_v1(const uint8_t* r, size_t n, size_t rl) {
  std::string out(reinterpret_cast<const char*>(r), n ? rl : 0);
  if (n < 2) return out;
  Encoder enc;
  Point10V1Encoder p10(r);
  BytesV1Encoder bytes(r + 20, static_cast<uint32_t>(rl - 20));
  for (size_t i = 1; i < n; ++i) {
    p10.write(enc, r + i * rl);
    if (rl > 20) bytes.write(enc, r + i * rl + 20);
  }
  const std::vector<uint8_t> s = enc.done();
  return out + std::string(s.begin(), s.end());
}

// The point data of a LAZ file of version 1 items: compressor 1 (LASzip
// 1.x point-wise, one stream) or 2 (chunks of `chunk_size` points after the
// offset of the chunk table, which ends the data).
inline std::string laz_point_data_v1(const std::string& records, size_t rl, int compressor,
                                     size_t chunk_size, uint64_t point_offset) {
  const auto* r = reinterpret_cast<const uint8_t*>(records.data());
  const size_t n = records.size() / rl;
  if (compressor == 1) return encode_stream_v1(r, n, rl);
  std::string out(8, '\0');
  std::vector<uint32_t> sizes;
  for (size_t at = 0; at < n; at += chunk_size) {
    const std::string c = encode_stream_v1(r + at * rl, std::min(chunk_size, n - at), rl);
    sizes.push_back(static_cast<uint32_t>(c.size()));
    out += c;
  }
  const uint64_t table_at = point_offset + out.size();
  std::memcpy(out.data(), &table_at, 8);
  const uint32_t head[2] = {0, static_cast<uint32_t>(sizes.size())};  // version 0, chunks
  out.append(reinterpret_cast<const char*>(head), 8);
  Encoder enc;
  IntegerCompressor ic(32, 2);
  uint32_t prev = 0;
  for (uint32_t s : sizes) {  // fixed chunks: byte counts only, context 1
    ic.compress(enc, static_cast<int32_t>(prev), static_cast<int32_t>(s), 1);
    prev = s;
  }
  const std::vector<uint8_t> t = enc.done();
  return out + std::string(t.begin(), t.end());
}

// The LASzip VLR payload: compressor, coder 0, LASzip 1.x, items POINT10 v1
// (+ BYTE v1 of `extra` bytes).
inline std::string laszip_vlr_payload_v1(uint16_t compressor, size_t extra,
                                         uint32_t chunk_size = 50000) {
  std::string b;
  auto put = [&b](auto v) { b.append(reinterpret_cast<const char*>(&v), sizeof(v)); };
  put(uint16_t{compressor});
  put(uint16_t{0});                    // coder: arithmetic
  put(uint8_t{1}), put(uint8_t{4});    // LASzip 1.4
  put(uint16_t{0});                    // revision
  put(uint32_t{0});                    // options
  put(uint32_t{chunk_size});
  put(int64_t{-1}), put(int64_t{-1});  // no special EVLRs
  put(uint16_t{static_cast<uint16_t>(extra ? 2 : 1)});
  put(uint16_t{6}), put(uint16_t{20}), put(uint16_t{1});  // POINT10 v1
  if (extra) put(uint16_t{0}), put(static_cast<uint16_t>(extra)), put(uint16_t{1});  // BYTE v1
  return b;
}

}  // namespace pointnpr::laz_test
