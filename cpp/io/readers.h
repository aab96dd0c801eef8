#pragma once
// Point cloud file readers. All throw pointnpr::ReadError (core/error.h) with
// the file, a reason a user can act on and, where it applies, the byte offset.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "io/point_data.h"

namespace pointnpr {

// Dispatches on the extension (.las .laz .e57 .ply .spz .pcd .xyz .pts .txt .csv),
// falling back to the file's signature when the extension is unknown.
PointData read_point_cloud(const std::string& path);

// ASPRS LAS 1.0-1.4, point formats 0-10 (waveform packets ignored).
PointData read_las(const std::string& path);
// A LAS or LAZ file's metadata (read_las's, with point_count) and no points:
// the header and VLRs are read and checked, the point data is not.
PointData read_las_header(const std::string& path);

// A block of a LAS/LAZ file's points as stream_las hands them over: points
// [first, first + count) of the file, the arrays valid during the call.
struct ScanBlock {
  uint64_t first = 0;
  size_t count = 0;
  const double* positions = nullptr;       // x, y, z (raw integer * scale + offset)
  const uint16_t* rgb16 = nullptr;         // r, g, b as stored (16 bits), or null: no colour
  const float* intensity = nullptr;        // as read_las gives it
  const uint8_t* classification = nullptr;
};
using ScanBlockSink = std::function<void(const ScanBlock&)>;
// Reads a LAS or LAZ file block after block without holding it whole: LAS
// records in blocks of `block_points`, in file order; LAZ chunk by chunk
// (decoded in parallel), in any order, the sink called by one thread at a
// time. The same checks and ReadErrors as read_las.
void stream_las(const std::string& path, const ScanBlockSink& sink, uint64_t block_points = uint64_t{1} << 20);

// Stanford PLY: ascii, binary_little_endian, binary_big_endian; vertices only.
PointData read_ply(const std::string& path);
// Niantic's SPZ (3D Gaussian splats), versions 2 to 4: the attributes of
// io/gaussians.h, turned from SPZ's right-up-back axes to 3DGS PLY's
// right-down-front ones. (A 3DGS PLY is read by read_ply, the same way.)
PointData read_spz(const std::string& path);
// PCL PCD v0.7 (ascii, binary, binary_compressed); non-finite points dropped.
PointData read_pcd(const std::string& path);
// Whitespace/comma separated text: x y z [r g b | intensity ...].
PointData read_text(const std::string& path);

// ASTM E2807 (E57) 1.x: every /data3D scan, one PointData each, in file
// order: positions with the scan's pose applied, spherical coordinates made
// cartesian (both in double), points whose cartesian/sphericalInvalidState
// is not 0 left out; intensity (its limits in metadata), colours scaled to
// 8 bits by their limits, normals (libE57's nor: extension, turned by the
// pose), row/column indices, returns, timeStamp (see docs/io.md). Every
// page's CRC-32C is checked. Metadata per scan: scan_name, scan_guid,
// pose_rotation (w, x, y, z), pose_translation, coordinate_metadata,
// images2d (one line per image), ...
std::vector<PointData> read_e57_scans(const std::string& path);
// All scans of an E57 file as one PointData: the attributes every scan has,
// plus "scan_index" (uint32, the scan each point came from); metadata
// "scan_names" (one per line), "scan_count" and "scan_origins" (each
// scan's pose translation, its scanner position: 3 per scan).
PointData read_e57(const std::string& path);

// The same readers on bytes in memory (fuzzing, embedded data). `name` takes
// the place of the path in messages and in extension-dependent choices
// (".laz", ".pts"). The bytes must stay valid during the call.
PointData read_las_memory(const uint8_t* data, size_t size, const std::string& name);
PointData read_ply_memory(const uint8_t* data, size_t size, const std::string& name);
PointData read_spz_memory(const uint8_t* data, size_t size, const std::string& name);
PointData read_pcd_memory(const uint8_t* data, size_t size, const std::string& name);
PointData read_text_memory(const uint8_t* data, size_t size, const std::string& name);
// verify_checksums = false skips the pages' CRC-32C (fuzzing reaches the
// layers behind them); files are always read with it.
std::vector<PointData> read_e57_scans_memory(const uint8_t* data, size_t size, const std::string& name,
                                             bool verify_checksums = true);
PointData read_e57_memory(const uint8_t* data, size_t size, const std::string& name,
                          bool verify_checksums = true);

// Writes `data` to `path`, the format chosen by the extension: ".ply"
// (binary little endian) or ".las" (LAS 1.4, point format 6, 7 or 8).
// Throws pointnpr::Error when the data cannot be represented or the file
// cannot be written; a partly written file is removed.
void write_point_cloud(const std::string& path, const PointData& data);
void write_ply(const std::string& path, const PointData& data);
void write_las(const std::string& path, const PointData& data);

}  // namespace pointnpr
