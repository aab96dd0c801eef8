#pragma once
// The entropy decoder of LASzip (LAZ): a 32-bit range decoder with adaptive
// binary and multi-symbol models, and the integer decompressor that codes
// a value as a prediction plus a corrector whose bit length k is coded
// first (Isenburg, "LASzip: lossless compression of LiDAR data", 2013).
//
// The decoder must reproduce the encoder's model updates bit for bit, so the
// constants and rounding below are those of the format, not tuning choices.
// Everything a point decode touches is inline: a LAZ point costs some 10-30
// symbol decodes, and a call per symbol would dominate.
#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <vector>

namespace pointnpr::laz {

// Adaptive probability of a binary event.
struct BitModel {
  static constexpr uint32_t kLengthShift = 13;
  static constexpr uint32_t kMaxCount = 1u << kLengthShift;
  uint32_t bit_0_count = 1, bit_count = 2;
  uint32_t bit_0_prob = 1u << (kLengthShift - 1);
  uint32_t update_cycle = 4, bits_until_update = 4;
  void update();
};

// Adaptive distribution over `symbols` values (2..2048).
class SymbolModel {
 public:
  static constexpr uint32_t kLengthShift = 15;
  static constexpr uint32_t kMaxCount = 1u << kLengthShift;
  // Models of kTableFrom symbols or more decode with a lookup table of
  // about as many entries as symbols (at least 8): it narrows the search to
  // a symbol or two, instead of a bisection whose data-dependent branches
  // mispredict. The table is the decoder's own (the encoder has none), so
  // its size is free to choose; LASzip's of a quarter of the symbols from
  // 17 symbols decodes some 10% slower here.
  static constexpr uint32_t kTableFrom = 8;

  SymbolModel() = default;
  explicit SymbolModel(uint32_t n) { init(n); }
  void init(uint32_t symbols);
  void update();

  uint32_t symbols = 0, last_symbol = 0;
  uint32_t table_shift = 0, table_size = 0;
  uint32_t total_count = 0, update_cycle = 0, symbols_until_update = 0;
  std::vector<uint32_t> distribution, symbol_count;
  std::vector<uint16_t> decoder_table;  // symbols < 2048: half the cache lines
};

// Range decoder over [begin, end). Reads past `end` return zero bytes and are
// counted, so a truncated or corrupt stream can never read out of bounds;
// the caller checks overrun() when the chunk is done.
class Decoder {
 public:
  static constexpr uint32_t kMinLength = 0x01000000u;
  static constexpr uint32_t kMaxLength = 0xFFFFFFFFu;

  Decoder() = default;
  Decoder(const uint8_t* begin, const uint8_t* end) { init(begin, end); }
  void init(const uint8_t* begin, const uint8_t* end) {
    p_ = begin;
    end_ = end;
    overrun_ = 0;
    length_ = kMaxLength;
    value_ = 0;
    for (int i = 0; i < 4; ++i) value_ = (value_ << 8) | next_byte();
  }

  // Bytes consumed so far (the encoder writes exactly what the decoder reads).
  const uint8_t* position() const { return p_; }
  size_t overrun() const { return overrun_; }
  size_t remaining() const { return static_cast<size_t>(end_ - p_); }

  uint32_t decode_bit(BitModel& m) {
    const uint32_t x = m.bit_0_prob * (length_ >> BitModel::kLengthShift);
    uint32_t sym;
    if (value_ < x) {
      sym = 0;
      length_ = x;
      ++m.bit_0_count;
    } else {
      sym = 1;
      value_ -= x;
      length_ -= x;
    }
    if (length_ < kMinLength) renormalize();
    if (--m.bits_until_update == 0) m.update();
    return sym;
  }

  uint32_t decode_symbol(SymbolModel& m) {
    uint32_t n, sym, x, y = length_;
    const uint32_t* dist = m.distribution.data();
    if (m.table_size) {
      length_ >>= SymbolModel::kLengthShift;
      const uint32_t dv = value_ / length_;
      // Only a corrupt stream lets dv reach past the table; clamp so it
      // decodes garbage instead of reading out of bounds.
      const uint32_t t = std::min(dv >> m.table_shift, m.table_size);
      sym = m.decoder_table[t];
      n = m.decoder_table[t + 1] + 1;
      while (n > sym + 1) {  // bisection inside the table's bracket
        const uint32_t k = (sym + n) >> 1;
        if (dist[k] > dv) n = k; else sym = k;
      }
      x = dist[sym] * length_;
      if (sym != m.last_symbol) y = dist[sym + 1] * length_;
    } else {
      x = sym = 0;
      length_ >>= SymbolModel::kLengthShift;
      n = m.symbols;
      uint32_t k = n >> 1;
      do {
        const uint32_t z = length_ * dist[k];
        if (z > value_) {
          n = k;
          y = z;
        } else {
          sym = k;
          x = z;
        }
      } while ((k = (sym + n) >> 1) != sym);
    }
    value_ -= x;
    length_ = y - x;
    if (length_ < kMinLength) renormalize();
    ++m.symbol_count[sym];
    if (--m.symbols_until_update == 0) m.update();
    return sym;
  }

