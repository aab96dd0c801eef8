// LASzip point-wise items, versions 1 and 2: POINT10 (the 20 bytes common to
// LAS point formats 0-5), GPSTIME11, RGB12 and BYTE (extra bytes).
//
// Version 2 predicts x/y from the median of the last five differences of
// points with the same return context and z from the last point on the same
// return level; version 1 (LASzip 1.x) from the last three differences.
#include <cstring>
#include <optional>

#include "core/error.h"
#include "io/laz_items.h"
#include "io/laz_reader.h"

namespace pointnpr::laz {
namespace {

// Maps (number of returns n, return number r) to one of 16 contexts; the
// "incorrect" combinations (r = 0, r > n, ...) get contexts of their own.
constexpr uint8_t kNumberReturnMap[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8}, {14, 0, 1, 3, 6, 10, 10, 9},
    {13, 1, 2, 4, 7, 11, 11, 10},   {12, 3, 4, 5, 8, 12, 12, 11},
    {11, 6, 7, 8, 9, 13, 13, 12},   {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15}};
// |n - r|: points on the same level share the z predictor.
constexpr uint8_t kNumberReturnLevel[8][8] = {
    {0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 1, 2, 3, 4, 5, 6}, {2, 1, 0, 1, 2, 3, 4, 5},
    {3, 2, 1, 0, 1, 2, 3, 4}, {4, 3, 2, 1, 0, 1, 2, 3}, {5, 4, 3, 2, 1, 0, 1, 2},
    {6, 5, 4, 3, 2, 1, 0, 1}, {7, 6, 5, 4, 3, 2, 1, 0}};

inline uint32_t zero_bit_0(uint32_t n) { return n & ~1u; }

// A stream asking to switch GPS time sequences more often than a valid one
// can is corrupt; stop it before it spins.
[[noreturn]] void too_many_switches() {
  throw FormatError("the GPS time stream switches sequences without end", -1);
}

}  // namespace

// ---------------------------------------------------------------- POINT10 v2

Point10V2::Point10V2() {
  ic_intensity_.setup(16, 4);
  ic_point_source_.setup(16, 1);
  ic_dx_.setup(32, 2);
  ic_dy_.setup(32, 22);
  ic_z_.setup(32, 20);
}

void Point10V2::init(const uint8_t* first) {
  for (int i = 0; i < 16; ++i) {
    last_x_diff_[i] = Median5{};
    last_y_diff_[i] = Median5{};
    last_intensity_[i] = 0;
  }
  for (int& h : last_height_) h = 0;
  changed_values_.init(64);
  scan_angle_rank_[0].init(256);
  scan_angle_rank_[1].init(256);
  bit_byte_.reset();
  classification_.reset();
  user_data_.reset();
  ic_intensity_.init();
  ic_point_source_.init();
  ic_dx_.init();
  ic_dy_.init();
  ic_z_.init();
  std::memcpy(last_, first, 20);
  put<uint16_t>(last_ + 12, 0);  // the intensity context starts at zero
}

