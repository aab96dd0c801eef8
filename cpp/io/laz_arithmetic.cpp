// Model adaptation and integer decompressor set-up of the LASzip entropy
// decoder (see laz_arithmetic.h). These run once every few symbols or once
// per chunk, so they stay out of line.
#include "io/laz_arithmetic.h"

namespace pointnpr::laz {

void BitModel::update() {
  // Halve the counts when they grow too large, so the model keeps adapting.
  if ((bit_count += update_cycle) > kMaxCount) {
    bit_count = (bit_count + 1) >> 1;
    bit_0_count = (bit_0_count + 1) >> 1;
    if (bit_0_count == bit_count) ++bit_count;
  }
  const uint32_t scale = 0x80000000u / bit_count;
  bit_0_prob = (bit_0_count * scale) >> (31 - kLengthShift);
  update_cycle = (5 * update_cycle) >> 2;
  if (update_cycle > 64) update_cycle = 64;
  bits_until_update = update_cycle;
}

void SymbolModel::init(uint32_t n) {
  symbols = n;
  last_symbol = n - 1;
  if (n >= kTableFrom) {
    uint32_t table_bits = 3;
    while (n > (1u << table_bits)) ++table_bits;
    table_size = 1u << table_bits;
    table_shift = kLengthShift - table_bits;
    decoder_table.assign(table_size + 2, 0);
  } else {
    table_size = table_shift = 0;
    decoder_table.clear();
  }
  distribution.assign(n, 0);
  symbol_count.assign(n, 1);
  total_count = 0;
  update_cycle = n;
  update();
  symbols_until_update = update_cycle = (n + 6) >> 1;
}

void SymbolModel::update() {
  if ((total_count += update_cycle) > kMaxCount) {
    total_count = 0;
    for (uint32_t k = 0; k < symbols; ++k) {
      symbol_count[k] = (symbol_count[k] + 1) >> 1;
      total_count += symbol_count[k];
    }
  }
  const uint32_t scale = 0x80000000u / total_count;
  uint32_t sum = 0;
  if (table_size == 0) {
    for (uint32_t k = 0; k < symbols; ++k) {
      distribution[k] = (scale * sum) >> (31 - kLengthShift);
      sum += symbol_count[k];
    }
  } else {
    uint32_t s = 0;
    for (uint32_t k = 0; k < symbols; ++k) {
      distribution[k] = (scale * sum) >> (31 - kLengthShift);
      sum += symbol_count[k];
      const uint32_t w = distribution[k] >> table_shift;
      while (s < w) decoder_table[++s] = static_cast<uint16_t>(k - 1);
    }
    decoder_table[0] = 0;
    while (s <= table_size) decoder_table[++s] = static_cast<uint16_t>(symbols - 1);
  }
  update_cycle = (5 * update_cycle) >> 2;
  const uint32_t max_cycle = (symbols + 6) << 3;
  if (update_cycle > max_cycle) update_cycle = max_cycle;
  symbols_until_update = update_cycle;
}

void IntegerDecompressor::setup(uint32_t bits, uint32_t contexts, uint32_t bits_high,
                                uint32_t range) {
  contexts_ = contexts;
  bits_high_ = bits_high;
  if (range) {
    corr_bits_ = 0;
    corr_range_ = range;
    while (range) {
      range >>= 1;
      ++corr_bits_;
    }
    if (corr_range_ == (1u << (corr_bits_ - 1))) --corr_bits_;
    corr_min_ = -static_cast<int32_t>(corr_range_ / 2);
  } else if (bits && bits < 32) {
    corr_bits_ = bits;
    corr_range_ = 1u << bits;
    corr_min_ = -static_cast<int32_t>(corr_range_ / 2);
  } else {
    corr_bits_ = 32;
    corr_range_ = 0;
    corr_min_ = INT32_MIN;
  }
}

void IntegerDecompressor::init() {
  m_bits_.resize(contexts_);
  for (SymbolModel& m : m_bits_) m.init(corr_bits_ + 1);
  corrector0_ = BitModel{};
  corrector_.resize(corr_bits_);
  for (uint32_t i = 1; i <= corr_bits_; ++i)
    corrector_[i - 1].init(i <= bits_high_ ? (1u << i) : (1u << bits_high_));
}

}  // namespace pointnpr::laz
