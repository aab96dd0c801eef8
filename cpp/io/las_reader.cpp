// ASPRS LAS 1.0-1.4 reader (point data record formats 0-10).
//
// The whole file is memory-mapped; every header field is validated against
// the file size before anything is allocated, so a corrupt header can only
// produce a ReadError, never a huge allocation or an out-of-bounds read.
// Point records are decoded column by column with the per-format offsets
// fixed before each loop (no per-point dispatch). LAZ (LASzip) point data is
// first decompressed into the same records (io/laz_reader.h), so both read
// into the columns by the same code.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include "core/error.h"
#include "io/laz_reader.h"
#include "io/mapped_file.h"
#include "io/readers.h"

namespace pointnpr {
namespace {

using io::load_le;

constexpr size_t kVlrHeaderSize = 54;
constexpr size_t kEvlrHeaderSize = 60;
constexpr size_t kExtraBytesDescriptorSize = 192;
constexpr uint16_t kMinRecordLength[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};


// Byte offsets of the optional fields of each point format (-1 = absent).
struct Layout {
  bool extended = false;  // formats 6-10
  int gps = -1;
  int rgb = -1;
  int nir = -1;
};

Layout layout_for(int pf) {
  Layout l;
  switch (pf) {
    case 0: break;
    case 1: l.gps = 20; break;
    case 2: l.rgb = 20; break;
    case 3: l.gps = 20; l.rgb = 28; break;
    case 4: l.gps = 20; break;
    case 5: l.gps = 20; l.rgb = 28; break;
    case 6: l.extended = true; l.gps = 22; break;
    case 7: l.extended = true; l.gps = 22; l.rgb = 30; break;
    case 8: l.extended = true; l.gps = 22; l.rgb = 30; l.nir = 36; break;
    case 9: l.extended = true; l.gps = 22; break;
    case 10: l.extended = true; l.gps = 22; l.rgb = 30; l.nir = 36; break;
    default: break;
  }
  return l;
}

std::string fixed_string(const uint8_t* p, size_t n) {
  size_t len = 0;
  while (len < n && p[len] != 0) ++len;
  std::string s(reinterpret_cast<const char*>(p), len);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.pop_back();
  return s;
}

// One field described by the extra bytes VLR (LASF_Spec, record 4).
struct ExtraField {
  std::string name;
  int base_type = 0;  // 1..10: u8 i8 u16 i16 u32 i32 u64 i64 f32 f64
  int components = 1;
  size_t offset = 0;  // within the point record
  bool scaled = false;
  double scale[3] = {1, 1, 1};
  double add[3] = {0, 0, 0};
};

// Output columns of the standard fields; null where the format lacks them.
struct Columns {
  double* pos;
  float* intensity;
  uint8_t* return_number;
  uint8_t* number_of_returns;
  uint8_t* classification;
  uint8_t* user_data;
  float* scan_angle;
  uint16_t* point_source_id;
  double* gps_time;
  uint8_t* colors;
  uint16_t* nir;
};

constexpr size_t kBaseTypeSize[11] = {0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8};

class LasReader : private io::ReaderBase {
 public:
  using ReaderBase::ReaderBase;

  PointData read();
  // The header's metadata alone (read_las_header).
  PointData header() {
    PointData out;
    add_metadata(out, parse_header());
    return out;
  }
  // The points block after block (readers.h, stream_las).
  void stream(uint64_t block_points, const ScanBlockSink& sink);

 private:
  // What read() and stream() need of the header, every field validated.
  struct Header {
    int vmajor = 0, vminor = 0, pf = 0;
    uint16_t record_length = 0;
    uint32_t point_offset = 0, num_vlrs = 0;
    uint64_t count = 0;
    uint64_t data_end = 0;  // LAZ: where the compressed bytes end
    double scale[3] = {1, 1, 1}, offset[3] = {0, 0, 0}, bounds[6] = {};
    size_t extra_room = 0;
  };
  Header parse_header();
  void add_metadata(PointData& out, const Header& h) const;

  void parse_vlr(const std::string& user, uint16_t id, const uint8_t* payload, uint64_t len,
                 size_t at);
  void parse_extra_bytes(const uint8_t* payload, uint64_t len, size_t at);
  void parse_geokeys(const uint8_t* payload, uint64_t len);
  void decode_points(PointData& out, int pf, size_t record_length, uint64_t n,
                     const uint8_t* base, const double scale[3], const double offset[3]);
  std::function<void(uint64_t, uint64_t, const uint8_t*)> prepare_extra(PointData& out,
                                                                         const ExtraField& f,
                                                                         size_t record_length);
  std::vector<std::function<void(uint64_t, uint64_t, const uint8_t*)>> prepare_extras(
      PointData& out, int pf, size_t record_length);
  void decode_laz_points(PointData& out, int pf, size_t record_length, uint64_t n,
                         const double scale[3], const double offset[3], uint64_t point_offset,
                         uint64_t data_end);


