// The feature_strokes mark's quads and their pixels, written once for the
// GL passes (feature_strokes.vert/.frag) and the native ones
// (cpp/marks/feature_strokes/native.cpp), in the subset of cpp/core/glsl.h.
// The includer defines stroke_image(uv), the stroke texture's sample.
#ifndef FEATURE_STROKES_SPRITE_GLSL
#define FEATURE_STROKES_SPRITE_GLSL
#include "id_hash.glsl"
#include "feature_strokes_settings.glsl"

// A record's quad: r1 along the projected stroke direction (directional
// points) or the constant screen direction, r2 across it.
StrokeSprite stroke_sprite(Record rec) {
  vec3 c = vec3(rec.center_kind);
  float depth = -c.z;
  vec2 size = vec2(float(u.size_x), float(u.size_y));
  vec4 clip = mat_vec(u.projection, vec4(c, 1.0f));
  PRECISE vec2 center = (vec2(clip.x, clip.y) / clip.w * 0.5f + 0.5f) * size;
  vec2 r1 = vec2(u.screen_dir_x, u.screen_dir_y);
  vec3 dir = vec3(rec.dir_length);
  if (rec.primitive == 1u) {
    r1 = vec2(1.0f, 0.0f);
  } else if (dot(dir, dir) > 0.5f) {
    // The projected 3D direction, in pixels; along the view ray: the constant one.
    vec4 tip = mat_vec(u.projection, vec4(c + dir * (u.ortho != 0 ? 1e-3f : 1e-3f * depth), 1.0f));
    vec2 d = (vec2(tip.x, tip.y) / tip.w - vec2(clip.x, clip.y) / clip.w) * size;
    if (dot(d, d) > 1e-12f) r1 = normalize(d);
  }
  StrokeSprite s;
  s.color = rec.color;
  s.center = center;
  s.r1 = r1;
  s.size = vec2(rec.dir_length.w, rec.width);
  s.depth = depth;
  // Reversed Z, as the visibility pass (whose discs lie behind the surface).
  s.z = u.ortho != 0 ? 1.0f - (depth - u.near_plane) / (u.far_plane - u.near_plane) : u.near_plane / depth;
  s.aspect = rec.dir_length.w / max(rec.width, 1e-3f);
  s.primitive = rec.primitive;
  s.id = rec.point_id;
  s.chain = rec.chain;
  return s;
}

// Corner (0 or 1 along r1, 0 or 1 along r2) of a quad, in frame pixels; a
// solid line's quad half a pixel larger on every side, for the pixels its
// edges cover in part (sprite_alpha).
vec2 sprite_corner(StrokeSprite s, vec2 corner) {
  vec2 r2 = vec2(-s.r1.y, s.r1.x);
  float grow = s.primitive == 2u ? 1.0f : 0.0f;
  PRECISE vec2 at = s.center + (2.0f * corner.x - 1.0f) * 0.5f * (s.size.x + grow) * s.r1 +
                    (2.0f * corner.y - 1.0f) * 0.5f * (s.size.y + grow) * r2;
  return at;
}

// How a link of a chain tapers along (uv.x 0 at the point, 1 at its
// parent): to a point at a free end of the chain, not at all where it joins
// the next link.
float chain_taper(StrokeSprite s, float x) {
  int ends = int(s.chain) - 1;
  float t = (ends & 1) != 0 ? smoothstep(0.0f, 0.6f, x) : 1.0f;
  return (ends & 2) != 0 ? t * (1.0f - smoothstep(0.4f, 1.0f, x)) : t;
}

// A textured stroke's alpha at uv (0..1 along, 0..1 across).
float stroke_alpha(StrokeSprite s, vec2 uv) {
  float across = abs(2.0f * uv.y - 1.0f);
  bool chained = s.chain > 0.5f;
  if (u.stroke_texture == 3) {
    vec4 t = stroke_image(uv);
    return t.a * (1.0f - dot(vec3(t), vec3(0.2126f, 0.7152f, 0.0722f)));
  }
  if (u.stroke_texture == 1) {  // bristle brush: streaks across, each fading out at its own length
    float bristle = floor(uv.y * 7.0f);
    uint h = id_hash(s.id * 7u + uint(int(bristle)));
    float reach = 0.65f + 0.35f * float(h >> 8) / 16777216.0f;
    float ink = 0.55f + 0.45f * float(id_hash(h) >> 8) / 16777216.0f;
    float along = chained ? chain_taper(s, uv.x) : smoothstep(0.0f, 0.08f, uv.x) * (1.0f - smoothstep(reach - 0.15f, reach, uv.x));
    return ink * along * (1.0f - pow(across, 8.0f));
  }
  float taper = chained ? chain_taper(s, uv.x) : smoothstep(0.0f, 0.2f, uv.x) * (1.0f - smoothstep(0.7f, 1.0f, uv.x));
  if (u.stroke_texture == 2) {  // dry brush: broken by grain along the stroke
    float g = id_value_noise(vec2(uv.x * s.aspect * 2.0f, uv.y * 5.0f), s.id);
    return taper * smoothstep(0.3f, 0.55f, g) * (1.0f - pow(across, 4.0f));
  }
  // taper: pointed ends, round profile; a chain's line is as wide as its
  // quad (its width is the line's weight; overlapping strokes give theirs)
  return taper * (chained ? 1.0f - pow(across, 4.0f) : 1.0f - across * across);
}

// The quad's opacity at a frame pixel's centre (not > 0: nothing), its
// texture coordinates from the frame pixel (not interpolated varyings,
// whose rounding follows a tile's origin).
float sprite_alpha(StrokeSprite s, vec2 frame_px) {
  vec2 rel = frame_px - s.center;
  vec2 r2 = vec2(-s.r1.y, s.r1.x);
  vec2 uv = vec2(dot(rel, s.r1), dot(rel, r2)) / max(s.size, vec2(1e-6f)) + 0.5f;
  float k;
  if (s.primitive == 1u) {  // Gaussian splatting kernel (Fig. 4a)
    vec2 q = 2.0f * uv - 1.0f;
    float d2 = dot(q, q);
    if (d2 > 1.0f) return 0.0f;
    k = exp(-d2 / (2.0f * 0.4f * 0.4f));
  } else if (s.primitive == 2u) {
    // The share of the pixel the line covers (a box filter along and across
    // it): a hard-edged line a pixel or two wide turns whole pixels on and
    // off as it moves by a fraction of one, and crawls on a slow orbit.
    vec2 half_size = 0.5f * s.size + 0.5f;
    k = clamp(half_size.x - abs(dot(rel, s.r1)), 0.0f, 1.0f) * clamp(half_size.y - abs(dot(rel, r2)), 0.0f, 1.0f);
  } else {
    k = stroke_alpha(s, uv);
  }
  return clamp(s.color.a * k, 0.0f, 1.0f);
}
#endif
