// The brush_splats mark (cpp/marks/brush_splats.cpp, seed 004): per-point
// splat setup shared by its passes: size r + eps, the tangent frame from
// the normal, the brush's per-column angles.
#include "point_attributes.glsl"
#include "id_hash.glsl"

layout(std430, binding = 3) readonly buffer Resolution { float resolution[]; };  // mean kNN distance r
layout(std430, binding = 4) readonly buffer Deviation { float deviation[]; };    // its deviation eps
layout(std430, binding = 5) readonly buffer Clusters { uint clusters_u[]; };    // 4 per point: axis, elongation, size, label
layout(std430, binding = 6) readonly buffer PointIds { uint point_ids[]; };
layout(std430, binding = 13) readonly buffer Axes { uint axes_u[]; };  // covariance frame: major axis, snorm8
layout(std430, binding = 14) readonly buffer Queue { uint queue_order[]; };  // chunk-local indices (u_queue)
layout(std430, binding = 15) readonly buffer SplatRadii { float splat_radius[]; };    // size_mode splat
layout(std430, binding = 16) readonly buffer SplatOpacities { float splat_opacity[]; };  // u_opacity_weight
uniform int u_queue;  // 1: the chunk's i-th splat is the i-th point of its resolution queue

// The point of the chunk's i-th splat.
uint splat_point(uint i) { return u_first + (u_queue != 0 ? queue_order[u_first + i] : i); }

uniform mat4 u_projection;
uniform int u_ortho;
uniform float u_near;
uniform float u_far;
uniform float u_px_per_unit;    // pixels per scene unit at view depth 1
uniform int u_size_mode;        // 0 resolution (r + eps), 1 world, 2 the Gaussian splat's own footprint
uniform int u_opacity_weight;   // 1: a Gaussian splat's opacity weighs its brush's alpha
uniform int u_eps_mode;         // 0 deviation of the kNN distance, 1 user
uniform float u_epsilon;        // user eps (scene units)
uniform float u_size_scale;
uniform float u_world_radius;   // size_mode world
uniform float u_max_radius_px;  // the farthest a brush reaches from its point
uniform vec2 u_support;         // brush_support(): its visible part's reach, sqrt((x stretch)^2 + y) radii
uniform int u_frame;            // 0 householder, 1 eberly, 2 square_plate, 3 covariance
uniform float u_angle;          // brush angle theta (radians)
uniform float u_angle_jitter;   // bound of theta's noise per column (radians)
uniform uint u_seed;
uniform int u_clusters;          // 1: the point's cluster shapes its brush
uniform float u_small_cluster;   // clusters with fewer points: two layers
uniform float u_elongation_gain; // stretch = elongation ^ gain ...
uniform float u_max_stretch;     // ... at most this
uniform int u_shading;           // 1: the brush's colour lit by its splat's plane (two-sided diffuse)
uniform float u_shading_strength;
uniform vec3 u_light_dir;        // towards the light, view space

// Randomness from point ids only (id_hash.glsl).
float brush_rand(uint id, uint salt) { return id_rand(id, salt, u_seed); }

// Householder formula (seed 004 section 3.3.1, after Lopes et al.): the
// columns 2 and 3 of H = I - 2 v v^T / v.v with v = n + sign(n.x) e1 are
// orthonormal and orthogonal to n; continuous except across n.x = 0.
// 1 comparison, 1 division, a few products.
void frame_householder(vec3 n, out vec3 t, out vec3 b) {
  float s = n.x >= 0.0 ? 1.0 : -1.0;
  float ih = 1.0 / (1.0 + abs(n.x));
  t = vec3(-s * n.y, 1.0 - n.y * n.y * ih, -n.y * n.z * ih);
  b = vec3(-s * n.z, -n.y * n.z * ih, 1.0 - n.z * n.z * ih);
}

// Eberly (Geometric Tools, orthonormal sets): n crossed with the identity
// column chosen by the larger of |n.x|, |n.y|; jumps across |n.x| = |n.y|.
void frame_eberly(vec3 n, out vec3 t, out vec3 b) {
  if (abs(n.x) > abs(n.y)) t = vec3(-n.z, 0.0, n.x) / sqrt(n.x * n.x + n.z * n.z);
  else t = vec3(0.0, n.z, -n.y) / sqrt(n.y * n.y + n.z * n.z);
  b = cross(n, t);
}

// Square plate (our stand-in for the seed's reference [24], which we could
// not read): the plate's diagonal (1,1,1)/sqrt(3) projected onto the
// tangent plane, its other diagonal where n is nearly along it: globally
// similar diagonal directions, as the seed describes.
void frame_square_plate(vec3 n, out vec3 t, out vec3 b) {
  vec3 d = vec3(0.57735027);
  if (abs(dot(n, d)) > 0.9) d = vec3(0.70710678, -0.70710678, 0.0);
  t = normalize(d - dot(d, n) * n);
  b = cross(n, t);
}