  std::string wkt_;
  int64_t epsg_ = 0;
  std::optional<laz::LaszipVlr> laszip_;
  const uint8_t* laszip_payload_ = nullptr;
  uint64_t laszip_len_ = 0;
  size_t laszip_at_ = 0;
  std::vector<ExtraField> extra_;
  size_t extra_descriptor_bytes_ = 0;
  bool have_extra_vlr_ = false;
};

void LasReader::parse_vlr(const std::string& user, uint16_t id, const uint8_t* payload,
                          uint64_t len, size_t at) {
  if (user == "laszip encoded" && id == 22204) {
    // Parsed once the point format says the points are compressed.
    laszip_payload_ = payload;
    laszip_len_ = len;
    laszip_at_ = at + kVlrHeaderSize;
  }
  if (user == "LASF_Projection") {
    if (id == 2112) {
      std::string w = fixed_string(payload, static_cast<size_t>(len));
      if (w.find('[') != std::string::npos) wkt_ = std::move(w);  // ignore placeholders
    } else if (id == 34735) {
      parse_geokeys(payload, len);
    }
  } else if (user == "LASF_Spec" && id == 4) {
    parse_extra_bytes(payload, len, at);
  }
}

void LasReader::parse_geokeys(const uint8_t* p, uint64_t len) {
  // GeoKeyDirectory: 4 header shorts, then (key, location, count, value) quads.
  if (len < 8) return;
  uint16_t nkeys = load_le<uint16_t>(p + 6);
  uint64_t avail = (len - 8) / 8;
  uint64_t count = std::min<uint64_t>(nkeys, avail);
  int64_t projected = 0, geographic = 0;
  for (uint64_t k = 0; k < count; ++k) {
    const uint8_t* e = p + 8 + 8 * k;
    uint16_t key = load_le<uint16_t>(e);
    uint16_t location = load_le<uint16_t>(e + 2);
    uint16_t value = load_le<uint16_t>(e + 6);
    if (location != 0 || value == 0 || value == 32767) continue;  // not inline / user-defined
    if (key == 3072) projected = value;   // ProjectedCSTypeGeoKey
    if (key == 2048) geographic = value;  // GeographicTypeGeoKey
  }
  epsg_ = projected ? projected : geographic;
}

void LasReader::parse_extra_bytes(const uint8_t* p, uint64_t len, size_t at) {
  if (len % kExtraBytesDescriptorSize != 0)
    fail("extra bytes VLR has length " + std::to_string(len) +
             ", which is not a multiple of the 192-byte descriptor size",
         static_cast<int64_t>(at));
  have_extra_vlr_ = true;
  extra_.clear();
  size_t offset = 0;
  uint64_t count = len / kExtraBytesDescriptorSize;
  for (uint64_t i = 0; i < count; ++i) {
    const uint8_t* e = p + i * kExtraBytesDescriptorSize;
    const int type = e[2];
    const int options = e[3];
    if (type == 0) {  // undocumented bytes: `options` holds their size
      offset += static_cast<size_t>(options);
      continue;
    }
    if (type > 30)
      fail("extra bytes descriptor " + std::to_string(i) + " has unknown data type " +
               std::to_string(type),
           static_cast<int64_t>(at + i * kExtraBytesDescriptorSize));
    ExtraField f;
    f.base_type = (type - 1) % 10 + 1;
    f.components = (type - 1) / 10 + 1;
    f.name = fixed_string(e + 4, 32);
    if (f.name.empty()) f.name = "extra_" + std::to_string(i);
    f.offset = offset;
    // options bit 3: scale present, bit 4: offset present (3 doubles each).
    if (options & (8 | 16)) {
      f.scaled = true;
      for (int c = 0; c < 3; ++c) {
        if (options & 8) {
          double s = load_le<double>(e + 112 + 8 * c);
          f.scale[c] = (s == 0.0 || !std::isfinite(s)) ? 1.0 : s;
        }
        if (options & 16) {
          double o = load_le<double>(e + 136 + 8 * c);
          f.add[c] = std::isfinite(o) ? o : 0.0;
        }
      }
    }
    offset += kBaseTypeSize[f.base_type] * static_cast<size_t>(f.components);
    extra_.push_back(f);
  }
  extra_descriptor_bytes_ = offset;
}

// Fills records [begin, end) (the first at `first`) of an extra bytes field.
using ExtraFill = std::function<void(uint64_t begin, uint64_t end, const uint8_t* first)>;

// The column is taken when the fill runs: it may be sized after this (size_columns).
template <class T>
ExtraFill prepare_extra_typed(PointData& out, const ExtraField& f, size_t rl,
                              const std::string& name) {
  const int comps = f.components;
  if (f.scaled) {
    std::vector<double>* column = &out.add<double>(name, comps);
    return [column, f, rl, comps](uint64_t begin, uint64_t end, const uint8_t* first) {
      double* v = column->data();
      for (uint64_t i = begin; i < end; ++i) {
        const uint8_t* r = first + (i - begin) * rl + f.offset;
        for (int c = 0; c < comps; ++c)
          v[i * comps + c] =
              static_cast<double>(load_le<T>(r + c * sizeof(T))) * f.scale[c] + f.add[c];
      }
    };
  }
  std::vector<T>* column = &out.add<T>(name, comps);
  return [column, f, rl, comps](uint64_t begin, uint64_t end, const uint8_t* first) {
    T* v = column->data();
    for (uint64_t i = begin; i < end; ++i) {
      const uint8_t* r = first + (i - begin) * rl + f.offset;
      for (int c = 0; c < comps; ++c) v[i * comps + c] = load_le<T>(r + c * sizeof(T));
    }
  };
}

ExtraFill LasReader::prepare_extra(PointData& out, const ExtraField& f, size_t rl) {
  std::string name = f.name;
  while (out.has(name)) name = "extra_" + name;
  switch (f.base_type) {
    case 1: return prepare_extra_typed<uint8_t>(out, f, rl, name);
    case 2: return prepare_extra_typed<int8_t>(out, f, rl, name);
    case 3: return prepare_extra_typed<uint16_t>(out, f, rl, name);
    case 4: return prepare_extra_typed<int16_t>(out, f, rl, name);
    case 5: return prepare_extra_typed<uint32_t>(out, f, rl, name);
    case 6: return prepare_extra_typed<int32_t>(out, f, rl, name);
    case 7: return prepare_extra_typed<uint64_t>(out, f, rl, name);
    case 8: return prepare_extra_typed<int64_t>(out, f, rl, name);
    case 9: return prepare_extra_typed<float>(out, f, rl, name);
    case 10: return prepare_extra_typed<double>(out, f, rl, name);
    default: return {};
  }
}


// Decodes records [begin, end) of point format PF (the first at `first`) in
// one pass; the layout is a compile-time constant, so the loop has no
// per-point dispatch.
template <int PF>
void decode_range(const uint8_t* first, size_t rl, uint64_t begin, uint64_t end,
                  const double scale[3], const double offset[3], bool sixteen_bit_color,
                  const Columns& c) {
  constexpr bool ext = PF >= 6;
  constexpr int gps = PF == 0 || PF == 2 ? -1 : ext ? 22 : 20;
  constexpr int rgb = PF == 2 ? 20 : (PF == 3 || PF == 5) ? 28 : (PF == 7 || PF == 8 || PF == 10) ? 30 : -1;
  constexpr int nir = (PF == 8 || PF == 10) ? 36 : -1;
  const double sx = scale[0], sy = scale[1], sz = scale[2];
  const double ox = offset[0], oy = offset[1], oz = offset[2];
  const int shift = sixteen_bit_color ? 8 : 0;
  for (uint64_t i = begin; i < end; ++i) {
    const uint8_t* r = first + (i - begin) * rl;
    c.pos[3 * i + 0] = static_cast<double>(load_le<int32_t>(r + 0)) * sx + ox;
    c.pos[3 * i + 1] = static_cast<double>(load_le<int32_t>(r + 4)) * sy + oy;
    c.pos[3 * i + 2] = static_cast<double>(load_le<int32_t>(r + 8)) * sz + oz;
    c.intensity[i] = static_cast<float>(load_le<uint16_t>(r + 12));
    if constexpr (ext) {
      c.return_number[i] = r[14] & 0x0F;
      c.number_of_returns[i] = static_cast<uint8_t>(r[14] >> 4);
      c.classification[i] = r[16];
      c.user_data[i] = r[17];
      c.scan_angle[i] = static_cast<float>(load_le<int16_t>(r + 18) * 0.006);
      c.point_source_id[i] = load_le<uint16_t>(r + 20);
    } else {
      c.return_number[i] = r[14] & 0x07;
      c.number_of_returns[i] = (r[14] >> 3) & 0x07;
      c.classification[i] = r[15] & 0x1F;
      c.scan_angle[i] = static_cast<float>(static_cast<int8_t>(r[16]));
      c.user_data[i] = r[17];
      c.point_source_id[i] = load_le<uint16_t>(r + 18);
    }
    if constexpr (gps >= 0) c.gps_time[i] = load_le<double>(r + gps);
    if constexpr (rgb >= 0) {
      if (c.colors) {
        c.colors[3 * i + 0] = static_cast<uint8_t>(load_le<uint16_t>(r + rgb) >> shift);
        c.colors[3 * i + 1] = static_cast<uint8_t>(load_le<uint16_t>(r + rgb + 2) >> shift);
        c.colors[3 * i + 2] = static_cast<uint8_t>(load_le<uint16_t>(r + rgb + 4) >> shift);
      }
    }
    if constexpr (nir >= 0) c.nir[i] = load_le<uint16_t>(r + nir);
  }
}

using DecodeFn = void (*)(const uint8_t*, size_t, uint64_t, uint64_t, const double*, const double*,
                          bool, const Columns&);
constexpr DecodeFn kDecoders[11] = {decode_range<0>, decode_range<1>, decode_range<2>,
                                    decode_range<3>, decode_range<4>, decode_range<5>,
                                    decode_range<6>, decode_range<7>, decode_range<8>,
                                    decode_range<9>, decode_range<10>};

// Runs fn(begin, end) over [0, n) in blocks, in parallel for large clouds.
template <class Fn>
void for_blocks(uint64_t n, const Fn& fn) {
  constexpr uint64_t kBlock = 1 << 16;
  if (n <= kBlock) {
    fn(uint64_t{0}, n);
    return;
  }
  const uint64_t blocks = (n + kBlock - 1) / kBlock;
  tbb::parallel_for(uint64_t{0}, blocks, [&](uint64_t b) {
    fn(b * kBlock, std::min(n, (b + 1) * kBlock));
  });
}

// Declares the standard columns of point format `pf`, in their order, still
// empty (positions included): size_columns gives them their rows.
void declare_columns(PointData& out, int pf) {
  const Layout lay = layout_for(pf);
  out.positions.clear();
  out.add<float>("intensity");
  out.add<uint8_t>("return_number");
  out.add<uint8_t>("number_of_returns");
  out.add<uint8_t>("classification");
  out.add<uint8_t>("user_data");
  out.add<float>("scan_angle");
  out.add<uint16_t>("point_source_id");
  if (lay.gps >= 0) out.add<double>("gps_time");
  if (lay.nir >= 0) out.add<uint16_t>("nir");
}

// Gives the positions and every column declared empty n rows, and runs
// `more` (other buffers to size), all on the threads at once. First touching
// fresh columns (some 60 bytes a point: the kernel's page faults, zeroing
// and, for huge pages, compaction) is otherwise a serial step; before the
// LAZ decode of 2.2 million points it was 20-30 ms of a 400 ms read, and up
// to 700 ms when the kernel had to compact memory for huge pages.
void size_columns(PointData& out, uint64_t n, std::vector<std::function<void()>> more = {}) {
  std::vector<std::function<void()>> jobs;
  jobs.push_back([&out, n] { io::resize_fresh(out.positions, n * 3); });  // the largest first
  for (PointAttribute& a : out.attributes) {
    if (a.num_points() != 0) continue;
    const size_t rows = n * static_cast<size_t>(a.components);
    jobs.push_back([&a, rows] { std::visit([rows](auto& v) { io::resize_fresh(v, rows); }, a.values); });
  }
  for (auto& job : more) jobs.push_back(std::move(job));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, jobs.size(), 1),
                    [&](const tbb::blocked_range<size_t>& r) {
                      for (size_t i = r.begin(); i != r.end(); ++i) jobs[i]();
                    },
                    tbb::simple_partitioner());
}

