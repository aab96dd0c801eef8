#pragma once
// Decoders of the LASzip item types: each turns the compressed stream back
// into the bytes of one part of a LAS point record (POINT10 = the 20 bytes
// shared by formats 0-5, GPSTIME11 = 8, RGB12 = 6, BYTE = extra bytes; the
// *14 items are the layered ones of formats 6-10).
//
// Every item keeps the previous point's values as context. init() starts a
// chunk from its first point (stored raw), read() decodes the next point
// into `item`, which must hold the item's bytes. The chunk decoder calls
// them directly on concrete types (no virtual calls per point).
#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "io/laz_arithmetic.h"

namespace pointnpr::laz {

// Little-endian fields of a raw point record, and the wrap-around integer
// arithmetic the item decoders predict with (LASzip's, on unsigned values).
template <class T>
T get(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}
template <class T>
void put(uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof(T));
}
inline int32_t wrap_add(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) + static_cast<uint32_t>(b));
}
inline int32_t wrap_mul(int32_t a, int32_t b) {
  return static_cast<int32_t>(static_cast<uint32_t>(a) * static_cast<uint32_t>(b));
}

// Running median of the last five values (the x/y difference predictor).
struct Median5 {
  int32_t v[5] = {0, 0, 0, 0, 0};
  bool high = true;
  // Inserts x, dropping the oldest extreme (alternately the high or low end).
  void add(int32_t x) {
    if (high) {
      if (x < v[2]) {
        v[4] = v[3];
        v[3] = v[2];
        if (x < v[0]) {
          v[2] = v[1];
          v[1] = v[0];
          v[0] = x;
        } else if (x < v[1]) {
          v[2] = v[1];
          v[1] = x;
        } else {
          v[2] = x;
        }
      } else {
        if (x < v[3]) {
          v[4] = v[3];
          v[3] = x;
        } else {
          v[4] = x;
        }
        high = false;
      }
    } else {
      if (v[2] < x) {
        v[0] = v[1];
        v[1] = v[2];
        if (v[4] < x) {
          v[2] = v[3];
          v[3] = v[4];
          v[4] = x;
        } else if (v[3] < x) {
          v[2] = v[3];
          v[3] = x;
        } else {
          v[2] = x;
        }
      } else {
        if (v[1] < x) {
          v[0] = v[1];
          v[1] = x;
        } else {
          v[0] = x;
        }
        high = true;
      }
    }
  }
  int32_t get() const { return v[2]; }
};

// Models created on first use, indexed by a context byte (most of the 256
// contexts of a classification or flag byte never occur).
class LazyModels {
 public:
  explicit LazyModels(uint32_t symbols = 256) : symbols_(symbols) {}
  void reset() {
    for (auto& m : models_)
      if (m) m->init(symbols_);
  }
  SymbolModel& operator[](uint32_t context) {
    auto& m = models_[context & 255];
    if (!m) m = std::make_unique<SymbolModel>(symbols_);
    return *m;
  }

 private:
  uint32_t symbols_;
  std::array<std::unique_ptr<SymbolModel>, 256> models_;
};

// ---- point-wise items, version 2 (LASzip 2.x; formats 0-5) ----

class Point10V2 {
 public:
  Point10V2();
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  uint8_t last_[20];
  uint16_t last_intensity_[16];
  Median5 last_x_diff_[16], last_y_diff_[16];
  int32_t last_height_[8];
  SymbolModel changed_values_;
  SymbolModel scan_angle_rank_[2];
  LazyModels bit_byte_, classification_, user_data_;
  IntegerDecompressor ic_intensity_, ic_point_source_, ic_dx_, ic_dy_, ic_z_;
};

class GpsTime11V2 {
 public:
  GpsTime11V2();
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  uint32_t last_ = 0, next_ = 0;
  uint64_t last_gps_[4];
  int32_t last_diff_[4];
  int32_t multi_extreme_[4];
  SymbolModel multi_, zero_diff_;
  IntegerDecompressor ic_gps_;
};

// Models of the version 2 colour coder (also used by the layered RGB14).
struct RgbModels {
  SymbolModel byte_used;
  SymbolModel diff[6];
  void init();
};
// Decodes the next colour given the last one, which it updates.
void decode_rgb_v2(Decoder& dec, RgbModels& m, uint16_t last[3]);

class Rgb12V2 {
 public:
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  uint16_t last_[3];
  RgbModels models_;
};

class BytesV2 {
 public:
  explicit BytesV2(uint32_t count);
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  std::vector<uint8_t> last_;
  std::vector<SymbolModel> models_;
};

// Wave packet descriptors of formats 4 and 5 (29 bytes: descriptor index,
// byte offset to the waveform, packet size, return point location, x(t),
// y(t), z(t)), versions 1 and 2 alike. The waveforms themselves are not
// read; the packets must still be decoded for the items after them.
class WavePacket13 {
 public:
  WavePacket13();
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  std::array<uint8_t, 29> last_{};
  int32_t last_offset_diff_ = 0;
  uint32_t offset_case_ = 0;  // how the last offset was coded: a context for the next
  SymbolModel index_;
  std::array<SymbolModel, 4> offset_cases_;
  IntegerDecompressor ic_offset_diff_, ic_size_, ic_return_point_, ic_xyz_;
};

// ---- point-wise items, version 1 (LASzip 1.x; the early compressor) ----

class Point10V1 {
 public:
  Point10V1();
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  uint8_t last_[20];
  int32_t last_x_diff_[3], last_y_diff_[3];
  int last_incr_ = 0;
  SymbolModel changed_values_;
  LazyModels bit_byte_, classification_, user_data_;
  IntegerDecompressor ic_dx_, ic_dy_, ic_z_, ic_intensity_, ic_scan_angle_, ic_point_source_;
};

class GpsTime11V1 {
 public:
  GpsTime11V1();
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  uint64_t last_gps_ = 0;
  int32_t last_diff_ = 0;
  int32_t multi_extreme_ = 0;
  SymbolModel multi_, zero_diff_;
  IntegerDecompressor ic_gps_;
};

class Rgb12V1 {
 public:
  Rgb12V1();
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  uint16_t last_[3];
  SymbolModel byte_used_;
  IntegerDecompressor ic_rgb_;
};

// Extra bytes of LASzip 1.x: each byte is an 8-bit integer coded against
// the same byte of the last point, one integer context per byte.
class BytesV1 {
 public:
  explicit BytesV1(uint32_t count);
  void init(const uint8_t* first);
  void read(Decoder& dec, uint8_t* item);

 private:
  std::vector<uint8_t> last_;
  IntegerDecompressor ic_byte_;
};

}  // namespace pointnpr::laz
