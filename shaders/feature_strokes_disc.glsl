// The feature_strokes mark's visibility disc (seed 001 section 6.1) on
// screen, written once for feature_strokes_depth.vert/.frag and the native
// pass (cpp/marks/feature_strokes/native.cpp), in the subset of
// cpp/core/glsl.h. The disc lies in the point's tangent plane, so it shows
// as an ellipse: its short axis, along the normal's direction on screen,
// is the diameter times the cosine between the normal and the view ray
// (half a pixel at least). A stray point between two surfaces (a laser's
// mixed pixels, lined up along the ray; an isolated point whose
// neighbours lie behind it) has its normal across the ray: it hides a
// sliver, not a disc the size of its gap floating beside the surface.
#ifndef FEATURE_STROKES_DISC_GLSL
#define FEATURE_STROKES_DISC_GLSL

// The disc's shape for view-space normal n (unit, or zero: none) at view
// position v: the normal's direction on screen (xy, unit) and the cosine
// (z). No normal, or one facing the camera: a round disc.
vec3 disc_shape(vec3 n, vec3 v, bool ortho) {
  float across = sqrt(n.x * n.x + n.y * n.y);
  if (!(across > 1e-6f)) return vec3(1.0f, 0.0f, 1.0f);
  float cosine = abs(n.z);
  if (!ortho) {
    float len = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    cosine = len > 0.0f ? abs(n.x * v.x + n.y * v.y + n.z * v.z) / len : 1.0f;
  }
  return vec3(n.x / across, n.y / across, min(cosine, 1.0f));
}

// Whether the pixel at `offset` (pixels) from the centre of a disc of
// `diameter` (2 px or more) and `shape` is on it.
bool on_disc(vec2 offset, float diameter, vec3 shape) {
  float half_long = 0.5f * diameter;
  float half_short = max(half_long * shape.z, 0.5f);
  float along = offset.x * shape.x + offset.y * shape.y;
  float ax = offset.x - along * shape.x;
  float ay = offset.y - along * shape.y;
  float long2 = half_long * half_long, short2 = half_short * half_short;
  return along * along * long2 + (ax * ax + ay * ay) * short2 <= long2 * short2;
}
#endif
