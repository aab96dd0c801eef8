// The hatching mark's strokes as quads and their pixels, written once for
// the GL passes (hatching_strokes.vert/.frag) and the native ones
// (cpp/marks/hatching/native.cpp) in the subset of cpp/core/glsl.h.
// Corners are drawn at their exact frame positions, and each pixel finds
// its place on the stroke from its frame pixel's view ray (not from
// interpolated varyings, whose rounding follows a tile's origin:
// cpp/render/exact_raster.h).
#ifndef HATCHING_QUAD_GLSL
#define HATCHING_QUAD_GLSL
#include "id_hash.glsl"
#include "hatching_settings.glsl"

vec2 frame_pixel(vec3 p) {
  vec4 clip = mat_vec(raster.projection, vec4(p, 1.0f));
  PRECISE vec2 px = (vec2(clip.x, clip.y) / clip.w * 0.5f + 0.5f) * vec2(float(raster.size_x), float(raster.size_y));
  return px;
}

// Line `line` of stroke s (0: d1; 1: the crossing one), size 0 where it
// draws nothing.
StrokeQuad stroke_quad(Stroke s, uint line) {
  StrokeQuad q;
  q.color = vec4(0.0f);
  q.center = vec3(0.0f);
  q.aspect = 0.0f;
  q.along = vec3(0.0f);
  q.offset = 0.0f;
  q.across = vec3(0.0f);
  q.id = 0u;
  q.size = vec2(0.0f);
  q.center_px = vec2(0.0f);
  bool crossing = s.n_width.w < 0.0f;
  if (!(s.center_alpha.w > 0.0f) || (line == 1u && !crossing)) return q;
  vec3 center = vec3(s.center_alpha);
  vec3 n = vec3(s.n_width);
  vec3 d = line == 0u ? vec3(s.d1_length) : cross(n, vec3(s.d1_length));
  float len = s.d1_length.w, width = abs(s.n_width.w);
  float depth = -center.z;
  float px_per_unit = raster.px_per_unit / (raster.ortho != 0 ? 1.0f : depth);
  // Thin strokes are drawn 1.5 px wide with proportionally less opacity:
  // sub-pixel quads would drop pixels and shimmer as the camera moves.
  float width_px = width * px_per_unit;
  float alpha = s.center_alpha.w;
  if (width_px < 1.5f) {
    alpha *= width_px / 1.5f;
    width = 1.5f / px_per_unit;
  }
  // Across the stroke: perpendicular to the line and to the view ray.
  vec3 view_dir = raster.ortho != 0 ? vec3(0.0f, 0.0f, -1.0f) : normalize(center);
  vec3 across = cross(d, view_dir);
  if (dot(across, across) < 1e-8f) across = cross(d, n);
  across = normalize(across);
  // A stroke reaching in front of the near plane would project through the
  // camera: not drawn (its point lies within half a stroke of the plane).
  float nearest = depth - 0.5f * len * abs(d.z) - 0.5f * width * abs(across.z);
  if (!(nearest >= raster.near_plane)) return q;
  // The paper's polygon offset, in scene units along the view ray (the
  // screen position is unchanged; the pixels apply it to depth): disc radii
  // at this depth.
  float disc_radius = 0.5f * (raster.disc_world != 0 ? raster.disc_size : raster.disc_size / px_per_unit);
  q.color = vec4(s.color, alpha);
  q.center = center;
  q.aspect = len / width;
  q.along = d;
  // A depth disc faces the camera at its point's depth, so on a surface
  // inclined by theta the nearest disc over a pixel lies up to a radius x
  // tan(theta) in front of the surface there: the offset covers that where
  // the paper's does not (steep sides, where a sparse scan's discs are
  // wide), up to twice the paper's (steeper, a stroke is nearly edge-on,
  // and a larger offset shows the surface behind through it).
  float facing = abs(dot(n, view_dir));
  float incline = sqrt(max(1.0f - facing * facing, 0.0f)) / max(facing, 1e-6f);
  q.offset = clamp(incline, raster.offset_radii, 2.0f * raster.offset_radii) * disc_radius;
  q.across = across;
  q.id = s.point_id * 2u + line;
  q.size = vec2(len, width);
  q.center_px = frame_pixel(center);
  return q;
}

// Pixels per scene unit at linear depth `depth`.
float quad_px_per_unit(float depth) { return raster.px_per_unit / (raster.ortho != 0 ? 1.0f : depth); }

// Corner (0 or 1 along, 0 or 1 across) of a quad, in frame pixels: half a
// pixel beyond the stroke on every side, for the pixels its edges cover in
// part (stroke_alpha).
vec2 quad_corner(StrokeQuad q, vec2 corner) {
  float grow = 1.0f / quad_px_per_unit(-q.center.z);
  return frame_pixel(q.center + q.along * (corner.x - 0.5f) * (q.size.x + grow) +
                     q.across * (corner.y - 0.5f) * (q.size.y + grow));
}

// The integral from 0 to t of the profile 1 - t^n across a stroke (n even;
// n = 0: a solid 1).
float profile_integral(float t, float n) { return n == 0.0f ? t : t * (1.0f - pow(t * t, 0.5f * n) / (n + 1.0f)); }

