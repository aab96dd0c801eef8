// The gaussians mark's per-splat maths (Kerbl et al. 2023, the 3DGS forward
// pass), written once for both backends in the subset of cpp/core/glsl.h:
// a splat's 3D covariance from its scales and rotation, its projection to a
// 2D conic by the affine (EWA) approximation with the 0.3 px low-pass
// dilation, its view-dependent colour from spherical harmonics, and a
// pixel's alpha. The includer provides, before including this file:
//   GaussianSettings u;              the frame's numbers (below)
//   vec3 sh_at(uint base, int k);    coefficient k (r, g, b) of a splat
#ifndef GAUSSIANS_KERNELS_GLSL
#define GAUSSIANS_KERNELS_GLSL

// A splat on the screen: centre (frame pixels, less the tile's origin),
// inverse 2D covariance (conic a, b, c of a dx^2 + 2 b dx dy + c dy^2),
// radius in pixels (3 sigma of the larger axis, <= 0: not drawn).
struct ScreenSplat {
  vec2 center;
  vec3 conic;
  float radius;
  float depth;  // linear view depth
  // det S / det(S + dilation I) of the 2D covariance S: what anti-aliased
  // (Mip-Splatting) captures scale their opacity by, square-rooted.
  float det_ratio;
};

// Rotation matrix of a unit quaternion (w, x, y, z), as rows.
mat3 quat_rows(vec4 q) {
  float w = q.x;
  float x = q.y;
  float y = q.z;
  float z = q.w;
  return mat3(1.0f - 2.0f * (y * y + z * z), 2.0f * (x * y - w * z), 2.0f * (x * z + w * y),
              2.0f * (x * y + w * z), 1.0f - 2.0f * (x * x + z * z), 2.0f * (y * z - w * x),
              2.0f * (x * z - w * y), 2.0f * (y * z + w * x), 1.0f - 2.0f * (x * x + y * y));
}

// Row r of a matrix stored as rows (mat3(r0, r1, r2) puts row r in column r).
vec3 row_of(mat3 m, int r) { return vec3(m[r][0], m[r][1], m[r][2]); }

// The view-space covariance W R S S^T R^T W^T (W: the view's linear part,
// given as rows), returned as rows of a symmetric matrix.
mat3 view_covariance(mat3 view_rows, vec4 q, vec3 s) {
  mat3 r = quat_rows(q);
  // M = W R S: its rows m_i = (sum_k W_ik R_kj s_j)_j.
  vec3 m0 = vec3(0.0f);
  vec3 m1 = vec3(0.0f);
  vec3 m2 = vec3(0.0f);
  for (int k = 0; k < 3; ++k) {
    vec3 rk = row_of(r, k) * s;
    m0 += view_rows[0][k] * rk;
    m1 += view_rows[1][k] * rk;
    m2 += view_rows[2][k] * rk;
  }
  return mat3(dot(m0, m0), dot(m0, m1), dot(m0, m2), dot(m1, m0), dot(m1, m1), dot(m1, m2), dot(m2, m0),
              dot(m2, m1), dot(m2, m2));
}

