#pragma once
// A camera composed in double precision. Matrices are only cast to float
// per chunk, after the large world offsets have cancelled.
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <string>

namespace pointnpr {

enum class SensorFit { Auto, Horizontal, Vertical };
SensorFit parse_sensor_fit(const std::string& s);

struct Camera {
  glm::dmat4 view_from_world{1.0};  // inverse of the camera's world matrix
  // Projection in OpenGL convention (view space looks down -Z). Only x/y
  // and w are used: depth is kept linear, clip range is applied explicitly.
  glm::dmat4 projection{1.0};
  bool orthographic = false;
  double clip_start = 0.1;
  double clip_end = 1000.0;
  // The render size the camera was made for (its aspect and sensor fit
  // depend on it); {0, 0} for cameras from matrices (the viewport).
  glm::ivec2 resolution{0, 0};

  // Blender's camera model (BKE_camera_params_compute_viewplane).
  static Camera perspective(const glm::dmat4& world_from_camera, double lens_mm, double sensor_width,
                            double sensor_height, SensorFit fit, double shift_x, double shift_y, double clip_start,
                            double clip_end, glm::ivec2 resolution, double pixel_aspect = 1.0);
  static Camera orthographic_camera(const glm::dmat4& world_from_camera, double ortho_scale, SensorFit fit,
                                    double shift_x, double shift_y, double clip_start, double clip_end,
                                    glm::ivec2 resolution, double pixel_aspect = 1.0);
  // Viewport: Blender's region view matrix and window (projection) matrix.
  static Camera from_matrices(const glm::dmat4& view_from_world, const glm::dmat4& projection);

  // Projected size in pixels of a world-space length at view depth w
  // (w = 1 for orthographic), for a target of `height` pixels.
  double pixels_per_unit(double view_depth, int height) const;
};

}  // namespace pointnpr
