// LASzip container: the VLR that names the compressor and items, the chunk
// table, and the parallel decompression of independent chunks.
//
// Layout of the point data of a chunked LAZ file (LASzip 2+):
//   [int64 offset of the chunk table] [chunk 0] [chunk 1] ... [chunk table]
// The chunk table: uint32 version, uint32 chunk count, then per chunk its
// point count (variable-size chunks only) and byte size, arithmetic-coded
// as differences to the previous chunk's. A writer that could not seek back
// stores -1 as the offset and the real offset in the file's last 8 bytes;
// when neither is valid the chunks are found by decoding them in order.
#include "io/laz_reader.h"

#include <algorithm>
#include <cstring>
#include <exception>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "core/progress.h"
#include "io/laz_arithmetic.h"
#include "io/point_data.h"

namespace pointnpr::laz {
namespace {

template <class T>
T get(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

std::string item_name(uint16_t type) {
  switch (type) {
    case kByte: return "BYTE";
    case 1: return "SHORT";
    case 2: return "INT";
    case 3: return "LONG";
    case 4: return "FLOAT";
    case 5: return "DOUBLE";
    case kPoint10: return "POINT10";
    case kGpsTime11: return "GPSTIME11";
    case kRgb12: return "RGB12";
    case kWavePacket13: return "WAVEPACKET13";
    case kPoint14: return "POINT14";
    case kRgb14: return "RGB14";
    case kRgbNir14: return "RGBNIR14";
    case kWavePacket14: return "WAVEPACKET14";
    case kByte14: return "BYTE14";
    default: return "unknown item type " + std::to_string(type);
  }
}

constexpr uint32_t kVariableChunks = 0xFFFFFFFFu;

struct ChunkTable {
  std::vector<uint64_t> start;   // byte offset of each chunk
  std::vector<uint64_t> bytes;   // byte size of each chunk
  std::vector<uint64_t> points;  // point count (0: from the chunk itself)
};

// Reads the chunk table at `table_at`; nullopt when it is absent or does
// not fit (the caller then scans the chunks in order).
std::optional<ChunkTable> read_chunk_table(const uint8_t* d, uint64_t table_at, uint64_t first_chunk,
                                           uint64_t data_end, uint64_t file_size,
                                           uint32_t chunk_size, size_t rl) {
  if (table_at < first_chunk || table_at > file_size || file_size - table_at < 8)
    return std::nullopt;
  const uint32_t version = get<uint32_t>(d + table_at);
  const uint32_t n = get<uint32_t>(d + table_at + 4);
  if (version != 0)
    throw FormatError("LAZ chunk table has version " + std::to_string(version) +
                          " (only version 0 is defined)",
                      static_cast<int64_t>(table_at));
  // Every chunk holds at least its first point uncompressed.
  if (n > (table_at - first_chunk) / std::max<size_t>(rl, 1) + 1)
    throw FormatError("LAZ chunk table declares " + std::to_string(n) +
                          " chunks, more than fit in the " +
                          std::to_string(table_at - first_chunk) + " bytes of point data",
                      static_cast<int64_t>(table_at + 4));
  ChunkTable t;
  t.start.resize(n);
  t.bytes.resize(n);
  t.points.assign(n, 0);
  Decoder dec(d + table_at + 8, d + file_size);
  IntegerDecompressor ic(32, 2);
  ic.init();
  uint32_t prev_count = 0, prev_bytes = 0;
  uint64_t at = first_chunk;
  for (uint32_t i = 0; i < n; ++i) {
    if (chunk_size == kVariableChunks) {
      prev_count = static_cast<uint32_t>(ic.decompress(dec, static_cast<int32_t>(prev_count), 0));
      t.points[i] = prev_count;
    }
    prev_bytes = static_cast<uint32_t>(ic.decompress(dec, static_cast<int32_t>(prev_bytes), 1));
    t.start[i] = at;
    t.bytes[i] = prev_bytes;
    at += prev_bytes;
    if (at > data_end)
      throw FormatError("LAZ chunk table: chunk " + std::to_string(i) + " of " +
                            std::to_string(n) + " (" + std::to_string(prev_bytes) +
                            " bytes at byte " + std::to_string(t.start[i]) +
                            ") ends past the end of the point data (byte " +
                            std::to_string(data_end) + "); the table or the file is corrupt",
                        static_cast<int64_t>(t.start[i]));
  }
  // The encoder's closing bytes make a whole table decode without reading
  // past its end.
  if (dec.overrun() != 0)
    throw FormatError("LAZ chunk table is truncated", static_cast<int64_t>(table_at));
  return t;
}

// The ReadError adds the chunk's byte offset.
std::string chunk_error(size_t index, uint64_t, const std::string& what) {
  return "LAZ chunk " + std::to_string(index) + " is corrupt: " + what;
}

}  // namespace

LaszipVlr parse_laszip_vlr(const uint8_t* p, uint64_t len, int64_t at) {
  if (len < 34)
    throw FormatError("LASzip VLR is " + std::to_string(len) + " bytes, shorter than its 34-byte header",
                      at);
  LaszipVlr v;
  v.compressor = get<uint16_t>(p);
  v.coder = get<uint16_t>(p + 2);
  v.version_major = p[4];
  v.version_minor = p[5];
  v.revision = get<uint16_t>(p + 6);
  v.chunk_size = get<uint32_t>(p + 12);
  const uint16_t n = get<uint16_t>(p + 32);
  if (34 + 6 * static_cast<uint64_t>(n) > len)
    throw FormatError("LASzip VLR declares " + std::to_string(n) + " items, more than its " +
                          std::to_string(len) + " bytes hold",
                      at);
  for (uint16_t i = 0; i < n; ++i) {
    const uint8_t* e = p + 34 + 6 * i;
    v.items.push_back(Item{get<uint16_t>(e), get<uint16_t>(e + 2), get<uint16_t>(e + 4)});
  }
  const std::string lz = "LASzip " + std::to_string(v.version_major) + "." +
                         std::to_string(v.version_minor) + "r" + std::to_string(v.revision);
  if (v.coder != 0)
    throw FormatError("LAZ file uses entropy coder " + std::to_string(v.coder) + " (" + lz +
                          "); only the arithmetic coder (0) is defined",
                      at + 2);
  if (v.compressor < 1 || v.compressor > 3)
    throw FormatError("LAZ file uses compressor " + std::to_string(v.compressor) + " (" + lz +
                          "); supported: 1 point-wise, 2 point-wise chunked, 3 layered chunked",
                      at);
  if (v.compressor != 1 && v.chunk_size == 0)
    throw FormatError("LAZ file declares a chunk size of 0", at + 12);
  return v;
}

void check_items(const LaszipVlr& v, int pf, size_t rl) {
  size_t total = 0;
  const bool layered = v.compressor == 3;
  for (const Item& it : v.items) {
    const std::string name = item_name(it.type) + " version " + std::to_string(it.version);
    bool ok = false;
    int expected_size = -1;
    switch (it.type) {
      case kPoint10: ok = !layered && (it.version == 1 || it.version == 2); expected_size = 20; break;
      case kGpsTime11: ok = !layered && (it.version == 1 || it.version == 2); expected_size = 8; break;
      case kRgb12: ok = !layered && (it.version == 1 || it.version == 2); expected_size = 6; break;
      case kByte: ok = !layered && (it.version == 1 || it.version == 2); break;
      case kWavePacket13: ok = !layered && (it.version == 1 || it.version == 2); expected_size = 29; break;
      case kPoint14: ok = layered && (it.version == 3 || it.version == 4); expected_size = 30; break;
      case kRgb14: ok = layered && (it.version == 3 || it.version == 4); expected_size = 6; break;
      case kRgbNir14: ok = layered && (it.version == 3 || it.version == 4); expected_size = 8; break;
      case kByte14: ok = layered && (it.version == 3 || it.version == 4); break;
      case kWavePacket14: ok = layered && (it.version == 3 || it.version == 4); expected_size = 29; break;
      default: break;
    }
    if (!ok)
      throw FormatError("LAZ item " + name + " is not supported with the " +
                            (layered ? "layered" : "point-wise") + " compressor " +
                            std::to_string(v.compressor) + " (point format " + std::to_string(pf) +
                            ")",
                        -1);
    if (expected_size >= 0 && it.size != expected_size)
      throw FormatError("LAZ item " + name + " has size " + std::to_string(it.size) +
                            " instead of " + std::to_string(expected_size),
                        -1);
    if (it.size == 0)
      throw FormatError("LAZ item " + name + " has size 0", -1);
    total += it.size;
  }
  if (v.items.empty() || (v.items[0].type != kPoint10 && v.items[0].type != kPoint14))
    throw FormatError("LAZ items do not start with POINT10 or POINT14", -1);
  // The decoders read the items in LASzip's order: point, GPS time (in
  // POINT14), colour (with NIR), wave packet, extra bytes; each once.
  auto rank = [](uint16_t type) {
    switch (type) {
      case kPoint10: case kPoint14: return 0;
      case kGpsTime11: return 1;
      case kRgb12: case kRgb14: case kRgbNir14: return 2;
      case kWavePacket13: case kWavePacket14: return 3;
      default: return 4;
    }
  };
  for (size_t i = 1; i < v.items.size(); ++i)
    if (rank(v.items[i].type) <= rank(v.items[i - 1].type))
      throw FormatError("LAZ item " + item_name(v.items[i].type) + " comes after " +
                            item_name(v.items[i - 1].type) +
                            ", out of LASzip's order (or twice)",
                        -1);
  if ((pf >= 6) != (v.items[0].type == kPoint14))
    throw FormatError("LAZ item " + item_name(v.items[0].type) + " does not match point format " +
                          std::to_string(pf),
                      -1);
  if (total != rl)
    throw FormatError("LAZ items add up to " + std::to_string(total) +
                          " bytes per point, but the header's point record length is " +
                          std::to_string(rl),
                      105);
}

void decompress(const uint8_t* d, size_t file_size, uint64_t point_offset, uint64_t data_end,
                uint64_t count, size_t rl, const LaszipVlr& vlr, const std::function<void()>& ready,
                const ChunkSink& sink) {
  if (count == 0) return;
  Progress* progress = current_progress();
  if (progress) progress->expect(count);

  auto make_decoder = [&]() {
    return vlr.compressor == 3 ? make_layered_decoder(vlr, rl) : make_pointwise_decoder(vlr, rl);
  };
  const uint64_t first_chunk = vlr.compressor == 1 ? point_offset : point_offset + 8;
  if (data_end < first_chunk)
    throw FormatError("LAZ point data is truncated: no room for the chunk table offset",
                      static_cast<int64_t>(point_offset));
  int64_t table_at = vlr.compressor == 1 ? 0 : get<int64_t>(d + point_offset);
  std::optional<ChunkTable> table;
  if (table_at == -1 && file_size >= 8) {
    // A streaming writer's table pointer, in the file's last 8 bytes; if
    // those hold something else (an EVLR), the chunks are scanned instead.
    table_at = get<int64_t>(d + file_size - 8);
    try {
      if (table_at > 0)
        table = read_chunk_table(d, static_cast<uint64_t>(table_at), first_chunk, data_end,
                                 file_size, vlr.chunk_size, rl);
    } catch (const FormatError&) {
      table.reset();
    }
  } else if (table_at > 0) {
    table = read_chunk_table(d, static_cast<uint64_t>(table_at), first_chunk, data_end, file_size,
                             vlr.chunk_size, rl);
  }
  const uint64_t chunks_end = table ? static_cast<uint64_t>(table_at) : data_end;
  // LAZ shrinks points some 5 to 20 times; a count needing over 1000 times
  // the compressed bytes is a corrupt header, not a file to allocate for
  // (the caller allocates its columns for `count` points).
  if (count / 1000 > (chunks_end - first_chunk) / rl + 1)
    throw FormatError("the header declares " + std::to_string(count) + " points of " +
                          std::to_string(rl) + " bytes, implausibly many for " +
                          std::to_string(chunks_end - first_chunk) + " bytes of LAZ data",
                      static_cast<int64_t>(point_offset));

  if (vlr.compressor == 1) {
    // One stream for all points, no chunks: decoded in pieces of a chunk's
    // size, handed to the sink as they come.
    std::vector<uint8_t> buf;
    auto dec = make_decoder();
    const uint8_t* end = nullptr;
    ready();
    try {
      io::resize_fresh(buf, count * rl);
      dec->decode(d + first_chunk, d + chunks_end, count, count, buf.data(), &end, false);
    } catch (const FormatError& e) {
      throw FormatError("LAZ point data is corrupt: " + std::string(e.what()),
                        static_cast<int64_t>(point_offset));
    }
    sink(0, buf.data(), count);
    if (progress) progress->advance(count);
    return;
  }

  if (table) {
    // Points per chunk: from the table (variable), the chunk size (fixed),
    // or the chunk itself (layered chunks store their count).
    const size_t n = table->start.size();
    uint64_t total = 0;
    if (vlr.chunk_size == kVariableChunks) {
      for (uint64_t p : table->points) total += p;
    } else {
      const uint64_t cs = vlr.chunk_size;
      if (n == 0 || count > n * cs || count <= (n - 1) * cs)
        throw FormatError("the header declares " + std::to_string(count) +
                              " points, but the LAZ chunk table holds " + std::to_string(n) +
                              " chunks of " + std::to_string(cs) + " points",
                          static_cast<int64_t>(table_at));
      for (size_t i = 0; i < n; ++i) {
        table->points[i] = i + 1 < n ? cs : count - (n - 1) * cs;
        total += table->points[i];
      }
    }
    if (total != count)
      throw FormatError("the header declares " + std::to_string(count) +
                            " points, but the LAZ chunk table's chunks hold " + std::to_string(total),
                        static_cast<int64_t>(table_at));
    std::vector<uint64_t> first_point(n + 1, 0);
    for (size_t i = 0; i < n; ++i) {
      if (table->points[i] > 0 && table->bytes[i] < rl)
        throw FormatError(chunk_error(i, table->start[i],
                                      "its " + std::to_string(table->bytes[i]) +
                                          " bytes cannot hold even one " + std::to_string(rl) +
                                          "-byte point"),
                          static_cast<int64_t>(table->start[i]));
      first_point[i + 1] = first_point[i] + table->points[i];
    }
    ready();
    // Each thread decodes a chunk into its own buffer (a chunk's records fit
    // in cache) and hands it to the sink at once.
    struct Worker {
      std::unique_ptr<ChunkDecoder> decoder;
      std::vector<uint8_t> records;
    };
    tbb::enumerable_thread_specific<Worker> workers([&] { return Worker{make_decoder(), {}}; });
    // Errors are collected per chunk and the first one reported, so the
    // message does not depend on thread timing.
    std::vector<std::string> errors(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        try {
          if (progress) progress->check();
          const uint64_t pts = table->points[i];
          if (pts == 0) continue;
          Worker& w = workers.local();
          if (w.records.size() < pts * rl) w.records.resize(pts * rl);
          const uint8_t* end = nullptr;
          const uint8_t* begin = d + table->start[i];
          const uint64_t got = w.decoder->decode(begin, begin + table->bytes[i], pts, pts,
                                                 w.records.data(), &end, true);
          if (got != pts)
            throw FormatError("it holds " + std::to_string(got) + " points instead of " +
                                  std::to_string(pts),
                              -1);
          sink(first_point[i], w.records.data(), pts);
          if (progress) progress->advance(pts);
        } catch (const FormatError& e) {
          errors[i] = e.what();
        } catch (const Cancelled&) {
          errors[i] = "\x01";
        }
      }
    });
    for (size_t i = 0; i < n; ++i) {
      if (errors[i].empty()) continue;
      if (errors[i] == "\x01") throw Cancelled();
      throw FormatError(chunk_error(i, table->start[i], errors[i]),
                        static_cast<int64_t>(table->start[i]));
    }
    return;
  }