template <class T>
T* column(PointData& out, const std::string& name) {
  return std::get<std::vector<T>>(out.find(name)->values).data();
}

// The standard columns of point format `pf` (declared and sized).
Columns columns_of(PointData& out, int pf) {
  const Layout lay = layout_for(pf);
  Columns c{};
  c.pos = out.positions.data();
  c.intensity = column<float>(out, "intensity");
  c.return_number = column<uint8_t>(out, "return_number");
  c.number_of_returns = column<uint8_t>(out, "number_of_returns");
  c.classification = column<uint8_t>(out, "classification");
  c.user_data = column<uint8_t>(out, "user_data");
  c.scan_angle = column<float>(out, "scan_angle");
  c.point_source_id = column<uint16_t>(out, "point_source_id");
  if (lay.gps >= 0) c.gps_time = column<double>(out, "gps_time");
  if (lay.nir >= 0) c.nir = column<uint16_t>(out, "nir");
  return c;
}

std::vector<ExtraFill> LasReader::prepare_extras(PointData& out, int pf, size_t rl) {
  std::vector<ExtraFill> fills;
  for (ExtraField f : extra_) {
    f.offset += kMinRecordLength[pf];
    if (ExtraFill fill = prepare_extra(out, f, rl)) fills.push_back(std::move(fill));
  }
  return fills;
}