void Point10V2::read(Decoder& dec, uint8_t* item) {
  const uint32_t changed = dec.decode_symbol(changed_values_);
  uint32_t r, n, m, l;
  if (changed) {
    if (changed & 32) last_[14] = static_cast<uint8_t>(dec.decode_symbol(bit_byte_[last_[14]]));
    r = last_[14] & 7;
    n = (last_[14] >> 3) & 7;
    m = kNumberReturnMap[n][r];
    l = kNumberReturnLevel[n][r];
    if (changed & 16) {
      const auto v = static_cast<uint16_t>(
          ic_intensity_.decompress(dec, last_intensity_[m], m < 3 ? m : 3));
      put<uint16_t>(last_ + 12, v);
      last_intensity_[m] = v;
    } else {
      put<uint16_t>(last_ + 12, last_intensity_[m]);
    }
    if (changed & 8)
      last_[15] = static_cast<uint8_t>(dec.decode_symbol(classification_[last_[15]]));
    if (changed & 4) {
      const uint32_t v = dec.decode_symbol(scan_angle_rank_[(last_[14] >> 6) & 1]);
      last_[16] = fold_u8(static_cast<int32_t>(v) + last_[16]);
    }
    if (changed & 2) last_[17] = static_cast<uint8_t>(dec.decode_symbol(user_data_[last_[17]]));
    if (changed & 1)
      put<uint16_t>(last_ + 18, static_cast<uint16_t>(ic_point_source_.decompress(
                                    dec, get<uint16_t>(last_ + 18))));
  } else {
    r = last_[14] & 7;
    n = (last_[14] >> 3) & 7;
    m = kNumberReturnMap[n][r];
    l = kNumberReturnLevel[n][r];
  }

  int32_t diff = ic_dx_.decompress(dec, last_x_diff_[m].get(), n == 1);
  put<int32_t>(last_, wrap_add(get<int32_t>(last_), diff));
  last_x_diff_[m].add(diff);

  uint32_t k_bits = ic_dx_.k();
  diff = ic_dy_.decompress(dec, last_y_diff_[m].get(),
                           (n == 1) + (k_bits < 20 ? zero_bit_0(k_bits) : 20));
  put<int32_t>(last_ + 4, wrap_add(get<int32_t>(last_ + 4), diff));
  last_y_diff_[m].add(diff);

  k_bits = (ic_dx_.k() + ic_dy_.k()) / 2;
  const int32_t z =
      ic_z_.decompress(dec, last_height_[l], (n == 1) + (k_bits < 18 ? zero_bit_0(k_bits) : 18));
  put<int32_t>(last_ + 8, z);
  last_height_[l] = z;
  std::memcpy(item, last_, 20);
}

// -------------------------------------------------------------- GPSTIME11 v2

namespace {
constexpr int32_t kGpsMulti = 500;
constexpr int32_t kGpsMultiMinus = -10;
constexpr int32_t kGpsMultiUnchanged = kGpsMulti - kGpsMultiMinus + 1;  // 511
constexpr int32_t kGpsMultiCodeFull = kGpsMulti - kGpsMultiMinus + 2;   // 512
constexpr int32_t kGpsMultiTotal = kGpsMulti - kGpsMultiMinus + 6;      // 516
}  // namespace

GpsTime11V2::GpsTime11V2() { ic_gps_.setup(32, 9); }

void GpsTime11V2::init(const uint8_t* first) {
  last_ = next_ = 0;
  for (int i = 0; i < 4; ++i) last_diff_[i] = multi_extreme_[i] = 0;
  multi_.init(kGpsMultiTotal);
  zero_diff_.init(6);
  ic_gps_.init();
  last_gps_[0] = get<uint64_t>(first);
  last_gps_[1] = last_gps_[2] = last_gps_[3] = 0;
}

