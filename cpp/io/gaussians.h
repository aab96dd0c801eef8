#pragma once
// 3D Gaussian splats in a PointData (3DGS PLY, SPZ): the attributes every
// splat reader gives, with their meaning rather than their storage.
//
//   "opacity"   float32 (N,)       in [0, 1] (the stored logit through the sigmoid)
//   "scales"    float32 (N, 3)     standard deviations along the splat's axes, scene units (exp of the stored logs)
//   "rotations" float32 (N, 4)     unit quaternions w, x, y, z (normalised; a zero quaternion becomes identity)
//   "sh"        float32 (N, 3*K)   K = (degree + 1)^2 spherical-harmonic coefficients, each r, g, b
//                                  (coefficient-major; DC first), display-referred sRGB as trained
//   "colors"    uint8 (N, 3)       the view-independent colour 0.5 + C0 * DC, clamped, 8-bit sRGB
// metadata "gaussian_splats" = 1 and "sh_degree".
#include <string>

#include "io/point_data.h"

namespace pointnpr::io {

// Whether the vertex properties of a PLY name a 3DGS layout: f_dc_0..2,
// opacity, scale_0..2 and rot_0..3 (f_rest_* optional).
bool has_3dgs_properties(const PointData& data);

// Turns the raw 3DGS PLY columns (read as float attributes of their own
// names) into the attributes above and removes the raw ones; the all-zero
// normals 3DGS writes are dropped. Throws ReadError (naming `file`) for an
// incomplete layout, an f_rest_* count that is no SH degree 1-3, or a
// non-finite value.
void convert_3dgs_ply(PointData& data, const std::string& file);

// Fills "colors" from the DC coefficients of "sh" (3 * K floats a point).
void colors_from_sh_dc(PointData& data, int coefficients);

}  // namespace pointnpr::io
