#include <cstring>
#include <string>

#include "core/error.h"
#include "io/mapped_file.h"
#include "io/readers.h"

namespace pointnpr {

namespace {

enum class Kind { Las, E57, Ply, Spz, Pcd, Text, Unknown };

Kind kind_from_extension(const std::string& ext) {
  if (ext == ".las" || ext == ".laz") return Kind::Las;
  if (ext == ".e57") return Kind::E57;
  if (ext == ".ply") return Kind::Ply;
  if (ext == ".spz") return Kind::Spz;
  if (ext == ".pcd") return Kind::Pcd;
  if (ext == ".xyz" || ext == ".pts" || ext == ".txt" || ext == ".csv" || ext == ".asc")
    return Kind::Text;
  return Kind::Unknown;
}

Kind kind_from_signature(const std::string& path) {
  io::MappedFile f(path);
  const char* d = reinterpret_cast<const char*>(f.data());
  const size_t n = f.size();
  if (n >= 4 && std::memcmp(d, "LASF", 4) == 0) return Kind::Las;
  if (n >= 8 && std::memcmp(d, "ASTM-E57", 8) == 0) return Kind::E57;
  if (n >= 4 && std::memcmp(d, "ply", 3) == 0 && (d[3] == '\n' || d[3] == '\r')) return Kind::Ply;
  const std::string head(d, std::min<size_t>(n, 256));
  if (head.rfind("# .PCD", 0) == 0 || head.rfind("VERSION", 0) == 0) return Kind::Pcd;
  return Kind::Unknown;
}

}  // namespace

PointData read_point_cloud(const std::string& path) {
  const std::string ext = io::file_extension(path);
  Kind kind = kind_from_extension(ext);
  if (kind == Kind::Unknown) kind = kind_from_signature(path);
  switch (kind) {
    case Kind::Las: return read_las(path);
    case Kind::E57: return read_e57(path);
    case Kind::Ply: return read_ply(path);
    case Kind::Spz: return read_spz(path);
    case Kind::Pcd: return read_pcd(path);
    case Kind::Text: return read_text(path);
    case Kind::Unknown: break;
  }
  throw ReadError(path, "unrecognised point cloud format" +
                            (ext.empty() ? std::string(" (no file extension)")
                                         : " (extension '" + ext + "')") +
                            "; supported: .las, .laz, .e57, .ply, .spz, .pcd, .xyz, .pts, .txt, .csv, .asc");
}

}  // namespace pointnpr
