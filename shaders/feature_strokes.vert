// Feature strokes, pass 2b: 6 vertices per record, a screen-aligned quad
// (seed 001 Fig. 5) at its exact frame position (tiles:
// cpp/render/exact_raster.h). The quad and its pixels:
// feature_strokes_sprite.glsl, shared with the native backend.
#include "feature_strokes_common.glsl"
vec4 stroke_image(vec2 uv) { return vec4(0.0); }  // (no pixel is drawn here)
#include "feature_strokes_sprite.glsl"
#include "exact_window.glsl"

flat out StrokeSprite v_sprite;

const vec2 CORNERS[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));

void main() {
  StrokeSprite s = stroke_sprite(records[uint(gl_VertexID) / 6u]);
  gl_Position = exact_clip(exact_window(sprite_corner(s, CORNERS[uint(gl_VertexID) % 6u])), s.z);
  v_sprite = s;
}
