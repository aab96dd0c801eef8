// The out-of-core scan cache (io/scan_cache.h, scene/cached_cloud.h): exact
// round trips, damaged files refused with a message that says why, the
// streamed prefixes are the resolution queue's, memory follows the budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <sstream>

#include "io/scan_cache.h"
#include "render/gpu_cloud.h"
#include "scene/cached_cloud.h"
#include "test_io_util.h"

namespace pointnpr {
namespace {

using test_io::scratch_dir;

struct Scan {
  std::vector<double> positions;
  std::vector<uint8_t> colors;
  std::vector<float> intensity;
  std::vector<uint8_t> classification;
  std::vector<uint32_t> ids;
  std::vector<float> normals;
};

// A georeferenced scan (1e6 m away) with every attribute the cache holds.
Scan make_scan(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Scan s;
  for (size_t i = 0; i < n; ++i) {
    s.positions.insert(s.positions.end(), {6.5e5 + 200.0 * u(rng), 6.8e6 + 150.0 * u(rng), 40.0 * u(rng)});
    for (int c = 0; c < 4; ++c) s.colors.push_back(uint8_t(rng() & 0xFF));
    s.intensity.push_back(float(u(rng) * 1000.0));
    s.classification.push_back(uint8_t(rng() % 20));
    s.ids.push_back(uint32_t(3 * i + 7));  // not 0..n-1: the ids are kept, not recomputed
    s.normals.insert(s.normals.end(), {float(u(rng) - 0.5), float(u(rng) - 0.5), 1.0f});
  }
  return s;
}

PointCloud make_cloud(const Scan& s, uint32_t chunk = 16384) {
  PointCloudInput in;
  in.positions = s.positions;
  in.colors = s.colors;
  in.color_channels = 4;
  in.intensity = s.intensity;
  in.classification = s.classification;
  in.point_index = s.ids;
  in.normals = s.normals;
  return PointCloud(in, chunk);
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string write_cache(const PointCloud& cloud, const std::string& name) {
  const std::string path = (scratch_dir() / name).string();
  io::write_scan_cache(path, cloud);
  return path;
}

std::string open_error(const std::string& path) {
  try {
    io::ScanCache cache(path);
  } catch (const ReadError& e) {
    EXPECT_EQ(e.file(), path);
    return e.reason();
  }
  ADD_FAILURE() << "opening " << path << " did not fail";
  return "";
}

template <class T>
T load(const uint8_t* p, size_t i) {
  T v;
  std::memcpy(&v, p + sizeof(T) * i, sizeof(T));
  return v;
}

TEST(IoScanCache, RoundTripIsExactInQueueOrder) {
  const Scan scan = make_scan(40000, 1);
  const PointCloud cloud = make_cloud(scan, 5000);
  const std::string path = write_cache(cloud, "round_trip.pnprcache");
  const io::ScanCache cache(path);
  ASSERT_EQ(cache.size(), cloud.size());
  ASSERT_EQ(cache.chunks().size(), cloud.chunks().size());
  EXPECT_EQ(cache.bounds_min(), cloud.bounds_min());
  EXPECT_EQ(cache.bounds_max(), cloud.bounds_max());
  for (Attribute a : {Attribute::Color, Attribute::Intensity, Attribute::Classification, Attribute::Normal})
    EXPECT_TRUE(cache.has(a));
  const std::vector<uint32_t> order = queue_order(cloud);
  // id -> input index, to compare the world positions with the input doubles.
  std::map<uint32_t, size_t> input_of;
  for (size_t i = 0; i < scan.ids.size(); ++i) input_of[scan.ids[i]] = i;
  std::set<uint32_t> seen;
  for (size_t c = 0; c < cloud.chunks().size(); ++c) {
    const PointChunk& ch = cloud.chunks()[c];
    const io::ScanCacheChunk& cc = cache.chunks()[c];
    EXPECT_EQ(cc.origin, ch.origin);
    EXPECT_EQ(cc.local_min, ch.local_min);
    EXPECT_EQ(cc.local_max, ch.local_max);
    ASSERT_EQ(cc.count, ch.count);
    const io::ScanCacheChunkData d = cache.chunk(c);
    for (uint32_t i = 0; i < ch.count; ++i) {
      const uint32_t k = ch.first + order[ch.first + i];  // the cloud's point at queue position i
      EXPECT_EQ(load<glm::vec3>(d.positions, i), cloud.local_positions()[k]);
      EXPECT_EQ(load<uint32_t>(d.point_index, i), cloud.point_index()[k]);
      EXPECT_EQ(load<uint32_t>(d.layout_rank, i), order[ch.first + i]);
      EXPECT_EQ(load<uint32_t>(d.colors, i), cloud.colors()[k]);
      EXPECT_EQ(load<float>(d.intensity, i), cloud.intensity()[k]);
      EXPECT_EQ(uint32_t(d.classification[i]), cloud.classification()[k]);
      EXPECT_EQ(load<glm::vec3>(d.normals, i), cloud.normals()[k]);
      // World position: double origin + float offset, as exact as the in-memory cloud (float offsets
      // of a chunk of 200 m: well under a millimetre).
      const uint32_t id = load<uint32_t>(d.point_index, i);
      const size_t in = input_of.at(id);
      const glm::dvec3 world = cc.origin + glm::dvec3(load<glm::vec3>(d.positions, i));
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(world[a], scan.positions[3 * in + a], 1e-4);
      EXPECT_EQ(scan.classification[in], d.classification[i]);
      seen.insert(id);
    }
  }
  EXPECT_EQ(seen.size(), scan.ids.size());
  // Deterministic bytes: the same cloud writes the same file.
  const std::string again = write_cache(make_cloud(scan, 5000), "round_trip_again.pnprcache");
  EXPECT_EQ(bytes_of(path), bytes_of(again));
}

TEST(IoScanCache, CloudWithoutAttributesKeepsOnlyPositionsAndIds) {
  std::vector<double> p{0, 0, 0, 1, 2, 3, -1, 5, 2};
  PointCloudInput in;
  in.positions = p;
  const PointCloud cloud(in);
  const io::ScanCache cache(write_cache(cloud, "bare.pnprcache"));
  EXPECT_EQ(cache.flags(), 0u);
  EXPECT_EQ(cache.file_bytes(), io::kScanCacheHeaderBytes + io::kScanCacheTableEntryBytes + 3 * 20);
  const io::ScanCacheChunkData d = cache.chunk(0);
  EXPECT_EQ(d.colors, nullptr);
  EXPECT_EQ(d.classification, nullptr);
  std::set<uint32_t> ids;
  for (uint32_t i = 0; i < 3; ++i) ids.insert(load<uint32_t>(d.point_index, i));
  EXPECT_EQ(ids, (std::set<uint32_t>{0, 1, 2}));
}

TEST(IoScanCache, TruncatedCachesAreRefused) {
  const std::string path = write_cache(make_cloud(make_scan(3000, 2), 1000), "whole.pnprcache");
  const std::string bytes = bytes_of(path);
  for (size_t keep : {size_t(0), size_t(5), size_t(100), size_t(200), bytes.size() / 2, bytes.size() - 1}) {
    const std::string cut = test_io::write_file("cut.pnprcache", bytes.substr(0, keep));
    const std::string why = open_error(cut);
    if (keep < 8)
      EXPECT_NE(why.find("not a PointNPR scan cache"), std::string::npos) << why;
    else
      EXPECT_NE(why.find("truncated"), std::string::npos) << keep << ": " << why;
  }
  const std::string longer = test_io::write_file("longer.pnprcache", bytes + "extra");
  EXPECT_NE(open_error(longer).find("5 bytes after its end"), std::string::npos);
}

TEST(IoScanCache, AlteredBytesAreFoundByTheChecksums) {
  const PointCloud cloud = make_cloud(make_scan(3000, 3), 1000);
  const std::string bytes = bytes_of(write_cache(cloud, "intact.pnprcache"));
  auto altered = [&](size_t at) {
    std::string b = bytes;
    b[at] = char(b[at] ^ 0x10);
    return test_io::write_file("altered.pnprcache", b);
  };
  EXPECT_NE(open_error(altered(30)).find("header's checksum"), std::string::npos);
  EXPECT_NE(open_error(altered(io::kScanCacheHeaderBytes + 50)).find("chunk table's checksum"), std::string::npos);
  // A point's byte: the table is intact, so the cache opens; the chunk is refused when first read.
  const size_t second_chunk = io::kScanCacheHeaderBytes + 3 * io::kScanCacheTableEntryBytes +
                              io::scan_cache_chunk_bytes(1000, io::ScanCache(write_cache(cloud, "x.pnprcache")).flags());
  const std::string path = altered(second_chunk + 123);
  const io::ScanCache cache(path);
  EXPECT_NO_THROW(cache.chunk(0));
  try {
    cache.chunk(1);
    ADD_FAILURE() << "an altered chunk was read";
  } catch (const ReadError& e) {
    EXPECT_NE(e.reason().find("chunk 1's checksum does not match"), std::string::npos) << e.what();
    EXPECT_EQ(e.byte_offset(), int64_t(second_chunk));
  }
  // Through the cached cloud: a render of that chunk fails with the same error, nothing is kept.
  const CachedCloud cached(path);
  EXPECT_THROW(cached.stream(cached.counts_for_budget(3000)), ReadError);
  EXPECT_EQ(cached.stream_points(), 0u);
  EXPECT_NO_THROW(cached.stream({1000, 0, 1000}));
}

TEST(IoScanCache, LayoutRanksThatAreNoPermutationAreRefusedEvenWithValidChecksums) {
  const PointCloud cloud = make_cloud(make_scan(100, 8), 100);
  std::string b = bytes_of(write_cache(cloud, "ranks.pnprcache"));
  auto* d = reinterpret_cast<uint8_t*>(b.data());
  const size_t chunk = io::kScanCacheHeaderBytes + io::kScanCacheTableEntryBytes;
  std::memcpy(d + chunk + 16 * 100 + 4 * 7, d + chunk + 16 * 100 + 4 * 3, 4);  // rank 3 twice
  // A file that lies consistently: every checksum recomputed.
  const uint32_t chunk_crc = io::crc32(d + chunk, io::scan_cache_chunk_bytes(100, io::ScanCache(
                                                      write_cache(cloud, "ranks_flags.pnprcache")).flags()));
  std::memcpy(d + io::kScanCacheHeaderBytes + 52, &chunk_crc, 4);
  const uint32_t table_crc = io::crc32(d + io::kScanCacheHeaderBytes, io::kScanCacheTableEntryBytes);
  std::memcpy(d + 104, &table_crc, 4);
  const uint32_t header_crc = io::crc32(d, 124);
  std::memcpy(d + 124, &header_crc, 4);
  const io::ScanCache cache(test_io::write_file("lying.pnprcache", b));
  try {
    cache.chunk(0);
    ADD_FAILURE() << "duplicate layout ranks were accepted";
  } catch (const ReadError& e) {
    EXPECT_NE(e.reason().find("layout ranks are not a permutation"), std::string::npos) << e.what();
  }
}

TEST(IoScanCache, OtherVersionsAndOtherFilesAreRefused) {
  std::string bytes = bytes_of(write_cache(make_cloud(make_scan(500, 4)), "v1.pnprcache"));
  bytes[8] = 2;  // version 2: a newer PointNPR's cache
  const std::string why = open_error(test_io::write_file("v2.pnprcache", bytes));
  EXPECT_NE(why.find("scan cache version 2, this PointNPR reads version 1"), std::string::npos) << why;
  EXPECT_NE(why.find("import the scan again"), std::string::npos) << why;
  const std::string las = test_io::write_file("not_a_cache.pnprcache", std::string("LASF") + std::string(300, '\0'));
  EXPECT_NE(open_error(las).find("not a PointNPR scan cache"), std::string::npos);
  EXPECT_NE(open_error((scratch_dir() / "missing.pnprcache").string()).find("cannot open"), std::string::npos);
}

TEST(IoScanCache, StreamedPrefixesAreTheResolutionQueuesPrefixes) {
  const PointCloud cloud = make_cloud(make_scan(20000, 5), 4000);
  const CachedCloud cached(write_cache(cloud, "prefix.pnprcache"));
  const std::vector<uint32_t> order = queue_order(cloud);
  const std::vector<uint32_t> counts{0, 17, 4000, 1, 999};
  const auto streamed = cached.stream(counts);
  ASSERT_EQ(streamed->size(), 17u + 4000 + 1 + 999);
  ASSERT_EQ(streamed->chunks().size(), 4u);  // the chunk drawing none is left out
  // Each chunk's first counts[c] of its queue, drawn in the cloud's own (spatial) order.
  size_t k = 0;
  for (size_t c = 0; c < counts.size(); ++c) {
    const PointChunk& ch = cloud.chunks()[c];
    std::vector<uint32_t> ranks(order.begin() + ch.first, order.begin() + ch.first + counts[c]);
    std::sort(ranks.begin(), ranks.end());
    for (uint32_t r : ranks) {
      ASSERT_EQ(streamed->point_index()[k], cloud.point_index()[ch.first + r]);
      ASSERT_EQ(streamed->local_positions()[k], cloud.local_positions()[ch.first + r]);
      ++k;
    }
  }
  // The whole of every chunk: the cloud itself, point for point.
  std::vector<uint32_t> all;
  for (const PointChunk& ch : cloud.chunks()) all.push_back(ch.count);
  const auto whole = cached.stream(all);
  EXPECT_EQ(whole->point_index(), cloud.point_index());
  EXPECT_EQ(whole->colors(), cloud.colors());
  EXPECT_EQ(whole->classification(), cloud.classification());
  EXPECT_NE(whole, streamed);
  EXPECT_EQ(cached.stream(all), whole);  // unchanged counts: the same cloud (no upload)
}

TEST(IoScanCache, BudgetsSharePointsByWeightAndGrowOnlyAtTheQueuesEnd) {
  const PointCloud cloud = make_cloud(make_scan(50000, 6), 10000);
  const CachedCloud cached(write_cache(cloud, "budget.pnprcache"));
  const std::vector<double> weights{100.0, 0.0, 300.0, 1.0, 100.0};
  std::vector<uint32_t> previous(5, 0);
  for (uint64_t budget : {0u, 10u, 1000u, 5000u, 20000u, 25000u, 40000u, 1000000u}) {
    const std::vector<uint32_t> counts = cached.counts_for(weights, budget);
    const uint64_t total = std::accumulate(counts.begin(), counts.end(), uint64_t(0));
    EXPECT_LE(total, budget);
    EXPECT_EQ(counts[1], 0u);  // out of view
    for (size_t c = 0; c < 5; ++c) {
      EXPECT_LE(counts[c], 10000u);
      EXPECT_GE(counts[c], previous[c]) << "a larger budget removed points of chunk " << c;
    }
    // Uncapped chunks are drawn at one density: points per weight.
    if (counts[2] < 10000 && counts[0] >= 100) {  // (small budgets: rounding)
      EXPECT_NEAR(double(counts[2]) / counts[0], 3.0, 0.01);
    }
    // What capped chunks leave goes to the others: nearly all of the budget is used.
    EXPECT_GE(double(total), std::min(double(budget), 30000.0) - 5.0);
    previous = counts;
  }
  EXPECT_EQ(cached.counts_for(weights, 1000000), (std::vector<uint32_t>{10000, 0, 10000, 10000, 10000}));
  EXPECT_EQ(cached.counts_for_budget(25000), (std::vector<uint32_t>{5000, 5000, 5000, 5000, 5000}));
}

// Resident bytes of the mappings of `path` in this process (/proc/self/smaps).
uint64_t resident_bytes_of_mapping(const std::string& path) {
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  uint64_t kb = 0;
  while (std::getline(smaps, line)) {
    // A mapping's line starts "lo-hi perms ..." and ends with its path; its fields ("Rss:   12 kB") follow.
    const std::string first = line.substr(0, line.find(' '));
    if (first.find('-') != std::string::npos && first.find(':') == std::string::npos) {
      inside = line.size() >= path.size() && line.compare(line.size() - path.size(), path.size(), path) == 0;
      continue;
    }
    if (inside && line.rfind("Rss:", 0) == 0) kb += std::stoull(line.substr(4));
  }
  return kb * 1024;
}

TEST(IoScanCache, MemoryFollowsTheBudgetNotTheScan) {
  const uint64_t budget = 20000;
  uint64_t small_scan_bytes = 0;
  for (size_t points : {size_t(100000), size_t(400000)}) {
    const std::string path = write_cache(make_cloud(make_scan(points, 7)), "mem" + std::to_string(points) + ".pnprcache");
    const CachedCloud cached(path, budget);
    EXPECT_EQ(cached.stream_bytes(), 0u);  // opening reads the header and table only
    EXPECT_LT(resident_bytes_of_mapping(path), 64u * 1024);
    for (int frame = 0; frame < 3; ++frame) {
      // Three "views", each a different share of the chunks.
      std::vector<double> weights(cached.cache().chunks().size(), 0.0);
      for (size_t c = size_t(frame); c < weights.size(); c += 2) weights[c] = 1.0 + double(c);
      const auto cloud = cached.stream(cached.counts_for(weights, budget));
      EXPECT_LE(cloud->size(), budget);
      // Positions, ids, colours, intensity, classification (uint32), normals: 40 bytes a point, plus the chunk list.
      EXPECT_LE(cached.stream_bytes(), budget * 40 + cached.cache().chunks().size() * sizeof(PointChunk));
      // The mapping's pages were handed back after the copy (its checksums read whole chunks).
      EXPECT_LT(resident_bytes_of_mapping(path), 64u * 1024) << points << " points, frame " << frame;
    }
    if (points == 100000)
      small_scan_bytes = cached.stream_bytes();
    else
      EXPECT_LE(double(cached.stream_bytes()), 1.1 * double(small_scan_bytes));  // 4x the scan, same memory
  }
}

}  // namespace
}  // namespace pointnpr