// Projects a splat at view-space t with view covariance `cov` (rows).
// Pixel coordinates: px = (clip.x / clip.w * 0.5 + 0.5) * size - origin,
// the Jacobian of that at t (for a perspective camera at t's x and y
// limited to 1.3 times the frame's edge, as the reference rasterizer does).
ScreenSplat project_splat(vec3 t, mat3 cov) {
  ScreenSplat s;
  s.radius = 0.0f;
  s.depth = -t.z;
  s.center = vec2(0.0f);
  s.conic = vec3(0.0f);
  s.det_ratio = 1.0f;
  if (!(s.depth >= u.near_far.x && s.depth <= u.near_far.y)) return s;
  vec4 t4 = vec4(t, 1.0f);
  float w = dot(u.proj_row3, t4);
  float cx = dot(u.proj_row0, t4) / w;
  float cy = dot(u.proj_row1, t4) / w;
  s.center = vec2((cx * 0.5f + 0.5f) * u.frame.x - u.frame.z, (cy * 0.5f + 0.5f) * u.frame.y - u.frame.w);
  vec3 tj = t;
  if (u.ortho == 0) {
    // t's x and y with its NDC limited to +-1.3 (P = [p00 0 p02 0; 0 p11 p12 0; .; 0 0 -1 0]).
    float lx = clamp(cx, -1.3f, 1.3f);
    float ly = clamp(cy, -1.3f, 1.3f);
    tj = vec3((lx * w - u.proj_row0.z * t.z) / u.proj_row0.x, (ly * w - u.proj_row1.z * t.z) / u.proj_row1.y, t.z);
  }
  vec4 tj4 = vec4(tj, 1.0f);
  float wj = dot(u.proj_row3, tj4);
  float aj = dot(u.proj_row0, tj4);
  float bj = dot(u.proj_row1, tj4);
  // d(px)/dt = 0.5 size (row0 w - a row3) / w^2.
  vec3 j0 = (0.5f * u.frame.x / (wj * wj)) * (vec3(u.proj_row0) * wj - aj * vec3(u.proj_row3));
  vec3 j1 = (0.5f * u.frame.y / (wj * wj)) * (vec3(u.proj_row1) * wj - bj * vec3(u.proj_row3));
  vec3 cj0 = vec3(dot(row_of(cov, 0), j0), dot(row_of(cov, 1), j0), dot(row_of(cov, 2), j0));
  vec3 cj1 = vec3(dot(row_of(cov, 0), j1), dot(row_of(cov, 1), j1), dot(row_of(cov, 2), j1));
  float a0 = dot(j0, cj0);
  float b = dot(j0, cj1);
  float c0 = dot(j1, cj1);
  float a = a0 + u.dilation;
  float c = c0 + u.dilation;
  float det = a * c - b * b;
  if (!(det > 0.0f)) return s;
  s.det_ratio = max(a0 * c0 - b * b, 0.0f) / det;
  s.conic = vec3(c / det, -b / det, a / det);
  float mid = 0.5f * (a + c);
  float lambda = mid + sqrt(max(0.1f, mid * mid - det));
  s.radius = min(ceil(3.0f * sqrt(lambda)), u.max_radius);
  return s;
}

// The colour of a splat seen along `dir` (unit, from the camera to the
// splat, in the splat's frame): the SH bands up to `degree`, + 0.5, >= 0.
vec3 sh_color(uint base, int degree, vec3 dir) {
  vec3 result = 0.28209479177387814f * sh_at(base, 0);
  if (degree > 0) {
    float x = dir.x;
    float y = dir.y;
    float z = dir.z;
    result = result - 0.4886025119029199f * y * sh_at(base, 1) + 0.4886025119029199f * z * sh_at(base, 2) -
             0.4886025119029199f * x * sh_at(base, 3);
    if (degree > 1) {
      float xx = x * x;
      float yy = y * y;
      float zz = z * z;
      result = result + 1.0925484305920792f * x * y * sh_at(base, 4) - 1.0925484305920792f * y * z * sh_at(base, 5) +
               0.31539156525252005f * (2.0f * zz - xx - yy) * sh_at(base, 6) -
               1.0925484305920792f * x * z * sh_at(base, 7) + 0.5462742152960396f * (xx - yy) * sh_at(base, 8);
      if (degree > 2) {
        result = result - 0.5900435899266435f * y * (3.0f * xx - yy) * sh_at(base, 9) +
                 2.890611442640554f * x * y * z * sh_at(base, 10) -
                 0.4570457994644658f * y * (4.0f * zz - xx - yy) * sh_at(base, 11) +
                 0.3731763325901154f * z * (2.0f * zz - 3.0f * xx - 3.0f * yy) * sh_at(base, 12) -
                 0.4570457994644658f * x * (4.0f * zz - xx - yy) * sh_at(base, 13) +
                 1.445305721320277f * z * (xx - yy) * sh_at(base, 14) -
                 0.5900435899266435f * x * (xx - 3.0f * yy) * sh_at(base, 15);
      }
    }
  }
  return max(result + vec3(0.5f), vec3(0.0f));
}

// The exponent of a splat's Gaussian at a pixel centre offset (dx, dy)
// from its centre: -1/2 d^T S^-1 d.
float splat_power(vec3 conic, float dx, float dy) {
  return -0.5f * (conic.x * dx * dx + conic.z * dy * dy) - conic.y * dx * dy;
}

// A splat's alpha for that exponent: its opacity times the Gaussian, at
// most 0.99; 0 below 1/255 or for a power above 0 (as the reference skips).
float alpha_of_power(float power, float opacity) {
  if (power > 0.0f) return 0.0f;
  float alpha = min(0.99f, opacity * exp(power));
  return alpha < 1.0f / 255.0f ? 0.0f : alpha;
}

// A splat's alpha at a pixel centre offset (dx, dy) from its centre.
float splat_alpha(vec3 conic, float opacity, float dx, float dy) {
  return alpha_of_power(splat_power(conic, dx, dy), opacity);
}

#endif