void GpsTime11V2::read(Decoder& dec, uint8_t* item) {
  // The time is kept as the integer of its bits: differences of consecutive
  // doubles of one sequence are small integers.
  for (int switches = 0;; ++switches) {
    if (switches > 8) too_many_switches();
    auto full_time = [&] {
      next_ = (next_ + 1) & 3;
      const auto high = static_cast<uint32_t>(
          ic_gps_.decompress(dec, static_cast<int32_t>(last_gps_[last_] >> 32), 8));
      last_gps_[next_] = (static_cast<uint64_t>(high) << 32) | dec.read_int();
      last_ = next_;
      last_diff_[last_] = 0;
      multi_extreme_[last_] = 0;
    };
    if (last_diff_[last_] == 0) {
      const int32_t multi = static_cast<int32_t>(dec.decode_symbol(zero_diff_));
      if (multi == 1) {
        last_diff_[last_] = ic_gps_.decompress(dec, 0, 0);
        last_gps_[last_] += static_cast<uint64_t>(static_cast<int64_t>(last_diff_[last_]));
        multi_extreme_[last_] = 0;
      } else if (multi == 2) {
        full_time();
      } else if (multi > 2) {
        last_ = (last_ + static_cast<uint32_t>(multi) - 2) & 3;
        continue;
      }
    } else {
      int32_t multi = static_cast<int32_t>(dec.decode_symbol(multi_));
      if (multi == 1) {
        last_gps_[last_] += static_cast<uint64_t>(
            static_cast<int64_t>(ic_gps_.decompress(dec, last_diff_[last_], 1)));
        multi_extreme_[last_] = 0;
      } else if (multi < kGpsMultiUnchanged) {
        int32_t gps_diff;
        auto extreme = [&] {
          if (++multi_extreme_[last_] > 3) {
            last_diff_[last_] = gps_diff;
            multi_extreme_[last_] = 0;
          }
        };
        if (multi == 0) {
          gps_diff = ic_gps_.decompress(dec, 0, 7);
          extreme();
        } else if (multi < kGpsMulti) {
          gps_diff = ic_gps_.decompress(dec, wrap_mul(multi, last_diff_[last_]), multi < 10 ? 2 : 3);
        } else if (multi == kGpsMulti) {
          gps_diff = ic_gps_.decompress(dec, wrap_mul(kGpsMulti, last_diff_[last_]), 4);
          extreme();
        } else {
          multi = kGpsMulti - multi;
          if (multi > kGpsMultiMinus) {
            gps_diff = ic_gps_.decompress(dec, wrap_mul(multi, last_diff_[last_]), 5);
          } else {
            gps_diff = ic_gps_.decompress(dec, wrap_mul(kGpsMultiMinus, last_diff_[last_]), 6);
            extreme();
          }
        }
        last_gps_[last_] += static_cast<uint64_t>(static_cast<int64_t>(gps_diff));
      } else if (multi == kGpsMultiCodeFull) {
        full_time();
      } else if (multi > kGpsMultiCodeFull) {
        last_ = (last_ + static_cast<uint32_t>(multi - kGpsMultiCodeFull)) & 3;
        continue;
      }
    }
    break;
  }
  put<uint64_t>(item, last_gps_[last_]);
}

// ------------------------------------------------------------------ RGB12 v2

void RgbModels::init() {
  byte_used.init(128);
  for (SymbolModel& m : diff) m.init(256);
}

void Rgb12V2::init(const uint8_t* first) {
  models_.init();
  for (int c = 0; c < 3; ++c) last_[c] = get<uint16_t>(first + 2 * c);
}

void Rgb12V2::read(Decoder& dec, uint8_t* item) {
  decode_rgb_v2(dec, models_, last_);
  for (int c = 0; c < 3; ++c) put<uint16_t>(item + 2 * c, last_[c]);
}

void decode_rgb_v2(Decoder& dec, RgbModels& models, uint16_t last_[3]) {
  // Bits of `used`: which bytes changed (0/1 red low/high, 2/3 green, 4/5
  // blue); bit 6: green and blue differ from red. Green and blue are
  // predicted from red's change.
  SymbolModel* diff_ = models.diff;
  const uint32_t used = dec.decode_symbol(models.byte_used);
  uint16_t rgb[3];
  const int32_t l0 = last_[0] & 255, h0 = last_[0] >> 8;
  const int32_t l1 = last_[1] & 255, h1 = last_[1] >> 8;
  const int32_t l2 = last_[2] & 255, h2 = last_[2] >> 8;
  rgb[0] = (used & 1) ? fold_u8(static_cast<int32_t>(dec.decode_symbol(diff_[0])) + l0)
                      : static_cast<uint16_t>(l0);
  if (used & 2)
    rgb[0] |= static_cast<uint16_t>(
        fold_u8(static_cast<int32_t>(dec.decode_symbol(diff_[1])) + h0) << 8);
  else
    rgb[0] |= static_cast<uint16_t>(last_[0] & 0xFF00);
  if (used & 64) {
    int32_t diff = (rgb[0] & 255) - l0;
    if (used & 4)
      rgb[1] = fold_u8(static_cast<int32_t>(dec.decode_symbol(diff_[2])) + clamp_u8(diff + l1));
    else
      rgb[1] = static_cast<uint16_t>(l1);
    if (used & 16) {
      diff = (diff + ((rgb[1] & 255) - l1)) / 2;
      rgb[2] = fold_u8(static_cast<int32_t>(dec.decode_symbol(diff_[4])) + clamp_u8(diff + l2));
    } else {
      rgb[2] = static_cast<uint16_t>(l2);
    }
    diff = (rgb[0] >> 8) - h0;
    if (used & 8)
      rgb[1] |= static_cast<uint16_t>(
          fold_u8(static_cast<int32_t>(dec.decode_symbol(diff_[3])) + clamp_u8(diff + h1)) << 8);
    else
      rgb[1] |= static_cast<uint16_t>(last_[1] & 0xFF00);
    if (used & 32) {
      diff = (diff + ((rgb[1] >> 8) - h1)) / 2;
      rgb[2] |= static_cast<uint16_t>(
          fold_u8(static_cast<int32_t>(dec.decode_symbol(diff_[5])) + clamp_u8(diff + h2)) << 8);
    } else {
      rgb[2] |= static_cast<uint16_t>(last_[2] & 0xFF00);
    }
  } else {
    rgb[1] = rgb[2] = rgb[0];
  }
  for (int c = 0; c < 3; ++c) last_[c] = rgb[c];
}