  // `bits` raw bits (1..32), uniformly distributed.
  uint32_t read_bits(uint32_t bits) {
    if (bits > 19) {
      const uint32_t low = read_short();
      return (read_bits(bits - 16) << 16) | low;
    }
    length_ >>= bits;
    uint32_t sym = value_ / length_;
    value_ -= length_ * sym;
    if (length_ < kMinLength) renormalize();
    return sym;
  }
  uint32_t read_short() {
    length_ >>= 16;
    uint32_t sym = value_ / length_;
    value_ -= length_ * sym;
    if (length_ < kMinLength) renormalize();
    return sym;
  }
  uint32_t read_int() {
    const uint32_t low = read_short();
    return (read_short() << 16) | low;
  }
  uint64_t read_int64() {
    const uint64_t low = read_int();
    return (static_cast<uint64_t>(read_int()) << 32) | low;
  }

 private:
  uint32_t next_byte() {
    if (p_ < end_) return *p_++;
    ++overrun_;
    return 0;
  }
  void renormalize() {
    do {
      value_ = (value_ << 8) | next_byte();
    } while ((length_ <<= 8) < kMinLength);
  }

  const uint8_t* p_ = nullptr;
  const uint8_t* end_ = nullptr;
  size_t overrun_ = 0;
  uint32_t value_ = 0, length_ = kMaxLength;
};

// Integer decompressor: real = prediction + corrector, the corrector coded
// as its bit length k (one model per context) then its bits (a model per k
// up to `bits_high`, raw bits beyond), wrapped into the corrector range.
class IntegerDecompressor {
 public:
  IntegerDecompressor() = default;
  IntegerDecompressor(uint32_t bits, uint32_t contexts, uint32_t bits_high = 8,
                      uint32_t range = 0) {
    setup(bits, contexts, bits_high, range);
  }
  void setup(uint32_t bits, uint32_t contexts, uint32_t bits_high = 8, uint32_t range = 0);
  // Resets every model (start of a chunk).
  void init();

  int32_t decompress(Decoder& dec, int32_t pred, uint32_t context = 0) {
    const int32_t corr = read_corrector(dec, m_bits_[context]);
    // Two's-complement wrap, as the encoder computed it.
    uint32_t real = static_cast<uint32_t>(pred) + static_cast<uint32_t>(corr);
    if (corr_range_ != 0) {
      if (static_cast<int32_t>(real) < 0) real += corr_range_;
      else if (real >= corr_range_) real -= corr_range_;
    }
    return static_cast<int32_t>(real);
  }
  // Bit length of the last corrector (a context for the next field).
  uint32_t k() const { return k_; }

 private:
  int32_t read_corrector(Decoder& dec, SymbolModel& m_bits) {
    k_ = dec.decode_symbol(m_bits);
    if (k_ == 0) return static_cast<int32_t>(dec.decode_bit(corrector0_));
    if (k_ >= 32) return corr_min_;
    int32_t c;
    if (k_ <= bits_high_) {
      c = static_cast<int32_t>(dec.decode_symbol(corrector_[k_ - 1]));
    } else {
      const uint32_t k1 = k_ - bits_high_;
      const uint32_t high = dec.decode_symbol(corrector_[k_ - 1]);
      const uint32_t low = dec.read_bits(k1);
      c = static_cast<int32_t>((high << k1) | low);
    }
    // c in [0, 2^(k-1)) stands for [-(2^k - 1), -2^(k-1)]; the rest for [2^(k-1) + 1, 2^k].
    const uint32_t half = 1u << (k_ - 1);
    if (static_cast<uint32_t>(c) >= half)
      return static_cast<int32_t>(static_cast<uint32_t>(c) + 1u);
    return static_cast<int32_t>(static_cast<uint32_t>(c) - ((1u << k_) - 1u));
  }

  uint32_t k_ = 0;
  uint32_t contexts_ = 1, bits_high_ = 8, corr_bits_ = 16, corr_range_ = 0;
  int32_t corr_min_ = 0;
  std::vector<SymbolModel> m_bits_;
  BitModel corrector0_;
  std::vector<SymbolModel> corrector_;  // index k - 1
};

// Wrap-around helpers of the format (byte differences are taken mod 256).
inline uint8_t fold_u8(int32_t n) { return static_cast<uint8_t>(n); }
inline int32_t clamp_u8(int32_t n) { return n < 0 ? 0 : (n > 255 ? 255 : n); }

}  // namespace pointnpr::laz
