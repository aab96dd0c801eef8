// 3DGS PLY columns to splat attributes (io/gaussians.h).
//
// The layout of the 3DGS reference implementation's point_cloud.ply
// (Kerbl et al. 2023): f_dc_0..2 the SH DC term per channel, f_rest_j the
// higher bands channel-major (j = c * (K - 1) + k - 1), opacity a logit,
// scale_0..2 natural logs of the standard deviations, rot_0..3 a quaternion
// w, x, y, z, not necessarily normalised.
#include "io/gaussians.h"

#include <algorithm>
#include <cmath>
#include <variant>
#include <vector>

#include "core/error.h"

namespace pointnpr::io {
namespace {

constexpr float kShC0 = 0.28209479177387814f;

// An attribute of one component as doubles, whatever its type; empty when absent.
std::vector<double> column(const PointData& data, const std::string& name) {
  const PointAttribute* a = data.find(name);
  if (!a || a->components != 1) return {};
  return std::visit([](const auto& v) { return std::vector<double>(v.begin(), v.end()); }, a->values);
}

float sigmoid(double x) { return float(1.0 / (1.0 + std::exp(-x))); }

}  // namespace

bool has_3dgs_properties(const PointData& data) {
  for (const char* name : {"f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2", "rot_0",
                           "rot_1", "rot_2", "rot_3"})
    if (!data.has(name)) return false;
  return true;
}

void colors_from_sh_dc(PointData& data, int coefficients) {
  const std::vector<float>* sh = data.get<float>("sh");
  const size_t n = data.num_points();
  std::vector<uint8_t> colors(n * 3);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const float v = 0.5f + kShC0 * (*sh)[(i * size_t(coefficients)) * 3 + size_t(c)];
      colors[3 * i + size_t(c)] = uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    }
  data.set("colors", 3, std::move(colors));
}

void convert_3dgs_ply(PointData& data, const std::string& file) {
  // A partial layout is refused rather than read as plain points.
  const bool any = data.has("f_dc_0") || data.has("scale_0") || data.has("rot_0");
  if (!any) return;
  for (const char* name : {"f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2", "rot_0",
                           "rot_1", "rot_2", "rot_3"})
    if (!data.has(name) || data.find(name)->components != 1)
      throw ReadError(file, std::string("a 3D Gaussian splat PLY (it has f_dc_*, scale_* or rot_*) needs the "
                                        "scalar vertex property '") + name + "', which is missing");
  int rest = 0;
  while (data.has("f_rest_" + std::to_string(rest))) ++rest;
  int degree = -1;
  for (int d = 0; d <= 3; ++d)
    if (rest == 3 * ((d + 1) * (d + 1) - 1)) degree = d;
  if (degree < 0)
    throw ReadError(file, "the PLY has " + std::to_string(rest) +
                              " f_rest_* properties (0 to f_rest_" + std::to_string(rest - 1) +
                              "); 3D Gaussian splats have 9, 24 or 45 (SH degree 1, 2 or 3), or none");
  for (const PointAttribute& a : data.attributes)
    if (a.name.rfind("f_rest_", 0) == 0) {
      const std::string tail = a.name.substr(7);
      const bool digits = !tail.empty() && std::all_of(tail.begin(), tail.end(), [](char c) { return c >= '0' && c <= '9'; });
      if (!digits || tail.size() > 3 || std::stoi(tail) >= rest)
        throw ReadError(file, "vertex property '" + a.name + "' does not follow f_rest_0 .. f_rest_" +
                                  std::to_string(rest - 1) + " without gaps");
    }
  const size_t n = data.num_points();
  const int K = (degree + 1) * (degree + 1);
  std::vector<float> sh(n * 3 * size_t(K)), opacity(n), scales(n * 3), rotations(n * 4);
  auto check = [&](double v, size_t i, const std::string& name) {
    if (!std::isfinite(v))
      throw ReadError(file, "vertex " + std::to_string(i) + " has a non-finite " + name + " (" + std::to_string(v) + ")");
    return v;
  };
  for (int c = 0; c < 3; ++c) {
    const std::string name = "f_dc_" + std::to_string(c);
    const std::vector<double> v = column(data, name);
    for (size_t i = 0; i < n; ++i) sh[i * 3 * size_t(K) + size_t(c)] = float(check(v[i], i, name));
  }
  for (int j = 0; j < rest; ++j) {
    const std::string name = "f_rest_" + std::to_string(j);
    const std::vector<double> v = column(data, name);
    const int c = j / (K - 1), k = j % (K - 1) + 1;
    for (size_t i = 0; i < n; ++i) sh[(i * size_t(K) + size_t(k)) * 3 + size_t(c)] = float(check(v[i], i, name));
  }
  {
    const std::vector<double> v = column(data, "opacity");
    for (size_t i = 0; i < n; ++i) opacity[i] = sigmoid(check(v[i], i, "opacity"));
  }
  for (int a = 0; a < 3; ++a) {
    const std::string name = "scale_" + std::to_string(a);
    const std::vector<double> v = column(data, name);
    for (size_t i = 0; i < n; ++i) {
      // exp of a log beyond float's range is no finite standard deviation.
      const double s = std::exp(check(v[i], i, name));
      if (!(s <= 3.0e38)) throw ReadError(file, "vertex " + std::to_string(i) + " has a scale too large (" + name + " = " + std::to_string(v[i]) + ")");
      scales[3 * i + size_t(a)] = float(s);
    }
  }
  {
    std::vector<double> q[4];
    for (int a = 0; a < 4; ++a) q[a] = column(data, "rot_" + std::to_string(a));
    for (size_t i = 0; i < n; ++i) {
      double w = check(q[0][i], i, "rot_0"), x = check(q[1][i], i, "rot_1");
      double y = check(q[2][i], i, "rot_2"), z = check(q[3][i], i, "rot_3");
      const double len = std::sqrt(w * w + x * x + y * y + z * z);
      if (len > 0.0 && std::isfinite(len)) {
        w /= len, x /= len, y /= len, z /= len;
      } else {
        w = 1.0, x = y = z = 0.0;
      }
      rotations[4 * i] = float(w), rotations[4 * i + 1] = float(x);
      rotations[4 * i + 2] = float(y), rotations[4 * i + 3] = float(z);
    }
  }
  // The raw columns go; what they meant stays.
  for (const char* name : {"f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2", "rot_0",
                           "rot_1", "rot_2", "rot_3"})
    data.remove(name);
  for (int j = 0; j < rest; ++j) data.remove("f_rest_" + std::to_string(j));
  if (const std::vector<float>* normals = data.get<float>("normals"))
    if (std::all_of(normals->begin(), normals->end(), [](float v) { return v == 0.0f; })) data.remove("normals");
  data.set("opacity", 1, std::move(opacity));
  data.set("scales", 3, std::move(scales));
  data.set("rotations", 4, std::move(rotations));
  data.set("sh", 3 * K, std::move(sh));
  colors_from_sh_dc(data, K);
  data.metadata["gaussian_splats"] = int64_t{1};
  data.metadata["sh_degree"] = int64_t{degree};
}

}  // namespace pointnpr::io