// LAS stores 16-bit colour; many writers store 0-255 values instead.
// Decide on the file as a whole: any value above 255 means 16-bit, which
// is then reduced with v >> 8: exact for both common ways of widening
// 8-bit colour (c * 256 and c * 257) and within one level otherwise.
// Returns the shift, or -1 when every colour is zero (no colour column).
template <class MaxFn>
int colour_shift(PointData& out, MaxFn max_until_above_255) {
  const uint16_t maxv = max_until_above_255();
  if (maxv == 0) {
    out.metadata["colors_all_zero"] = int64_t{1};
    return -1;
  }
  out.metadata["color_bits"] = int64_t{maxv > 255 ? 16 : 8};
  return maxv > 255 ? 8 : 0;
}

void LasReader::decode_points(PointData& out, int pf, size_t rl, uint64_t n,
                              const uint8_t* base, const double scale[3],
                              const double offset[3]) {
  const Layout lay = layout_for(pf);
  declare_columns(out, pf);
  size_columns(out, n);
  Columns c = columns_of(out, pf);
  bool sixteen = false;
  // Records read are released block by block (MappedFile::release): the
  // mapped file never resides whole next to the columns read out of it.
  const size_t base_offset = static_cast<size_t>(base - d_);
  auto release = [&](uint64_t b, uint64_t e) { file_.release(base_offset + b * rl, (e - b) * rl); };
  if (lay.rgb >= 0) {
    // The scan stops at the first value above 255 (at once for most 16-bit files).
    const int shift = colour_shift(out, [&] {
      uint16_t maxv = 0;
      for (uint64_t i = 0; i < n && maxv <= 255; ++i) {
        const uint8_t* r = base + i * rl + lay.rgb;
        maxv = std::max({maxv, load_le<uint16_t>(r), load_le<uint16_t>(r + 2),
                         load_le<uint16_t>(r + 4)});
        if ((i + 1) % (1 << 16) == 0) release(i + 1 - (1 << 16), i + 1);
      }
      return maxv;
    });
    if (shift >= 0) {
      sixteen = shift == 8;
      c.colors = out.add<uint8_t>("colors", 3).data();
    }
  }
  const DecodeFn decode = kDecoders[pf];
  const std::vector<ExtraFill> extras = prepare_extras(out, pf, rl);
  for_blocks(n, [&](uint64_t b, uint64_t e) {
    decode(base + b * rl, rl, b, e, scale, offset, sixteen, c);
    for (const ExtraFill& fill : extras) fill(b, e, base + b * rl);
    release(b, e);
  });
}