// ---------------------------------------------------------------- POINT10 v1

namespace {
// The format's "median" of the last three differences (as LASzip 1.x
// computes it, which is not always the true median).
int32_t median3(const int32_t d[3]) {
  if (d[0] < d[1]) {
    if (d[1] < d[2]) return d[1];
    if (d[0] < d[2]) return d[2];
    return d[0];
  }
  if (d[0] < d[2]) return d[0];
  if (d[1] < d[2]) return d[2];
  return d[1];
}
}  // namespace

Point10V1::Point10V1() {
  ic_dx_.setup(32, 1);
  ic_dy_.setup(32, 20);
  ic_z_.setup(32, 20);
  ic_intensity_.setup(16, 1);
  ic_scan_angle_.setup(8, 2);
  ic_point_source_.setup(16, 1);
}

void Point10V1::init(const uint8_t* first) {
  for (int i = 0; i < 3; ++i) last_x_diff_[i] = last_y_diff_[i] = 0;
  last_incr_ = 0;
  ic_dx_.init();
  ic_dy_.init();
  ic_z_.init();
  ic_intensity_.init();
  ic_scan_angle_.init();
  ic_point_source_.init();
  changed_values_.init(64);
  bit_byte_.reset();
  classification_.reset();
  user_data_.reset();
  std::memcpy(last_, first, 20);
}

void Point10V1::read(Decoder& dec, uint8_t* item) {
  const int32_t x_diff = ic_dx_.decompress(dec, median3(last_x_diff_), 0);
  put<int32_t>(last_, wrap_add(get<int32_t>(last_), x_diff));
  uint32_t k_bits = ic_dx_.k();
  const int32_t y_diff = ic_dy_.decompress(dec, median3(last_y_diff_), k_bits < 19 ? k_bits : 19);
  put<int32_t>(last_ + 4, wrap_add(get<int32_t>(last_ + 4), y_diff));
  k_bits = (k_bits + ic_dy_.k()) / 2;
  put<int32_t>(last_ + 8, ic_z_.decompress(dec, get<int32_t>(last_ + 8), k_bits < 19 ? k_bits : 19));
  const uint32_t changed = dec.decode_symbol(changed_values_);
  if (changed) {
    if (changed & 32)
      put<uint16_t>(last_ + 12, static_cast<uint16_t>(
                                    ic_intensity_.decompress(dec, get<uint16_t>(last_ + 12))));
    if (changed & 16) last_[14] = static_cast<uint8_t>(dec.decode_symbol(bit_byte_[last_[14]]));
    if (changed & 8)
      last_[15] = static_cast<uint8_t>(dec.decode_symbol(classification_[last_[15]]));
    if (changed & 4)
      last_[16] = static_cast<uint8_t>(ic_scan_angle_.decompress(
          dec, static_cast<int8_t>(last_[16]), k_bits < 3 ? 1 : 0));
    if (changed & 2) last_[17] = static_cast<uint8_t>(dec.decode_symbol(user_data_[last_[17]]));
    if (changed & 1)
      put<uint16_t>(last_ + 18, static_cast<uint16_t>(ic_point_source_.decompress(
                                    dec, get<uint16_t>(last_ + 18))));
  }
  last_x_diff_[last_incr_] = x_diff;
  last_y_diff_[last_incr_] = y_diff;
  if (++last_incr_ > 2) last_incr_ = 0;
  std::memcpy(item, last_, 20);
}

