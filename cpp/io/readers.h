#pragma once
// Point cloud file readers. All throw pointnpr::ReadError (core/error.h) with
// the file, a reason a user can act on and, where it applies, the byte offset.
#include <string>

#include "io/point_data.h"

namespace pointnpr {

// Dispatches on the extension (.las .laz .ply .pcd .xyz .pts .txt .csv),
// falling back to the file's signature when the extension is unknown.
PointData read_point_cloud(const std::string& path);

// ASPRS LAS 1.0-1.4, point formats 0-10 (waveform packets ignored).
PointData read_las(const std::string& path);
// Stanford PLY: ascii, binary_little_endian, binary_big_endian; vertices only.
PointData read_ply(const std::string& path);
// PCL PCD v0.7 (ascii, binary, binary_compressed); non-finite points dropped.
PointData read_pcd(const std::string& path);
// Whitespace/comma separated text: x y z [r g b | intensity ...].
PointData read_text(const std::string& path);

}  // namespace pointnpr