void LasReader::decode_laz_points(PointData& out, int pf, size_t rl, uint64_t n,
                                  const double scale[3], const double offset[3],
                                  uint64_t point_offset, uint64_t data_end) {
  // Each decoded chunk goes straight into the columns (while its records are
  // in cache). Whether colours are 8 or 16 bits is known only once the whole
  // file has been seen, so both candidate 8-bit columns are filled (the high
  // and the low byte of every value) and the OR of all values decides which
  // one is kept: no pass over the points afterwards.
  const Layout lay = layout_for(pf);
  Columns c{};
  std::vector<ExtraFill> extras;
  std::vector<uint8_t> rgb_high, rgb_low;
  std::atomic<uint16_t> rgb_seen{0};
  const DecodeFn decode = kDecoders[pf];
  laz::decompress(d_, size_, point_offset, data_end, n, rl, *laszip_,
                  [&] {  // the counts are checked: allocate
                    declare_columns(out, pf);
                    extras = prepare_extras(out, pf, rl);
                    std::vector<std::function<void()>> more;
                    if (lay.rgb >= 0) {
                      more.push_back([&] { io::resize_fresh(rgb_high, n * 3); });
                      more.push_back([&] { io::resize_fresh(rgb_low, n * 3); });
                    }
                    size_columns(out, n, std::move(more));
                    c = columns_of(out, pf);
                  },
                  [&](uint64_t first, const uint8_t* records, uint64_t count) {
                    decode(records, rl, first, first + count, scale, offset, false, c);
                    for (const ExtraFill& fill : extras) fill(first, first + count, records);
                    if (lay.rgb < 0) return;
                    uint16_t seen = 0;
                    uint8_t* high = rgb_high.data() + 3 * first;
                    uint8_t* low = rgb_low.data() + 3 * first;
                    for (uint64_t i = 0; i < count; ++i) {
                      const uint8_t* r = records + i * rl + lay.rgb;
                      for (int k = 0; k < 3; ++k) {
                        const uint16_t v = load_le<uint16_t>(r + 2 * k);
                        high[3 * i + k] = static_cast<uint8_t>(v >> 8);
                        low[3 * i + k] = static_cast<uint8_t>(v);
                        seen |= v;
                      }
                    }
                    rgb_seen.fetch_or(seen, std::memory_order_relaxed);
                  });
  if (lay.rgb < 0) return;
  // The OR of all values is above 255, or 0, exactly when their maximum is.
  const uint16_t seen = rgb_seen.load();
  const int shift = colour_shift(out, [seen] { return seen; });
  if (shift < 0) return;
  out.set<uint8_t>("colors", 3, std::move(shift == 8 ? rgb_high : rgb_low));
}