// -------------------------------------------------------------- GPSTIME11 v1

namespace {
constexpr uint32_t kGpsMultiMaxV1 = 512;
}

GpsTime11V1::GpsTime11V1() { ic_gps_.setup(32, 6); }

void GpsTime11V1::init(const uint8_t* first) {
  multi_.init(kGpsMultiMaxV1);
  zero_diff_.init(3);
  ic_gps_.init();
  last_diff_ = 0;
  multi_extreme_ = 0;
  last_gps_ = get<uint64_t>(first);
}

void GpsTime11V1::read(Decoder& dec, uint8_t* item) {
  if (last_diff_ == 0) {
    const uint32_t multi = dec.decode_symbol(zero_diff_);
    if (multi == 1) {
      last_diff_ = ic_gps_.decompress(dec, 0, 0);
      last_gps_ += static_cast<uint64_t>(static_cast<int64_t>(last_diff_));
    } else if (multi == 2) {
      last_gps_ = dec.read_int64();
    }
  } else {
    const uint32_t multi = dec.decode_symbol(multi_);
    if (multi < kGpsMultiMaxV1 - 2) {
      int32_t gps_diff;
      if (multi == 1) {
        gps_diff = ic_gps_.decompress(dec, last_diff_, 1);
        last_diff_ = gps_diff;
        multi_extreme_ = 0;
      } else if (multi == 0) {
        gps_diff = ic_gps_.decompress(dec, last_diff_ / 4, 2);
        if (++multi_extreme_ > 3) {
          last_diff_ = gps_diff;
          multi_extreme_ = 0;
        }
      } else {
        gps_diff = ic_gps_.decompress(dec, wrap_mul(last_diff_, static_cast<int32_t>(multi)),
                                      multi < 10 ? 3 : multi < 50 ? 4 : 5);
        if (multi == kGpsMultiMaxV1 - 3 && ++multi_extreme_ > 3) {
          last_diff_ = gps_diff;
          multi_extreme_ = 0;
        }
      }
      last_gps_ += static_cast<uint64_t>(static_cast<int64_t>(gps_diff));
    } else if (multi < kGpsMultiMaxV1 - 1) {
      last_gps_ = dec.read_int64();
    }
  }
  put<uint64_t>(item, last_gps_);
}

// ------------------------------------------------------------------ RGB12 v1

Rgb12V1::Rgb12V1() { ic_rgb_.setup(8, 6); }

void Rgb12V1::init(const uint8_t* first) {
  byte_used_.init(64);
  ic_rgb_.init();
  for (int c = 0; c < 3; ++c) last_[c] = get<uint16_t>(first + 2 * c);
}

void Rgb12V1::read(Decoder& dec, uint8_t* item) {
  // Bit 2c / 2c+1 of `used`: the low / high byte of component c changed.
  const uint32_t used = dec.decode_symbol(byte_used_);
  for (uint32_t c = 0; c < 3; ++c) {
    uint16_t v = (used & (1u << (2 * c)))
                     ? static_cast<uint16_t>(ic_rgb_.decompress(dec, last_[c] & 255, 2 * c))
                     : static_cast<uint16_t>(last_[c] & 255);
    if (used & (1u << (2 * c + 1)))
      v |= static_cast<uint16_t>(ic_rgb_.decompress(dec, last_[c] >> 8, 2 * c + 1) << 8);
    else
      v |= static_cast<uint16_t>(last_[c] & 0xFF00);
    last_[c] = v;
    put<uint16_t>(item + 2 * c, v);
  }
}

