// The brush_splats native path's frame settings (the shaders' uniforms,
// resolved once a frame), the brush's fitted falloff, and the
// camera-independent part of each splat (point frames, kept per cloud).
#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/hash.h"
#include "marks/brush_splats/brush_splats.h"
#include "marks/brush_splats/native_types.h"
#include "scene/camera.h"

namespace pointnpr::brush_native {
namespace {

// Householder, Eberly, square plate, covariance (brush_common.glsl).
void frame_householder(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
  const float s = n.x >= 0.0f ? 1.0f : -1.0f;
  const float ih = 1.0f / (1.0f + std::abs(n.x));
  t = {-s * n.y, 1.0f - n.y * n.y * ih, -n.y * n.z * ih};
  b = {-s * n.z, -n.y * n.z * ih, 1.0f - n.z * n.z * ih};
}
void tangent_frame(int kind, glm::vec3 n, const glm::vec3* major, glm::vec3& t, glm::vec3& b) {
  if (kind == 1) {
    if (std::abs(n.x) > std::abs(n.y)) t = glm::vec3(-n.z, 0.0f, n.x) / std::sqrt(n.x * n.x + n.z * n.z);
    else t = glm::vec3(0.0f, n.z, -n.y) / std::sqrt(n.y * n.y + n.z * n.z);
    b = glm::cross(n, t);
  } else if (kind == 2) {
    glm::vec3 d(0.57735027f);
    if (std::abs(glm::dot(n, d)) > 0.9f) d = glm::vec3(0.70710678f, -0.70710678f, 0.0f);
    t = normalized(d - glm::dot(d, n) * n);
    b = glm::cross(n, t);
  } else if (kind == 3) {
    const glm::vec3 along = *major - glm::dot(*major, n) * n;
    if (glm::dot(along, along) < 1e-6f) return frame_householder(n, t, b);
    t = normalized(along);
    b = glm::cross(n, t);
  } else {
    frame_householder(n, t, b);
  }
}


}  // namespace

// brush_splat()'s camera-independent part.
PointFrame point_frame(const FrameInputs& in, const Settings& s, uint32_t index) {
  PointFrame f;
  float r = s.world_radius;
  if (s.resolution_size) r = in.r[index] + (s.user_eps ? s.epsilon : in.eps[index]);
  else if (s.splat_size) r = in.splat_r[index];
  f.radius = r * s.size_scale;
  f.two = s.two_layers;
  glm::vec3 n = as_uploaded(in.normals[index]);
  const float len = std::sqrt(glm::dot(n, n));
  if (len > 1e-3f) {
    n /= len;
    glm::vec3 major(0.0f);
    if (s.tangent_frame == 3) major = as_uploaded(in.axes[index]);
    tangent_frame(s.tangent_frame, n, &major, f.t, f.b);
    if (s.clusters && in.shapes->size[index] > 0) {
      f.two = f.two || float(in.shapes->size[index]) < s.small_cluster;
      const float st = std::min(std::pow(std::max(in.shapes->elongation[index], 1.0f), s.elongation_gain), s.max_stretch);
      const glm::vec3 axis = as_uploaded(in.shapes->axis[index]);
      const glm::vec3 along = axis - glm::dot(axis, n) * n;
      if (st > 1.05f && glm::dot(along, along) > 0.01f) {
        f.t = normalized(along);
        f.b = glm::cross(n, f.t);
        f.stretch = st;
      }
    }
  }
  const uint32_t id = in.ids[index];
  float a = s.angle + s.jitter * (2.0f * id_rand(id, 1u, s.seed) - 1.0f);
  for (int col = 0; col < 3; ++col) {
    if (col > 0) a += s.jitter * (2.0f * id_rand(id, uint32_t(col + 1), s.seed) - 1.0f);
    f.cs[col] = std::cos(a);
    f.sn[col] = std::sin(a);
  }
  return f;
}

float falloff(const Settings& s, float q) {
  const float t = q * s.inv_reach;
  if (s.pieces) {
    const float x = (s.sqrt_index ? std::sqrt(t) : t) * float(kPieces);
    const int i = std::min(int(x), kPieces - 1);
    const float f = x - float(i);
    float r = s.poly[s.degree][i];
    for (int d = s.degree - 1; d >= 0; --d) r = r * f + s.poly[d][i];
    return r;
  }
  const float at = (s.sqrt_index ? std::sqrt(t) : t) * float(kTable);
  const int i = int(at);
  const float f = at - float(i);
  const float a = s.table[size_t(i)], b = s.table[size_t(i) + 1];
  return a + f * (b - a);
}

namespace {
// The brush's falloff as kPieces polynomials over t (or sqrt(t)) of the
// lowest degree up to kDegree that stays within kPieceError of
// exp(-q^lambda / 2) on a fine grid, as the runtime evaluates them (floats,
// Horner), interpolated at each piece's Chebyshev nodes; steep shapes
// (lambda < 1 at 0, very high lambda) keep the table. Eight lanes look a
// piece's coefficients up in registers, where the table takes two gathers.
constexpr double kPieceError = 1e-5;
void fit_pieces(Settings& s, double lambda) {
  auto exact = [&](double t) { return std::exp(-0.5 * std::pow(double(s.reach) * (s.sqrt_index ? t * t : t), lambda)); };
  for (int degree = 3; degree <= kDegree; ++degree) {
    Eigen::MatrixXd vandermonde(degree + 1, degree + 1);
    Eigen::VectorXd values(degree + 1);
    for (int i = 0; i < kPieces; ++i) {
      for (int k = 0; k <= degree; ++k) {
        const double f = 0.5 - 0.5 * std::cos((k + 0.5) * M_PI / (degree + 1));
        for (int d = 0; d <= degree; ++d) vandermonde(k, d) = std::pow(f, d);
        values(k) = exact((i + f) / kPieces);
      }
      const Eigen::VectorXd c = vandermonde.colPivHouseholderQr().solve(values);
      for (int d = 0; d <= kDegree; ++d) s.poly[d][i] = d <= degree ? float(c(d)) : 0.0f;
    }
    s.pieces = true;
    s.degree = degree;
    double worst = 0.0;
    for (int j = 0; j <= 64 * kPieces; ++j) {
      const double t = double(j) / (64 * kPieces);
      worst = std::max(worst, std::abs(double(falloff(s, float(s.sqrt_index ? t * t : t) * s.reach)) - exact(t)));
    }
    if (worst <= kPieceError) return;
  }
  s.pieces = false;
}
}  // namespace

Settings resolve_settings(const MarkContext& ctx, const ParamValues& p) {
  const Camera& cam = *ctx.camera;
  Settings s;
  const glm::ivec2 frame = frame_size(ctx.targets);
  s.frame = glm::vec2(frame);
  s.origin = ctx.targets.origin;
  s.clip = ctx.clip;
  s.near = float(cam.clip_start);
  s.far = float(cam.clip_end);
  s.ortho = cam.orthographic;
  s.px_per_unit = float(cam.pixels_per_unit(1.0, frame.y));
  s.projection = glm::mat4(cam.projection);
  // As brush_splats.cpp's u_view_from_pixel: composed in double.
  glm::dmat4 ndc_from_pixel(0.0);
  ndc_from_pixel[0][0] = 2.0 / double(frame.x);
  ndc_from_pixel[1][1] = 2.0 / double(frame.y);
  ndc_from_pixel[3] = glm::dvec4(-1.0, -1.0, -1.0, 1.0);
  s.view_from_pixel = glm::mat4(glm::inverse(cam.projection) * ndc_from_pixel);
  s.resolution_size = p.get_enum_name("size_mode") == "resolution";
  s.user_eps = s.resolution_size && p.get_enum_name("epsilon_mode") == "user";
  s.epsilon = s.resolution_size ? float(p.get_float("epsilon")) : 0.0f;
  s.size_scale = float(p.get_float("size_scale"));
  s.splat_size = p.get_enum_name("size_mode") == "splat";
  s.opacity_weight = p.get_bool("opacity_weight");
  s.world_radius = p.get_enum_name("size_mode") == "world" ? float(p.get_float("world_radius")) : 0.0f;
  s.max_radius_px = float(p.get_float("max_radius"));
  const BrushSupport support = brush_support(p);
  s.support_along = support.along;
  s.support_across2 = support.across2;
  s.tangent_frame = p.get_enum("tangent_frame");
  s.angle = float(glm::radians(p.get_float("brush_angle")));
  s.jitter = float(glm::radians(p.get_float("angle_jitter")));
  s.seed = uint32_t(p.get_int("seed"));
  s.two_layers = p.get_enum_name("layers") == "two";
  s.clusters = p.get_bool("clusters");
  s.small_cluster = s.clusters ? float(p.get_int("small_cluster")) : 0.0f;
  s.elongation_gain = float(p.get_float("elongation_stretch"));
  s.max_stretch = float(p.get_float("max_stretch"));
  s.depth_tolerance = float(p.get_float("depth_tolerance"));
  s.shading_strength = float(p.get_float("shading_strength"));
  s.light_dir = view_light_direction(p, *ctx.camera);
  s.gaussians = p.get_int("gaussians");
  const int rows = (s.gaussians + 2) / 3;
  const float dev = float(p.get_float("dev"));
  int k = 0;
  for (int row = 0; row < 3; ++row) {
    const int cols = std::clamp(s.gaussians - row * 3, 0, 3);
    for (int col = 0; col < cols; ++col, ++k) {
      s.cx[k] = 0.5f + (float(col) - 0.5f * float(cols - 1)) * dev;
      s.cy[k] = 0.5f + (float(row) - 0.5f * float(rows - 1)) * dev;
      s.column[k] = col;
    }
  }
  s.amplitude = float(p.get_float("amplitude"));
  s.inv_sx = 1.0f / float(p.get_float("sigma_x"));
  s.inv_sy = 1.0f / float(p.get_float("sigma_y"));
  s.reach = float(brush_reach(p));
  s.inv_reach = 1.0f / s.reach;
  s.layer_scale = float(p.get_float("layer_scale"));
  const float layer_angle = float(glm::radians(p.get_float("layer_angle")));
  s.layer_cos = std::cos(layer_angle);
  s.layer_sin = std::sin(layer_angle);
  s.layer_tint = float(p.get_float("layer_tint"));
  const double lambda = p.get_float("lambda");
  s.table.resize(kTable + 2);
  s.sqrt_index = lambda < 1.0;
  for (int i = 0; i <= kTable; ++i) {
    const double t = double(i) / kTable;
    s.table[size_t(i)] = float(std::exp(-0.5 * std::pow(double(s.reach) * (s.sqrt_index ? t * t : t), lambda)));
  }
  s.table[kTable + 1] = s.table[kTable];
  fit_pieces(s, lambda);
  s.blur_radius = p.get_int("blur_radius");
  s.blur_tolerance = float(p.get_float("blur_depth_tolerance"));
  const float sigma = std::max(0.5f, 0.5f * float(s.blur_radius));
  for (int tap = -s.blur_radius; tap <= s.blur_radius; ++tap)
    s.blur_weight.push_back(std::exp(-0.5f * float(tap * tap) / (sigma * sigma)));
  return s;
}

}  // namespace pointnpr::brush_native