LasReader::Header LasReader::parse_header() {
  if (size_ == 0) fail("file is empty (0 bytes)");
  if (size_ < 4 || std::memcmp(d_, "LASF", 4) != 0) {
    fail("not a LAS file: it does not start with the 'LASF' signature", 0);
  }
  if (size_ < 227)
    fail("file is truncated: " + std::to_string(size_) +
             " bytes is smaller than the 227-byte LAS header",
         static_cast<int64_t>(size_));

  const int vmajor = d_[24], vminor = d_[25];
  if (vmajor != 1 || vminor > 4)
    fail("unsupported LAS version " + std::to_string(vmajor) + "." + std::to_string(vminor) +
             " (supported: 1.0 to 1.4)",
         24);
  const uint16_t header_size = load_le<uint16_t>(d_ + 94);
  const size_t min_header = vminor >= 4 ? 375 : vminor == 3 ? 235 : 227;
  if (header_size < min_header)
    fail("header size " + std::to_string(header_size) + " is smaller than the " +
             std::to_string(min_header) + " bytes LAS 1." + std::to_string(vminor) + " requires",
         94);
  if (header_size > size_)
    fail("header size " + std::to_string(header_size) + " exceeds the file size " +
             std::to_string(size_) + "; the file is truncated",
         94);
  const uint32_t point_offset = load_le<uint32_t>(d_ + 96);
  const uint32_t num_vlrs = load_le<uint32_t>(d_ + 100);
  const uint8_t pf_byte = d_[104];
  const uint16_t record_length = load_le<uint16_t>(d_ + 105);
  const uint32_t legacy_count = load_le<uint32_t>(d_ + 107);

  // LASzip marks compressed files with bit 7 of the point format (bit 6 by
  // some early writers); the LASzip VLR found below says how.
  const bool compressed = (pf_byte & 0xC0) != 0;
  const int pf = pf_byte & 0x3F;
  if (pf > 10)
    fail("unsupported point data record format " + std::to_string(pf) +
             " (LAS defines formats 0 to 10)",
         104);
  if (record_length < kMinRecordLength[pf])
    fail("point record length " + std::to_string(record_length) + " is smaller than the " +
             std::to_string(kMinRecordLength[pf]) + " bytes point format " +
             std::to_string(pf) + " requires",
         105);
  if (point_offset < header_size)
    fail("offset to point data (" + std::to_string(point_offset) +
             ") lies inside the header (header size " + std::to_string(header_size) + ")",
         96);
  if (point_offset > size_)
    fail("offset to point data (" + std::to_string(point_offset) + ") is beyond the end of the " +
             std::to_string(size_) + "-byte file; the file is truncated",
         96);

  double scale[3], offset[3], bounds[6];
  for (int c = 0; c < 3; ++c) {
    scale[c] = load_le<double>(d_ + 131 + 8 * c);
    offset[c] = load_le<double>(d_ + 155 + 8 * c);
    if (scale[c] == 0.0 || !std::isfinite(scale[c]))
      fail(std::string("scale factor for ") + "XYZ"[c] + " is " + std::to_string(scale[c]) +
               "; it must be a finite non-zero number",
           131 + 8 * c);
    if (!std::isfinite(offset[c]))
      fail(std::string("offset for ") + "XYZ"[c] + " is not a finite number", 155 + 8 * c);
  }
  for (int k = 0; k < 6; ++k) bounds[k] = load_le<double>(d_ + 179 + 8 * k);

  uint64_t count = legacy_count;
  if (vminor >= 4) {
    const uint64_t count64 = load_le<uint64_t>(d_ + 247);
    if (count64 != 0) count = count64;
  }

  // Variable length records lie between the header and the point data.
  const size_t vlr_space = point_offset - header_size;
  if (static_cast<uint64_t>(num_vlrs) * kVlrHeaderSize > vlr_space)
    fail("header declares " + std::to_string(num_vlrs) + " variable length records (at least " +
             std::to_string(static_cast<uint64_t>(num_vlrs) * kVlrHeaderSize) +
             " bytes), but only " + std::to_string(vlr_space) +
             " bytes lie between the header and the point data; the VLR count is corrupt",
         100);
  size_t pos = header_size;
  for (uint32_t i = 0; i < num_vlrs; ++i) {
    if (pos + kVlrHeaderSize > point_offset)
      fail("variable length record " + std::to_string(i + 1) + " of " +
               std::to_string(num_vlrs) + " would start at byte " + std::to_string(pos) +
               ", past the start of the point data (byte " + std::to_string(point_offset) +
               "); the header's VLR count or a VLR length is wrong",
           static_cast<int64_t>(pos));
    const std::string user = fixed_string(d_ + pos + 2, 16);
    const uint16_t id = load_le<uint16_t>(d_ + pos + 18);
    const uint16_t len = load_le<uint16_t>(d_ + pos + 20);
    if (pos + kVlrHeaderSize + len > point_offset)
      fail("variable length record " + std::to_string(i + 1) + " of " +
               std::to_string(num_vlrs) + " ('" + user + "' " + std::to_string(id) + ") is " +
               std::to_string(len) + " bytes long and would run past the start of the point data (byte " +
               std::to_string(point_offset) + "); the header's VLR count or a VLR length is wrong",
           static_cast<int64_t>(pos));
    parse_vlr(user, id, d_ + pos + kVlrHeaderSize, len, pos);
    pos += kVlrHeaderSize + len;
  }

  if (compressed && !laszip_payload_)
    fail("the point format byte (" + std::to_string(pf_byte) +
             ") marks the points as compressed, but the file has no LASzip VLR",
         104);
  if (compressed) {  // a LASzip VLR on uncompressed points is a leftover: ignored
    try {
      laszip_ = laz::parse_laszip_vlr(laszip_payload_, laszip_len_,
                                      static_cast<int64_t>(laszip_at_));
      laz::check_items(*laszip_, pf, record_length);
    } catch (const laz::FormatError& e) {
      fail(e.what(), e.offset);
    }
  }

  // Point data.
  const uint64_t avail = size_ - point_offset;
  if (!laszip_ && count > avail / record_length) {
    // Overflow-safe: count * record_length would exceed what the file holds.
    const std::string need = count <= std::numeric_limits<uint64_t>::max() / record_length
                                 ? std::to_string(count * record_length)
                                 : std::string("more than 2^64");
    fail("file is truncated: the header declares " + std::to_string(count) + " points of " +
             std::to_string(record_length) + " bytes (" + need + " bytes) starting at byte " +
             std::to_string(point_offset) + ", but only " + std::to_string(avail) +
             " bytes follow; the file may be an incomplete copy or download",
         static_cast<int64_t>(size_));
  }

  // Extended VLRs (LAS 1.4) follow the point data; they may hold the WKT CRS
  // or the extra bytes description.
  if (vminor >= 4) {
    const uint64_t evlr_start = load_le<uint64_t>(d_ + 235);
    const uint32_t num_evlrs = load_le<uint32_t>(d_ + 243);
    if (num_evlrs > 0) {
      const uint64_t points_end = laszip_ ? point_offset : point_offset + count * record_length;
      if (evlr_start < points_end || evlr_start > size_)
        fail("start of extended VLRs (byte " + std::to_string(evlr_start) +
                 ") is not between the end of the point data (byte " +
                 std::to_string(points_end) + ") and the end of the file (byte " +
                 std::to_string(size_) + ")",
             235);
      if (static_cast<uint64_t>(num_evlrs) * kEvlrHeaderSize > size_ - evlr_start)
        fail("header declares " + std::to_string(num_evlrs) +
                 " extended VLRs, more than fit in the " + std::to_string(size_ - evlr_start) +
                 " bytes after byte " + std::to_string(evlr_start) +
                 "; the file is truncated or the count is corrupt",
             243);
      uint64_t p = evlr_start;
      for (uint32_t i = 0; i < num_evlrs; ++i) {
        if (p + kEvlrHeaderSize > size_)
          fail("extended VLR " + std::to_string(i + 1) + " of " + std::to_string(num_evlrs) +
                   " starts past the end of the file; the file is truncated",
               static_cast<int64_t>(p));
        const std::string user = fixed_string(d_ + p + 2, 16);
        const uint16_t id = load_le<uint16_t>(d_ + p + 18);
        const uint64_t len = load_le<uint64_t>(d_ + p + 20);
        if (len > size_ - p - kEvlrHeaderSize)
          fail("extended VLR " + std::to_string(i + 1) + " ('" + user + "' " +
                   std::to_string(id) + ") declares " + std::to_string(len) +
                   " bytes, more than remain in the file; the file is truncated",
               static_cast<int64_t>(p));
        parse_vlr(user, id, d_ + p + kEvlrHeaderSize, len, static_cast<size_t>(p));
        p += kEvlrHeaderSize + len;
      }
    }
  }

  const size_t extra_room = record_length - kMinRecordLength[pf];
  if (extra_descriptor_bytes_ > extra_room)
    fail("the extra bytes VLR describes " + std::to_string(extra_descriptor_bytes_) +
         " bytes per point, but point records only have " + std::to_string(extra_room) +
         " bytes beyond point format " + std::to_string(pf));

  Header h;
  h.vmajor = vmajor;
  h.vminor = vminor;
  h.pf = pf;
  h.record_length = record_length;
  h.point_offset = point_offset;
  h.num_vlrs = num_vlrs;
  h.count = count;
  for (int c = 0; c < 3; ++c) h.scale[c] = scale[c], h.offset[c] = offset[c];
  for (int k = 0; k < 6; ++k) h.bounds[k] = bounds[k];
  h.extra_room = extra_room;
  // The compressed bytes end at the first EVLR (LAS 1.4) or the file's end.
  h.data_end = size_;
  if (laszip_ && vminor >= 4 && load_le<uint32_t>(d_ + 243) > 0) {
    const uint64_t evlr_start = load_le<uint64_t>(d_ + 235);
    if (evlr_start >= point_offset && evlr_start <= size_) h.data_end = evlr_start;
  }
  return h;
}