// ------------------------------------------------------------------- BYTE v2

BytesV2::BytesV2(uint32_t count) : last_(count), models_(count) {}

void BytesV2::init(const uint8_t* first) {
  for (SymbolModel& m : models_) m.init(256);
  std::memcpy(last_.data(), first, last_.size());
}

void BytesV2::read(Decoder& dec, uint8_t* item) {
  for (size_t i = 0; i < last_.size(); ++i) {
    last_[i] = fold_u8(last_[i] + static_cast<int32_t>(dec.decode_symbol(models_[i])));
    item[i] = last_[i];
  }
}

// ------------------------------------------------------------------ BYTE v1

BytesV1::BytesV1(uint32_t count) : last_(count) { ic_byte_.setup(8, count); }

void BytesV1::init(const uint8_t* first) {
  ic_byte_.init();
  std::memcpy(last_.data(), first, last_.size());
}

void BytesV1::read(Decoder& dec, uint8_t* item) {
  for (size_t i = 0; i < last_.size(); ++i) {
    // The 8-bit corrector range wraps the value into 0..255.
    last_[i] = static_cast<uint8_t>(
        ic_byte_.decompress(dec, last_[i], static_cast<uint32_t>(i)));
    item[i] = last_[i];
  }
}

// ------------------------------------------------------------ WAVEPACKET13

WavePacket13::WavePacket13() {
  ic_offset_diff_.setup(32, 1);
  ic_size_.setup(32, 1);
  ic_return_point_.setup(32, 1);
  ic_xyz_.setup(32, 3);
}

void WavePacket13::init(const uint8_t* first) {
  index_.init(256);
  for (SymbolModel& m : offset_cases_) m.init(4);
  ic_offset_diff_.init();
  ic_size_.init();
  ic_return_point_.init();
  ic_xyz_.init();
  last_offset_diff_ = 0;
  offset_case_ = 0;
  std::memcpy(last_.data(), first, last_.size());
}

void WavePacket13::read(Decoder& dec, uint8_t* item) {
  const uint8_t* last = last_.data();
  item[0] = static_cast<uint8_t>(dec.decode_symbol(index_));
  // The waveform's offset: the same as the last packet's, right after it,
  // a coded difference to it, or raw.
  offset_case_ = dec.decode_symbol(offset_cases_[offset_case_]);
  const uint64_t last_offset = get<uint64_t>(last + 1);
  const uint32_t last_size = get<uint32_t>(last + 9);
  uint64_t offset;
  if (offset_case_ == 0) {
    offset = last_offset;
  } else if (offset_case_ == 1) {
    offset = last_offset + last_size;
  } else if (offset_case_ == 2) {
    last_offset_diff_ = ic_offset_diff_.decompress(dec, last_offset_diff_);
    offset = last_offset + static_cast<uint64_t>(static_cast<int64_t>(last_offset_diff_));
  } else {
    offset = dec.read_int64();
  }
  put<uint64_t>(item + 1, offset);
  put<int32_t>(item + 9, ic_size_.decompress(dec, static_cast<int32_t>(last_size)));
  // The float fields are predicted by their bit patterns.
  put<int32_t>(item + 13, ic_return_point_.decompress(dec, get<int32_t>(last + 13)));
  for (uint32_t c = 0; c < 3; ++c)
    put<int32_t>(item + 17 + 4 * c, ic_xyz_.decompress(dec, get<int32_t>(last + 17 + 4 * c), c));
  std::memcpy(last_.data(), item, last_.size());
}

}  // namespace pointnpr::laz

// ------------------------------------------------- point-wise chunk decoder

