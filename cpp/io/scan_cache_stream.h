#pragma once
// Scan caches written straight from a scan read block after block
// (stream_las), in memory bounded by an option, not by the scan: the
// importer's way for scans larger than memory (docs/io.md#scan-cache).
//
// The caches are the bytes write_scan_cache writes for the PointCloud the
// in-memory import would build (float32 offsets from `origin`, one cloud per
// class when split, point ids the row numbers within it): the same Morton
// order, chunks and resolution queues. That order is found by an external
// sort: the scan's Morton codes are counted in buckets (and the buckets
// too full for the budget counted again, finer), consecutive buckets form
// runs that fit the budget, the points are scattered run by run into a
// temporary file beside the caches, and each run is sorted in memory and
// cut into chunks.
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "io/readers.h"

namespace pointnpr::io {

struct StreamedCacheOptions {
  // Subtracted in double, then rounded to float: the offsets a mesh of the
  // scan holds after recentring.
  glm::dvec3 origin{0.0};
  // Instead: the centre of the scan's bounds rounded to whole units (as the
  // importer recentres), found by the first pass.
  bool recentre = false;
  bool split_by_classification = false;  // one cache per class
  // The sort's runs, its write buffers and one chunk; a run of points
  // that share their first 36 Morton bits (a cell 1/4096 of the scan's
  // extent wide) is sorted whole even when larger.
  uint64_t memory_bytes = uint64_t{256} << 20;
  uint32_t max_chunk_points = 16384;
};

struct StreamedCache {
  int classification = -1;  // -1: all the points (not split)
  std::string path;
  uint64_t points = 0;      // finite points written
  uint64_t rows = 0;        // points of the scan in this group (ids 0 .. rows - 1)
  size_t runs = 0;          // parts the sort ran in
  size_t refined_buckets = 0;  // Morton buckets counted again, finer
  glm::dvec3 origin{0.0};      // the offsets' origin (options.origin, or the one recentring chose)
};

// Reads the scan once per call, every block to the sink (stream_las).
using ScanPass = std::function<void(const ScanBlockSink&)>;

// Reads the scan three or four times. `path_for(classification)` names
// each cache (-1 when not split). Honours current_progress() (Cancelled);
// on any exception no cache and no temporary file is left.
std::vector<StreamedCache> write_scan_caches(const ScanPass& pass,
                                             const std::function<std::string(int classification)>& path_for,
                                             const StreamedCacheOptions& options = {});

}  // namespace pointnpr::io