PointData LasReader::read() {
  const Header h = parse_header();
  PointData out;
  if (laszip_) {
    try {
      decode_laz_points(out, h.pf, h.record_length, h.count, h.scale, h.offset, h.point_offset, h.data_end);
    } catch (const laz::FormatError& e) {
      fail(e.what(), e.offset);
    }
  } else {
    decode_points(out, h.pf, h.record_length, h.count, d_ + h.point_offset, h.scale, h.offset);
  }
  add_metadata(out, h);
  return out;
}

void LasReader::add_metadata(PointData& out, const Header& h) const {
  const int vmajor = h.vmajor, vminor = h.vminor, pf = h.pf;
  const uint16_t record_length = h.record_length;
  const uint32_t num_vlrs = h.num_vlrs;
  const uint64_t count = h.count;
  const double *scale = h.scale, *offset = h.offset, *bounds = h.bounds;
  const size_t extra_room = h.extra_room;
  auto& md = out.metadata;
  md["format"] = std::string("las");
  if (laszip_) {
    md["compression"] = std::string("laszip");
    md["laszip_compressor"] = static_cast<int64_t>(laszip_->compressor);
    md["laszip_version"] = std::to_string(laszip_->version_major) + "." +
                           std::to_string(laszip_->version_minor) + "r" +
                           std::to_string(laszip_->revision);
  }
  md["version"] = std::to_string(vmajor) + "." + std::to_string(vminor);
  md["point_format"] = static_cast<int64_t>(pf);
  md["point_record_length"] = static_cast<int64_t>(record_length);
  md["point_count"] = static_cast<int64_t>(count);
  md["scale"] = std::vector<double>{scale[0], scale[1], scale[2]};
  md["offset"] = std::vector<double>{offset[0], offset[1], offset[2]};
  md["bounds_min"] = std::vector<double>{bounds[1], bounds[3], bounds[5]};
  md["bounds_max"] = std::vector<double>{bounds[0], bounds[2], bounds[4]};
  md["system_identifier"] = fixed_string(d_ + 26, 32);
  md["generating_software"] = fixed_string(d_ + 58, 32);
  md["file_source_id"] = static_cast<int64_t>(load_le<uint16_t>(d_ + 4));
  md["creation_year"] = static_cast<int64_t>(load_le<uint16_t>(d_ + 92));
  md["creation_day"] = static_cast<int64_t>(load_le<uint16_t>(d_ + 90));
  md["vlr_count"] = static_cast<int64_t>(num_vlrs);
  if (!wkt_.empty()) md["crs_wkt"] = wkt_;
  if (epsg_ != 0) md["crs_epsg"] = epsg_;
  if (extra_room > extra_descriptor_bytes_)
    md["extra_bytes_undescribed"] = static_cast<int64_t>(extra_room - extra_descriptor_bytes_);
  if (pf == 4 || pf == 5 || pf == 9 || pf == 10) md["waveform_ignored"] = int64_t{1};
}