namespace pointnpr::laz {
namespace {

// The items of formats 0-5 in their fixed order, version V (1 or 2).
template <class P10, class Gps, class Rgb, class Bytes>
class PointwiseDecoder final : public ChunkDecoder {
 public:
  PointwiseDecoder(const LaszipVlr& vlr, size_t rl) : rl_(rl) {
    size_t at = 0;
    for (const Item& it : vlr.items) {
      switch (it.type) {
        case kPoint10: break;
        case kGpsTime11: gps_.emplace(); gps_at_ = at; break;
        case kRgb12: rgb_.emplace(); rgb_at_ = at; break;
        case kWavePacket13: wave_.emplace(); wave_at_ = at; break;
        case kByte: bytes_.emplace(it.size); bytes_at_ = at; break;
        default: break;  // check_items() allowed no other
      }
      at += it.size;
    }
  }

  bool self_delimiting() const override { return false; }

  uint64_t decode(const uint8_t* begin, const uint8_t* end, uint64_t points, uint64_t,
                  uint8_t* out, const uint8_t** consumed, bool check_end) override {
    if (points == 0) {
      *consumed = begin;
      return 0;
    }
    if (static_cast<size_t>(end - begin) < rl_)
      throw FormatError("its " + std::to_string(end - begin) +
                            " bytes cannot hold the first point uncompressed",
                        -1);
    // The first point is stored raw; it seeds every item's context.
    std::memcpy(out, begin, rl_);
    p10_.init(out);
    if (gps_) gps_->init(out + gps_at_);
    if (rgb_) rgb_->init(out + rgb_at_);
    if (wave_) wave_->init(out + wave_at_);
    if (bytes_) bytes_->init(out + bytes_at_);
    Decoder dec(begin + rl_, end);
    uint8_t* rec = out;
    for (uint64_t i = 1; i < points; ++i) {
      rec += rl_;
      p10_.read(dec, rec);
      if (gps_) gps_->read(dec, rec + gps_at_);
      if (rgb_) rgb_->read(dec, rec + rgb_at_);
      if (wave_) wave_->read(dec, rec + wave_at_);
      if (bytes_) bytes_->read(dec, rec + bytes_at_);
      if (dec.overrun() > kOverrunSlack) [[unlikely]]
        throw FormatError("its data ends after " + std::to_string(i) + " of " +
                              std::to_string(points) + " points (truncated or corrupt)",
                          -1);
    }
    // A valid stream ends exactly where the encoder stopped; a corrupt one
    // drifts and ends elsewhere (or with a chunk table that lies about it).
    if (dec.overrun() != 0 || (check_end && dec.remaining() != 0))
      throw FormatError("its compressed data does not end where the chunk does (" +
                            std::to_string(dec.remaining()) + " bytes left, " +
                            std::to_string(dec.overrun()) + " read past)",
                        -1);
    *consumed = dec.position();
    return points;
  }

 private:
  // Reads past the chunk's end show a stream cut short; the encoder's
  // closing bytes make a valid stream end exactly at its chunk's end.
  static constexpr size_t kOverrunSlack = 4;
  size_t rl_;
  P10 p10_;
  std::optional<Gps> gps_;
  std::optional<Rgb> rgb_;
  std::optional<WavePacket13> wave_;
  std::optional<Bytes> bytes_;
  size_t gps_at_ = 0, rgb_at_ = 0, wave_at_ = 0, bytes_at_ = 0;
};

}  // namespace

std::unique_ptr<ChunkDecoder> make_pointwise_decoder(const LaszipVlr& vlr, size_t rl) {
  // LASzip writes one version for all items of a file; mixed ones are refused.
  const uint16_t v = vlr.items.front().version;
  for (const Item& it : vlr.items)
    if (it.version != v)
      throw FormatError("LAZ items mix versions " + std::to_string(v) + " and " +
                            std::to_string(it.version),
                        -1);
  if (v == 1)
    return std::make_unique<PointwiseDecoder<Point10V1, GpsTime11V1, Rgb12V1, BytesV1>>(vlr, rl);
  return std::make_unique<PointwiseDecoder<Point10V2, GpsTime11V2, Rgb12V2, BytesV2>>(vlr, rl);
}

}  // namespace pointnpr::laz
