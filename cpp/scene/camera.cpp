#include "scene/camera.h"

#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"

namespace pointnpr {

SensorFit parse_sensor_fit(const std::string& s) {
  if (s == "AUTO") return SensorFit::Auto;
  if (s == "HORIZONTAL") return SensorFit::Horizontal;
  if (s == "VERTICAL") return SensorFit::Vertical;
  throw ParameterError("sensor_fit must be AUTO, HORIZONTAL or VERTICAL, got '" + s + "'");
}

namespace {

void check_common(double clip_start, double clip_end, glm::ivec2 res, double pixel_aspect) {
  if (!(clip_start > 0.0) || !(clip_end > clip_start) || !std::isfinite(clip_end))
    throw ParameterError("camera clip range must satisfy 0 < clip_start < clip_end (got " + std::to_string(clip_start) +
                         ", " + std::to_string(clip_end) + ")");
  if (res.x <= 0 || res.y <= 0) throw ParameterError("camera resolution must be positive");
  if (!(pixel_aspect > 0.0)) throw ParameterError("pixel aspect must be positive");
}

// A camera matrix that can place a camera: finite, and invertible (a
// camera scaled by 0 sees nothing and would render a silent blank frame).
glm::dmat4 inverse_of_camera_matrix(const glm::dmat4& m, const char* what) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) throw ParameterError(std::string("camera ") + what + " has a non-finite entry");
  const double det = glm::determinant(m);
  double scale = 0.0;
  for (int c = 0; c < 3; ++c) scale = std::max(scale, glm::length(glm::dvec3(m[c])));
  if (!(std::abs(det) > 1e-12 * scale * scale * scale) || !std::isfinite(det))
    throw ParameterError(std::string("camera ") + what + " is singular (a camera scaled by 0?)");
  return glm::inverse(m);
}

// The view plane at distance 1 (perspective: scaled by clip_start later),
// following Blender: the sensor maps to the larger image side for AUTO.
struct ViewPlane {
  double xmin, xmax, ymin, ymax;
};

ViewPlane view_plane(double sensor_size_over_distance, SensorFit fit, double shift_x, double shift_y,
                     glm::ivec2 res, double pixel_aspect) {
  const double winx = res.x, winy = res.y * pixel_aspect;
  SensorFit f = fit;
  if (f == SensorFit::Auto) f = winx >= winy ? SensorFit::Horizontal : SensorFit::Vertical;
  const double viewfac = f == SensorFit::Horizontal ? winx : winy;
  const double pixsize = sensor_size_over_distance / viewfac;
  ViewPlane v{-0.5 * winx, 0.5 * winx, -0.5 * winy, 0.5 * winy};
  const double dx = shift_x * viewfac, dy = shift_y * viewfac;
  v.xmin = (v.xmin + dx) * pixsize;
  v.xmax = (v.xmax + dx) * pixsize;
  v.ymin = (v.ymin + dy) * pixsize;
  v.ymax = (v.ymax + dy) * pixsize;
  return v;
}

double sensor_for_fit(SensorFit fit, double sensor_width, double sensor_height) {
  return fit == SensorFit::Vertical ? sensor_height : sensor_width;
}

}  // namespace

Camera Camera::perspective(const glm::dmat4& world_from_camera, double lens_mm, double sensor_width,
                           double sensor_height, SensorFit fit, double shift_x, double shift_y, double clip_start,
                           double clip_end, glm::ivec2 resolution, double pixel_aspect) {
  check_common(clip_start, clip_end, resolution, pixel_aspect);
  if (!(lens_mm > 0.0) || !(sensor_width > 0.0) || !(sensor_height > 0.0))
    throw ParameterError("lens and sensor size must be positive");
  Camera c;
  c.view_from_world = inverse_of_camera_matrix(world_from_camera, "matrix (world_from_camera)");
  c.resolution = resolution;
  const ViewPlane v = view_plane(sensor_for_fit(fit, sensor_width, sensor_height) / lens_mm, fit, shift_x, shift_y,
                                 resolution, pixel_aspect);
  c.projection = glm::frustum(v.xmin * clip_start, v.xmax * clip_start, v.ymin * clip_start, v.ymax * clip_start,
                              clip_start, clip_end);
  c.orthographic = false;
  c.clip_start = clip_start;
  c.clip_end = clip_end;
  return c;
}

Camera Camera::orthographic_camera(const glm::dmat4& world_from_camera, double ortho_scale, SensorFit fit,
                                   double shift_x, double shift_y, double clip_start, double clip_end,
                                   glm::ivec2 resolution, double pixel_aspect) {
  if (!(clip_end > clip_start)) throw ParameterError("camera clip range must satisfy clip_start < clip_end");
  check_common(std::max(clip_start, 1e-300), clip_end, resolution, pixel_aspect);
  if (!(ortho_scale > 0.0)) throw ParameterError("ortho_scale must be positive");
  Camera c;
  c.view_from_world = inverse_of_camera_matrix(world_from_camera, "matrix (world_from_camera)");
  c.resolution = resolution;
  const ViewPlane v = view_plane(ortho_scale, fit, shift_x, shift_y, resolution, pixel_aspect);
  c.projection = glm::ortho(v.xmin, v.xmax, v.ymin, v.ymax, clip_start, clip_end);
  c.orthographic = true;
  c.clip_start = clip_start;
  c.clip_end = clip_end;
  return c;
}

Camera Camera::from_matrices(const glm::dmat4& view_from_world, const glm::dmat4& projection) {
  (void)inverse_of_camera_matrix(view_from_world, "view matrix");
  for (int col = 0; col < 4; ++col)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(projection[col][r])) throw ParameterError("camera projection matrix has a non-finite entry");
  Camera c;
  c.view_from_world = view_from_world;
  c.projection = projection;
  // OpenGL projection: perspective iff the w row reads -z.
  c.orthographic = std::abs(projection[2][3]) < 0.5;
  const double a = projection[2][2], b = projection[3][2];
  if (c.orthographic) {
    // a = -2/(f-n), b = -(f+n)/(f-n)
    c.clip_start = (b + 1.0) / a;
    c.clip_end = (b - 1.0) / a;
  } else {
    // a = -(f+n)/(f-n), b = -2fn/(f-n)
    c.clip_start = b / (a - 1.0);
    c.clip_end = b / (a + 1.0);
  }
  if (!std::isfinite(c.clip_start) || !std::isfinite(c.clip_end) || c.clip_end <= c.clip_start)
    throw ParameterError("projection matrix has an invalid clip range");
  if (!c.orthographic && c.clip_start <= 0.0) throw ParameterError("perspective projection must have clip_start > 0");
  return c;
}

double Camera::pixels_per_unit(double view_depth, int height) const {
  const double w = orthographic ? 1.0 : view_depth;
  return projection[1][1] * 0.5 * double(height) / w;
}

}  // namespace pointnpr