void LasReader::stream(uint64_t block_points, const ScanBlockSink& sink) {
  const Header h = parse_header();
  const Layout lay = layout_for(h.pf);
  const DecodeFn decode = kDecoders[h.pf];
  const size_t rl = h.record_length;
  // One block's columns (the standard fields; extra bytes are not streamed),
  // decoded from the records at `records` (the block's first).
  auto deliver = [&](uint64_t first, uint64_t n, const uint8_t* records) {
    PointData block;
    declare_columns(block, h.pf);
    size_columns(block, n);
    Columns c = columns_of(block, h.pf);
    std::vector<uint16_t> rgb16;
    if (lay.rgb >= 0) rgb16.resize(n * 3);
    for_blocks(n, [&](uint64_t b, uint64_t e) {
      decode(records + b * rl, rl, b, e, h.scale, h.offset, false, c);
      if (lay.rgb >= 0)
        for (uint64_t i = b; i < e; ++i) std::memcpy(&rgb16[3 * i], records + i * rl + lay.rgb, 6);
    });
    ScanBlock s;
    s.first = first;
    s.count = n;
    s.positions = block.positions.data();
    s.rgb16 = rgb16.empty() ? nullptr : rgb16.data();
    s.intensity = c.intensity;
    s.classification = c.classification;
    sink(s);
  };
  if (laszip_) {
    // Chunks decode in parallel; the sink sees one at a time, in any order.
    std::mutex one_at_a_time;
    try {
      laz::decompress(d_, size_, h.point_offset, h.data_end, h.count, rl, *laszip_, [] {},
                      [&](uint64_t first, const uint8_t* records, uint64_t n) {
                        std::lock_guard<std::mutex> lock(one_at_a_time);
                        deliver(first, n, records);
                      });
    } catch (const laz::FormatError& e) {
      fail(e.what(), e.offset);
    }
    return;
  }
  if (block_points == 0) block_points = 1;
  for (uint64_t first = 0; first < h.count; first += block_points) {
    const uint64_t n = std::min(block_points, h.count - first);
    deliver(first, n, d_ + h.point_offset + first * rl);
    file_.release(h.point_offset + first * rl, n * rl);
  }
}

}  // namespace

PointData read_las(const std::string& path) {
  LasReader reader(path);
  return reader.read();
}

PointData read_las_header(const std::string& path) {
  LasReader reader(path);
  return reader.header();
}

void stream_las(const std::string& path, const ScanBlockSink& sink, uint64_t block_points) {
  LasReader reader(path);
  reader.stream(block_points, sink);
}

PointData read_las_memory(const uint8_t* data, size_t size, const std::string& name) {
  LasReader reader(name, data, size);
  return reader.read();
}

}  // namespace pointnpr