  // No usable chunk table: decode the chunks one after the other, each
  // starting where the previous one ended.
  if (vlr.chunk_size == kVariableChunks && vlr.compressor != 3)
    throw FormatError("LAZ file has variable-size chunks but no readable chunk table",
                      static_cast<int64_t>(point_offset));
  auto dec = make_decoder();
  std::vector<uint8_t> buf;
  ready();
  uint64_t done = 0;
  uint64_t at = first_chunk;
  for (size_t i = 0; done < count; ++i) {
    if (progress) progress->check();
    if (at >= chunks_end)
      throw FormatError("LAZ point data is truncated: the header declares " +
                            std::to_string(count) + " points, the data ends after " +
                            std::to_string(done) + " (no chunk table was found)",
                        static_cast<int64_t>(at));
    uint64_t want = count - done;
    if (vlr.chunk_size != kVariableChunks) want = std::min<uint64_t>(want, vlr.chunk_size);
    // A layered chunk states its count after its first point: the buffer
    // need hold no more (and the decoder checks the count against it).
    if (dec->self_delimiting() && chunks_end - at >= rl + 4)
      want = std::min<uint64_t>(want, std::max<uint32_t>(get<uint32_t>(d + at + rl), 1));
    if (buf.size() < want * rl) buf.resize(want * rl);
    const uint8_t* end = nullptr;
    uint64_t got = 0;
    try {
      got = dec->decode(d + at, d + chunks_end, dec->self_delimiting() ? 0 : want, want,
                        buf.data(), &end, false);
    } catch (const FormatError& e) {
      throw FormatError(chunk_error(i, at, e.what()), static_cast<int64_t>(at));
    }
    if (got == 0)
      throw FormatError(chunk_error(i, at, "it holds no points"), static_cast<int64_t>(at));
    sink(done, buf.data(), got);
    done += got;
    at = static_cast<uint64_t>(end - d);
    if (progress) progress->advance(got);
  }
}

std::vector<uint8_t> decompress(const uint8_t* d, size_t file_size, uint64_t point_offset,
                                uint64_t data_end, uint64_t count, size_t rl,
                                const LaszipVlr& vlr) {
  std::vector<uint8_t> raw;
  decompress(d, file_size, point_offset, data_end, count, rl, vlr, [&] { raw.resize(count * rl); },
             [&](uint64_t first, const uint8_t* records, uint64_t n) {
               std::memcpy(raw.data() + first * rl, records, n * rl);
             });
  return raw;
}

}  // namespace pointnpr::laz
