// LASzip layered chunked compression (LAS 1.4 point formats 6-10): items
// POINT14, RGB14, RGBNIR14, BYTE14 (versions 3 and 4); WAVEPACKET14 is read
// past.
//
// A layered chunk holds its first point raw, its point count, the byte size
// of every layer, then the layers: each field group (x/y with returns and
// channel, z, classification, flags, intensity, ...) is coded in a stream of
// its own, so a layer whose field never changes in the chunk is empty. All
// state is kept per scanner channel (up to 4 "contexts"), because points of
// different channels interleave in time.
#include <cstring>
#include <optional>

#include "io/laz_items.h"
#include "io/laz_reader.h"

namespace pointnpr::laz {
namespace {


// (number of returns, return number) -> one of 6 contexts for x/y, and the
// level (8 contexts) for z.
constexpr uint8_t kReturnMap6[16][16] = {
    {0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5}, {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
    {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3}, {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
    {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4}, {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
    {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4}, {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
    {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
    {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5}, {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5}};
constexpr uint8_t kReturnLevel8[16][16] = {
    {0, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7, 7, 7, 7, 7, 7}, {1, 0, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7, 7, 7, 7, 7},
    {2, 1, 0, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7, 7, 7, 7}, {3, 2, 1, 0, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7, 7, 7},
    {4, 3, 2, 1, 0, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7, 7}, {5, 4, 3, 2, 1, 0, 1, 2, 3, 4, 5, 6, 7, 7, 7, 7},
    {6, 5, 4, 3, 2, 1, 0, 1, 2, 3, 4, 5, 6, 7, 7, 7}, {7, 6, 5, 4, 3, 2, 1, 0, 1, 2, 3, 4, 5, 6, 7, 7},
    {7, 7, 6, 5, 4, 3, 2, 1, 0, 1, 2, 3, 4, 5, 6, 7}, {7, 7, 7, 6, 5, 4, 3, 2, 1, 0, 1, 2, 3, 4, 5, 6},
    {7, 7, 7, 7, 6, 5, 4, 3, 2, 1, 0, 1, 2, 3, 4, 5}, {7, 7, 7, 7, 7, 6, 5, 4, 3, 2, 1, 0, 1, 2, 3, 4},
    {7, 7, 7, 7, 7, 7, 6, 5, 4, 3, 2, 1, 0, 1, 2, 3}, {7, 7, 7, 7, 7, 7, 7, 6, 5, 4, 3, 2, 1, 0, 1, 2},
    {7, 7, 7, 7, 7, 7, 7, 7, 6, 5, 4, 3, 2, 1, 0, 1}, {7, 7, 7, 7, 7, 7, 7, 7, 7, 6, 5, 4, 3, 2, 1, 0}};

constexpr int32_t kGpsMulti = 500;
constexpr int32_t kGpsMultiMinus = -10;
constexpr int32_t kGpsMultiCodeFull = kGpsMulti - kGpsMultiMinus + 1;  // 511
constexpr int32_t kGpsMultiTotal = kGpsMulti - kGpsMultiMinus + 5;     // 515

// One arithmetic-coded layer of a chunk; empty layers are not decoded.
struct Layer {
  Decoder dec;
  bool present = false;
  void open(const uint8_t* begin, uint32_t size) {
    present = size > 0;
    if (present) dec.init(begin, begin + size);
  }
};

// ---------------------------------------------------------------- POINT14
// Record: x y z (int32) intensity (u16) returns (u8: number<<4 | return)
// flags (u8: edge<<7 | scan direction<<6 | channel<<4 | class flags)
// classification user_data (u8) scan_angle (i16) point_source (u16) gps (f64).
class Point14 {
 public:
  enum { kXY, kZ, kClass, kFlags, kIntensity, kScanAngle, kUserData, kSource, kGps, kLayers };
  Layer layers[kLayers];

  // Starts a chunk at its first point; returns the point's scanner channel.
  uint32_t init(const uint8_t* first) {
    for (Context& c : ctx_) c.unused = true;
    current_ = (first[15] >> 4) & 3;
    ctx_[current_].start_from(first);
    return current_;
  }

  // Decodes the next point into `item`; returns its scanner channel.
  uint32_t read(uint8_t* item) {
    Context* c = &ctx_[current_];
    Decoder& xy = layers[kXY].dec;
    const uint32_t changed = xy.decode_symbol(c->changed_values[c->last_point_return()]);
    if (changed & 64) {  // scanner channel changed
      const uint32_t diff = xy.decode_symbol(c->scanner_channel);
      const uint32_t channel = (current_ + diff + 1) & 3;
      if (ctx_[channel].unused) ctx_[channel].start_from(c->last);
      current_ = channel;
      c = &ctx_[channel];
      c->last[15] = static_cast<uint8_t>((c->last[15] & ~0x30) | (channel << 4));
    }
    uint8_t* last = c->last;
    const bool source_changed = changed & 32;
    const bool gps_changed = changed & 16;
    const bool scan_angle_changed = changed & 8;

    const uint32_t last_n = last[14] >> 4, last_r = last[14] & 15;
    const uint32_t n = (changed & 4) ? xy.decode_symbol(c->number_of_returns[last_n]) & 15 : last_n;
    uint32_t r;
    switch (changed & 3) {
      case 0: r = last_r; break;
      case 1: r = (last_r + 1) & 15; break;
      case 2: r = (last_r + 15) & 15; break;
      default:
        if (gps_changed) r = xy.decode_symbol(c->return_number[last_r]) & 15;
        else r = (last_r + xy.decode_symbol(c->return_number_gps_same) + 2) & 15;
    }
    last[14] = static_cast<uint8_t>((n << 4) | r);
    const uint32_t m = kReturnMap6[n][r], l = kReturnLevel8[n][r];
    const uint32_t cpr = (r == 1 ? 2 : 0) + (r >= n ? 1 : 0);  // first / last return

    const uint32_t idx = (m << 1) | (gps_changed ? 1 : 0);
    int32_t diff = c->ic_dx.decompress(xy, c->x_diff[idx].get(), n == 1);
    put<int32_t>(last, wrap_add(get<int32_t>(last), diff));
    c->x_diff[idx].add(diff);
    uint32_t k = c->ic_dx.k();
    diff = c->ic_dy.decompress(xy, c->y_diff[idx].get(), (n == 1) + (k < 20 ? k & ~1u : 20));
    put<int32_t>(last + 4, wrap_add(get<int32_t>(last + 4), diff));
    c->y_diff[idx].add(diff);

    if (layers[kZ].present) {
      k = (c->ic_dx.k() + c->ic_dy.k()) / 2;
      const int32_t z =
          c->ic_z.decompress(layers[kZ].dec, c->last_z[l], (n == 1) + (k < 18 ? k & ~1u : 18));
      put<int32_t>(last + 8, z);
      c->last_z[l] = z;
    }
    if (layers[kClass].present) {
      const uint32_t ccc = ((last[16] & 0x1Fu) << 1) + (cpr == 3 ? 1 : 0);
      last[16] = static_cast<uint8_t>(layers[kClass].dec.decode_symbol(c->classification[ccc]));
    }
    if (layers[kFlags].present) {
      const uint32_t last_flags = ((last[15] >> 7) << 5) | (((last[15] >> 6) & 1) << 4) | (last[15] & 15);
      const uint32_t f = layers[kFlags].dec.decode_symbol(c->flags[last_flags]);
      last[15] = static_cast<uint8_t>((((f >> 5) & 1) << 7) | (((f >> 4) & 1) << 6) |
                                      (last[15] & 0x30) | (f & 15));
    }
    if (layers[kIntensity].present) {
      const uint32_t i = (cpr << 1) | (gps_changed ? 1 : 0);
      const auto v = static_cast<uint16_t>(
          c->ic_intensity.decompress(layers[kIntensity].dec, c->last_intensity[i], cpr));
      put<uint16_t>(last + 12, v);
      c->last_intensity[i] = v;
    }
    if (layers[kScanAngle].present && scan_angle_changed)
      put<int16_t>(last + 18, static_cast<int16_t>(c->ic_scan_angle.decompress(
                                  layers[kScanAngle].dec, get<int16_t>(last + 18), gps_changed)));
    if (layers[kUserData].present)
      last[17] = static_cast<uint8_t>(layers[kUserData].dec.decode_symbol(c->user_data[last[17] / 4]));
    if (layers[kSource].present && source_changed)
      put<uint16_t>(last + 20, static_cast<uint16_t>(c->ic_source.decompress(
                                   layers[kSource].dec, get<uint16_t>(last + 20))));
    c->gps_change = gps_changed;
    if (layers[kGps].present && gps_changed) {
      read_gps(*c, layers[kGps].dec);
      put<uint64_t>(last + 22, c->gps_time[c->gps_last]);
    }
    std::memcpy(item, last, 30);
    return current_;
  }

 private:
  struct Context {
    bool unused = true;
    uint8_t last[30];
    bool gps_change = false;
    uint16_t last_intensity[8];
    Median5 x_diff[12], y_diff[12];
    int32_t last_z[8];
    SymbolModel changed_values[8];
    SymbolModel scanner_channel, return_number_gps_same, gps_multi, gps_no_diff;
    LazyModels number_of_returns{16}, return_number{16}, classification{256}, flags{64},
        user_data{256};
    IntegerDecompressor ic_dx{32, 2}, ic_dy{32, 22}, ic_z{32, 20}, ic_intensity{16, 4},
        ic_scan_angle{16, 2}, ic_source{16, 1}, ic_gps{32, 9};
    uint32_t gps_last = 0, gps_next = 0;
    uint64_t gps_time[4];
    int32_t gps_diff[4], gps_extreme[4];

    // Fresh models, predictions seeded from `point`.
    void start_from(const uint8_t* point) {
      unused = false;
      std::memmove(last, point, 30);
      gps_change = false;
      for (uint16_t& v : last_intensity) v = get<uint16_t>(point + 12);
      for (int i = 0; i < 12; ++i) x_diff[i] = y_diff[i] = Median5{};
      for (int32_t& z : last_z) z = get<int32_t>(point + 8);
      for (SymbolModel& cv : changed_values) cv.init(128);
      scanner_channel.init(3);
      return_number_gps_same.init(13);
      gps_multi.init(kGpsMultiTotal);
      gps_no_diff.init(5);
      number_of_returns.reset();
      return_number.reset();
      classification.reset();
      flags.reset();
      user_data.reset();
      for (IntegerDecompressor* ic : {&ic_dx, &ic_dy, &ic_z, &ic_intensity, &ic_scan_angle,
                                      &ic_source, &ic_gps})
        ic->init();
      gps_last = gps_next = 0;
      gps_time[0] = get<uint64_t>(point + 22);
      gps_time[1] = gps_time[2] = gps_time[3] = 0;
      for (int i = 0; i < 4; ++i) gps_diff[i] = gps_extreme[i] = 0;
    }
    // Single (3) / first (1) / last (2) / intermediate (0) return of the
    // last point, +4 if its GPS time changed.
    uint32_t last_point_return() const {
      const uint32_t r = last[14] & 15, n = last[14] >> 4;
      return (r == 1 ? 1 : 0) + (r >= n ? 2 : 0) + (gps_change ? 4 : 0);
    }
  };

  static void read_gps(Context& c, Decoder& dec) {
    auto full_time = [&] {
      c.gps_next = (c.gps_next + 1) & 3;
      const auto high = static_cast<uint32_t>(
          c.ic_gps.decompress(dec, static_cast<int32_t>(c.gps_time[c.gps_last] >> 32), 8));
      c.gps_time[c.gps_next] = (static_cast<uint64_t>(high) << 32) | dec.read_int();
      c.gps_last = c.gps_next;
      c.gps_diff[c.gps_last] = 0;
      c.gps_extreme[c.gps_last] = 0;
    };
    for (int switches = 0;; ++switches) {
      if (switches > 8)
        throw FormatError("the GPS time stream switches sequences without end", -1);
      const uint32_t s = c.gps_last;
      if (c.gps_diff[s] == 0) {
        const int32_t multi = static_cast<int32_t>(dec.decode_symbol(c.gps_no_diff));
        if (multi == 0) {
          c.gps_diff[s] = c.ic_gps.decompress(dec, 0, 0);
          c.gps_time[s] += static_cast<uint64_t>(static_cast<int64_t>(c.gps_diff[s]));
          c.gps_extreme[s] = 0;
        } else if (multi == 1) {
          full_time();
        } else {
          c.gps_last = (s + static_cast<uint32_t>(multi) - 1) & 3;
          continue;
        }
      } else {
        int32_t multi = static_cast<int32_t>(dec.decode_symbol(c.gps_multi));
        if (multi == 1) {
          c.gps_time[s] += static_cast<uint64_t>(
              static_cast<int64_t>(c.ic_gps.decompress(dec, c.gps_diff[s], 1)));
          c.gps_extreme[s] = 0;
        } else if (multi < kGpsMultiCodeFull) {
          int32_t d;
          auto extreme = [&] {
            if (++c.gps_extreme[s] > 3) {
              c.gps_diff[s] = d;
              c.gps_extreme[s] = 0;
            }
          };
          if (multi == 0) {
            d = c.ic_gps.decompress(dec, 0, 7);
            extreme();
          } else if (multi < kGpsMulti) {
            d = c.ic_gps.decompress(dec, wrap_mul(multi, c.gps_diff[s]), multi < 10 ? 2 : 3);
          } else if (multi == kGpsMulti) {
            d = c.ic_gps.decompress(dec, wrap_mul(kGpsMulti, c.gps_diff[s]), 4);
            extreme();
          } else {
            multi = kGpsMulti - multi;
            if (multi > kGpsMultiMinus) {
              d = c.ic_gps.decompress(dec, wrap_mul(multi, c.gps_diff[s]), 5);
            } else {
              d = c.ic_gps.decompress(dec, wrap_mul(kGpsMultiMinus, c.gps_diff[s]), 6);
              extreme();
            }
          }
          c.gps_time[s] += static_cast<uint64_t>(static_cast<int64_t>(d));
        } else if (multi == kGpsMultiCodeFull) {
          full_time();
        } else {
          c.gps_last = (s + static_cast<uint32_t>(multi - kGpsMultiCodeFull)) & 3;
          continue;
        }
      }
      return;
    }
  }

  Context ctx_[4];
  uint32_t current_ = 0;
};

// Per-channel state of the layered colour, NIR and extra-byte items.
// Version 3 keeps predicting from the previous channel's value when a
// channel seen before comes back (a quirk of LASzip that files carry);
// version 4 uses the channel's own.
template <class Models, size_t N>
class ChannelState {
 public:
  explicit ChannelState(int version) : version_(version) {}
  void init(const uint8_t* first, uint32_t channel) {
    for (bool& u : unused_) u = true;
    std::memcpy(last_[channel], first, N);
    unused_[channel] = false;
    models_[channel].init();
    current_ = channel;
  }
  // The models and the last value to predict from for a point of `channel`.
  std::pair<Models*, uint8_t*> select(uint32_t channel) {
    uint32_t last_idx = current_;
    if (current_ != channel) {
      current_ = channel;
      if (unused_[channel]) {
        std::memcpy(last_[channel], last_[last_idx], N);
        models_[channel].init();
        unused_[channel] = false;
        if (version_ == 3) last_idx = channel;
      }
      if (version_ == 4) last_idx = channel;
    }
    return {&models_[current_], last_[last_idx]};
  }

 private:
  int version_;
  Models models_[4];
  uint8_t last_[4][N];
  bool unused_[4] = {true, true, true, true};
  uint32_t current_ = 0;
};

struct RgbModels14 {
  RgbModels m;
  void init() { m.init(); }
};
struct NirModels {
  SymbolModel used, low, high;
  void init() {
    used.init(4);
    low.init(256);
    high.init(256);
  }
};

class Rgb14 {
 public:
  explicit Rgb14(int version) : state_(version) {}
  Layer layer;
  void init(const uint8_t* first, uint32_t channel) { state_.init(first, channel); }
  void read(uint8_t* item, uint32_t channel) {
    auto [models, last] = state_.select(channel);
    if (layer.present) {
      uint16_t rgb[3];
      std::memcpy(rgb, last, 6);
      decode_rgb_v2(layer.dec, models->m, rgb);
      std::memcpy(last, rgb, 6);
    }
    std::memcpy(item, last, 6);
  }

 private:
  ChannelState<RgbModels14, 6> state_;
};

class Nir14 {
 public:
  explicit Nir14(int version) : state_(version) {}
  Layer layer;
  void init(const uint8_t* first, uint32_t channel) { state_.init(first, channel); }
  void read(uint8_t* item, uint32_t channel) {
    auto [m, last] = state_.select(channel);
    if (layer.present) {
      Decoder& dec = layer.dec;
      const uint32_t used = dec.decode_symbol(m->used);
      if (used & 1) last[0] = fold_u8(last[0] + static_cast<int32_t>(dec.decode_symbol(m->low)));
      if (used & 2) last[1] = fold_u8(last[1] + static_cast<int32_t>(dec.decode_symbol(m->high)));
    }
    std::memcpy(item, last, 2);
  }

 private:
  ChannelState<NirModels, 2> state_;
};

class Bytes14 {
 public:
  Bytes14(int version, uint32_t count) : version_(version), n_(count), layers(count) {
    for (auto& c : ctx_) {
      c.models.resize(count);
      c.last.resize(count);
    }
  }
  void init(const uint8_t* first, uint32_t channel) {
    for (auto& c : ctx_) c.unused = true;
    start(ctx_[channel], first);
    current_ = channel;
  }
  void read(uint8_t* item, uint32_t channel) {
    uint32_t last_idx = current_;
    if (current_ != channel) {
      current_ = channel;
      if (ctx_[channel].unused) {
        start(ctx_[channel], ctx_[last_idx].last.data());
        if (version_ == 3) last_idx = channel;
      }
      if (version_ == 4) last_idx = channel;
    }
    uint8_t* last = ctx_[last_idx].last.data();
    std::vector<SymbolModel>& models = ctx_[current_].models;
    for (uint32_t i = 0; i < n_; ++i)
      if (layers[i].present)
        last[i] = fold_u8(last[i] + static_cast<int32_t>(layers[i].dec.decode_symbol(models[i])));
    std::memcpy(item, last, n_);
  }

 private:
  struct Context {
    bool unused = true;
    std::vector<SymbolModel> models;
    std::vector<uint8_t> last;
  };
  void start(Context& c, const uint8_t* first) {
    c.unused = false;
    std::memmove(c.last.data(), first, n_);
    for (SymbolModel& m : c.models) m.init(256);
  }
  int version_;
  uint32_t n_;
  Context ctx_[4];
  uint32_t current_ = 0;

 public:
  std::vector<Layer> layers;
};

class LayeredDecoder final : public ChunkDecoder {
 public:
  LayeredDecoder(const LaszipVlr& vlr, size_t rl) : rl_(rl) {
    size_t at = 0;
    for (const Item& it : vlr.items) {
      switch (it.type) {
        case kPoint14: break;
        case kRgb14: rgb_.emplace(it.version); rgb_at_ = at; break;
        case kRgbNir14:
          rgb_.emplace(it.version);
          nir_.emplace(it.version);
          rgb_at_ = at;
          nir_at_ = at + 6;
          break;
        case kByte14: bytes_.emplace(it.version, it.size); bytes_at_ = at; break;
        case kWavePacket14: wave_ = true; break;
        default: break;
      }
      at += it.size;
    }
  }

  bool self_delimiting() const override { return true; }

  uint64_t decode(const uint8_t* begin, const uint8_t* end, uint64_t points, uint64_t max_points,
                  uint8_t* out, const uint8_t** consumed, bool check_end) override {
    const uint8_t* p = begin;
    auto need = [&](size_t bytes, const char* what) {
      if (static_cast<size_t>(end - p) < bytes)
        throw FormatError(std::string("it ends inside its ") + what, -1);
    };
    need(rl_ + 4, "first point");
    std::memcpy(out, p, rl_);
    p += rl_;
    const uint32_t count = get<uint32_t>(p);
    p += 4;
    if (count == 0 || count > max_points || (points != 0 && count != points))
      throw FormatError("it declares " + std::to_string(count) + " points, expected " +
                            (points ? std::to_string(points)
                                    : "1 to " + std::to_string(max_points)),
                        -1);
    // Layer sizes of every item, then the layers in the same order.
    std::vector<std::pair<Layer*, uint32_t>> sizes;
    uint32_t wave_size = 0;
    auto size_of = [&](Layer* layer) {
      need(4, "layer sizes");
      const uint32_t s = get<uint32_t>(p);
      p += 4;
      if (layer) sizes.emplace_back(layer, s);
      return s;
    };
    for (Layer& l : p14_.layers) size_of(&l);
    if (rgb_) size_of(&rgb_->layer);
    if (nir_) size_of(&nir_->layer);
    if (wave_) wave_size = size_of(nullptr);
    if (bytes_)
      for (Layer& l : bytes_->layers) size_of(&l);
    // Layers follow in item order; the wave packets' layer sits between
    // the colours and the extra bytes.
    const size_t before_wave = p14_.kLayers + (rgb_ ? 1 : 0) + (nir_ ? 1 : 0);
    for (size_t i = 0; i < sizes.size(); ++i) {
      if (i == before_wave && wave_) {
        need(wave_size, "wave packet layer");
        p += wave_size;
      }
      need(sizes[i].second, "layers");
      sizes[i].first->open(p, sizes[i].second);
      p += sizes[i].second;
    }
    if (wave_ && sizes.size() == before_wave) {
      need(wave_size, "wave packet layer");
      p += wave_size;
    }
    if (!p14_.layers[Point14::kXY].present && count > 1)
      throw FormatError("its x/y layer is empty", -1);

    uint32_t channel = p14_.init(out);
    if (rgb_) rgb_->init(out + rgb_at_, channel);
    if (nir_) nir_->init(out + nir_at_, channel);
    if (bytes_) bytes_->init(out + bytes_at_, channel);
    uint8_t* rec = out;
    for (uint32_t i = 1; i < count; ++i) {
      rec += rl_;
      channel = p14_.read(rec);
      if (rgb_) rgb_->read(rec + rgb_at_, channel);
      if (nir_) nir_->read(rec + nir_at_, channel);
      if (bytes_) bytes_->read(rec + bytes_at_, channel);
    }
    for (auto& [layer, size] : sizes)
      if (layer->present &&
          (layer->dec.overrun() != 0 || layer->dec.remaining() != 0))
        throw FormatError("a layer's compressed data does not end where the layer does "
                          "(truncated or corrupt)",
                          -1);
    if (check_end && p != end)
      throw FormatError("its layers end " + std::to_string(end - p) +
                            " bytes before the chunk does", -1);
    *consumed = p;
    return count;
  }

 private:
  size_t rl_;
  Point14 p14_;
  std::optional<Rgb14> rgb_;
  std::optional<Nir14> nir_;
  std::optional<Bytes14> bytes_;
  bool wave_ = false;
  size_t rgb_at_ = 0, nir_at_ = 0, bytes_at_ = 0;
};

}  // namespace

std::unique_ptr<ChunkDecoder> make_layered_decoder(const LaszipVlr& vlr, size_t rl) {
  return std::make_unique<LayeredDecoder>(vlr, rl);
}

}  // namespace pointnpr::laz