// The profile's mean over a pixel: a at its centre (-1..1 across the
// stroke), h its half-width in those units; 0 beyond the stroke. A pixel
// sampled at its centre alone switches on and off as a stroke a pixel or two
// wide moves by a fraction of one, and the drawing crawls.
float filtered_profile(float a, float h, float n) {
  float lo = clamp(a - h, -1.0f, 1.0f), hi = clamp(a + h, -1.0f, 1.0f);
  return (profile_integral(hi, n) - profile_integral(lo, n)) / (2.0f * h);
}

// A stroke's texture over the pixel at uv (0..1 along, 0..1 across; the
// texture's detail at the pixel's centre), `px` the stroke's length and
// width in pixels there.
float stroke_alpha(StrokeQuad q, vec2 uv, vec2 px) {
  float along = 2.0f * uv.x - 1.0f;
  if (raster.stroke_texture == 3) {  // soft dot
    vec2 p = vec2(along * max(q.aspect, 1.0f), 2.0f * uv.y - 1.0f);
    return exp(-2.5f * dot(p, p) / max(q.aspect, 1.0f));
  }
  float h = 1.0f / max(px.y, 1e-6f), a = 2.0f * uv.y - 1.0f;
  // The share of the pixel within the stroke's ends.
  float ends = clamp(min(uv.x, 1.0f - uv.x) * px.x + 0.5f, 0.0f, 1.0f);
  if (raster.stroke_texture == 2) return ends * filtered_profile(a, h, 0.0f);  // ink: solid
  uv = clamp(uv, vec2(0.0f), vec2(1.0f));
  // Tapered ends and pressure along the stroke.
  float taper = smoothstep(0.0f, 0.18f, uv.x) * smoothstep(1.0f, 0.75f, uv.x);
  vec2 p = vec2(uv.x * q.aspect * 1.5f, uv.y * 2.0f);
  if (raster.stroke_texture == 1) {  // crayon: flat across, waxy gaps
    // Three grains across, but none under 1.5 px: a finer grain, sampled at
    // pixel centres, flickers as a thin stroke moves.
    float cell = max(px.y / 3.0f, 1.5f);
    float g = id_value_noise(vec2(0.5f * uv.x * px.x, uv.y * px.y) / cell, q.id);
    return ends * filtered_profile(a, h, 6.0f) * smoothstep(0.25f, 0.6f, g) * (0.6f + 0.4f * taper);
  }
  float g = id_value_noise(p, q.id);  // pencil: graphite profile with grain
  return filtered_profile(a, h, 2.0f) * taper * (0.55f + 0.45f * g);
}

// Where a frame pixel's view ray meets the quad's plane: (u, v) on the
// stroke (0..1 along, 0..1 across), the depth the depth test sees (reversed
// Z, the stroke moved toward the camera by its offset) and the surface's
// linear depth there; u = 2e6 where the pixel draws nothing of it (beyond
// the stroke's reach, or its plane seen edge-on).
vec4 stroke_hit(StrokeQuad q, vec2 frame_px) {
  // Perspective close-ups: no stroke reaches farther than the halo allows.
  if (distance(frame_px, q.center_px) > raster.max_reach) return vec4(2e6f, 0.0f, 0.0f, 0.0f);
  // The pixel's view ray (from the near plane) met with the stroke's plane.
  vec2 ndc = frame_px / vec2(float(raster.size_x), float(raster.size_y)) * 2.0f - 1.0f;
  vec4 near_point = mat_vec(raster.inv_projection, vec4(ndc, -1.0f, 1.0f));
  vec3 on_near = vec3(near_point) / near_point.w;
  vec3 origin = raster.ortho != 0 ? on_near : vec3(0.0f);
  vec3 ray = raster.ortho != 0 ? vec3(0.0f, 0.0f, -1.0f) : on_near;
  vec3 normal = cross(q.along, q.across);
  vec3 hit = origin + ray * (dot(q.center - origin, normal) / dot(ray, normal));
  vec3 rel = hit - q.center;
  vec2 uv = vec2(dot(rel, q.along), dot(rel, q.across)) / q.size + 0.5f;
  if (!(abs(uv.x) < 1e6f && abs(uv.y) < 1e6f)) return vec4(2e6f, 0.0f, 0.0f, 0.0f);  // edge-on (or NaN)
  float pd = raster.ortho != 0 ? -hit.z - q.offset : -hit.z * max(1.0f - q.offset / max(length(hit), 1e-20f), 0.0f);
  float z = raster.ortho != 0 ? 1.0f - (pd - raster.near_plane) / (raster.far_plane - raster.near_plane)
                              : raster.near_plane / max(pd, 1e-30f);
  return vec4(uv, clamp(z, 0.0f, 1.0f), -(q.center + q.along * (uv.x - 0.5f) * q.size.x).z);
}

// The stroke's opacity at a hit (not > 0: the pixel draws nothing).
float stroke_coverage(StrokeQuad q, vec4 hit) {
  if (!(hit.x < 1e6f)) return 0.0f;
  float px_per_unit = quad_px_per_unit(hit.w);
  return clamp(q.color.a * stroke_alpha(q, vec2(hit.x, hit.y), q.size * px_per_unit), 0.0f, 1.0f);
}
#endif
