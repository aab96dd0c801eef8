flat in vec4 v_color;
flat in float v_depth;
flat in float v_diameter;
flat in vec2 v_center;
flat in float v_spacing;
layout(location = 0) out vec4 o_color;
layout(location = 1) out float o_depth;
layout(location = 2) out float o_spacing;  // drawn only into the spacing framebuffer

// Same coverage rule as points.glsl's covers(). The offset from the pixel
// centre, not gl_PointCoord: that is interpolated from the images' corner,
// so its rounding would move with a tile's origin.
void main() {
  vec2 offset = gl_FragCoord.xy - v_center;
  if (v_diameter >= 2.0 && dot(offset, offset) > 0.25 * v_diameter * v_diameter) discard;
  o_color = v_color;
  o_depth = v_depth;
  o_spacing = v_spacing;
}