// Covariance matrix (the surface-aligned splatting standard): the
// neighbourhood's major principal axis, in the tangent plane.
void frame_covariance(vec3 n, vec3 major, out vec3 t, out vec3 b) {
  vec3 along = major - dot(major, n) * n;
  if (dot(along, along) < 1e-6) {
    frame_householder(n, t, b);  // no axis (degenerate neighbourhood)
    return;
  }
  t = normalize(along);
  b = cross(n, t);
}

struct BrushSplat {
  vec3 center;    // view space
  vec3 t;         // view space, unit: the brush's x axis
  vec3 b;         // view space, unit: its y axis
  vec3 n;         // view space, unit
  float radius;   // scene units: the texture is 2 radius wide across t ...
  float stretch;  // ... and 2 radius x stretch along it
  bool two_layers;
  bool visible;
};

BrushSplat brush_splat(uint index) {
  BrushSplat s;
  vec4 v = u_view_from_chunk * vec4(point_position(index), 1.0);
  s.center = v.xyz;
  float depth = -v.z;
  s.visible = depth >= u_near && depth <= u_far;
  // Size r + eps: denser regions get smaller brushes.
  float r = u_world_radius;
  if (u_size_mode == 0) {
    float eps = u_eps_mode == 0 ? deviation[index] : u_epsilon;
    r = resolution[index] + eps;
  } else if (u_size_mode == 2) {
    r = splat_radius[index];
  }
  r *= u_size_scale;
  // Frame from the chunk-space normal (strokes stay with the object as the
  // camera moves), then to view space.
  vec3 n = unpackSnorm4x8(normals_u[index]).xyz;
  float len = length(n);
  mat3 to_view = mat3(u_view_from_chunk);
  s.stretch = 1.0;
  s.two_layers = false;
  if (len > 1e-3) {
    n /= len;
    vec3 t, b;
    if (u_frame == 1) frame_eberly(n, t, b);
    else if (u_frame == 2) frame_square_plate(n, t, b);
    else if (u_frame == 3) frame_covariance(n, unpackSnorm4x8(axes_u[index]).xyz, t, b);
    else frame_householder(n, t, b);
    s.t = normalize(to_view * t);
    s.b = normalize(to_view * b);
    s.n = normalize(u_normal_matrix * n);
    if (u_clusters != 0 && clusters_u[4u * index + 2u] > 0u) {
      // Seed 004 section 3.2.1: small clusters get a two-layered brush,
      // elongated ones longer brushes along their main axis.
      uint base = 4u * index;
      s.two_layers = float(clusters_u[base + 2u]) < u_small_cluster;
      float stretch = min(pow(max(uintBitsToFloat(clusters_u[base + 1u]), 1.0), u_elongation_gain), u_max_stretch);
      vec3 axis = unpackSnorm4x8(clusters_u[base]).xyz;
      vec3 along = axis - dot(axis, n) * n;
      if (stretch > 1.05 && dot(along, along) > 0.01) {
        t = normalize(along);
        s.t = normalize(to_view * t);
        s.b = normalize(to_view * cross(n, t));
        s.stretch = stretch;
      }
    }
  } else {
    // No usable normal: a view-facing splat.
    s.t = vec3(1.0, 0.0, 0.0);
    s.b = vec3(0.0, 1.0, 0.0);
    s.n = vec3(0.0, 0.0, 1.0);
  }
  // u_max_radius_px bounds the farthest the brush's visible part reaches
  // from its point (so isolated points' brushes stay near them).
  float px_per_unit = u_px_per_unit / (u_ortho != 0 ? 1.0 : max(depth, 1e-20));
  float along = u_support.x * s.stretch;
  s.radius = min(r, u_max_radius_px / (px_per_unit * sqrt(along * along + u_support.y)));
  if (!(s.radius > 0.0)) s.visible = false;
  return s;
}

// Theta per column of the brush grid: each column within +-jitter of the
// previous one (seed 004 Fig. 4), seeded by the point id.
vec3 brush_column_angles(uint id) {
  float a0 = u_angle + u_angle_jitter * (2.0 * brush_rand(id, 1u) - 1.0);
  float a1 = a0 + u_angle_jitter * (2.0 * brush_rand(id, 2u) - 1.0);
  float a2 = a1 + u_angle_jitter * (2.0 * brush_rand(id, 3u) - 1.0);
  return vec3(a0, a1, a2);
}

// The brush's colour: the point's, lit by the splat's plane where shading
// is on (the same rule as the native setup's); alpha: the weight its brush's
// alpha is multiplied by (a Gaussian splat's opacity, else 1).
vec4 brush_color(uint index, BrushSplat s) {
  vec4 c = source_color(index);
  float weight = u_opacity_weight != 0 ? splat_opacity[index] : 1.0;
  if (u_shading == 0) return vec4(vec3(c), weight);
  return vec4(diffuse_shaded(vec3(c), cross(s.t, s.b), u_light_dir, u_shading_strength), weight);
}
