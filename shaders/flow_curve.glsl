// Flow curves: the integral curves of the structure tensor's edge direction
// (filters::structure_tensor's field, (t, anisotropy, 1) per pixel), traced
// one pixel per step from a pixel's centre. Offsets stay relative to the
// start pixel (small numbers), so a tile, whose pixels are the frame's
// shifted, rounds them alike. The field is bound at 5 and valid in
// [u_flow_min, u_flow_max); lookups outside clamp to that rectangle.
layout(rgba32f, binding = 5) uniform readonly image2D u_flow;
uniform ivec2 u_flow_min;
uniform ivec2 u_flow_max;

// The edge direction at the pixel holding offset o from pixel p's centre.
vec2 flow_tangent(ivec2 p, vec2 o) {
  ivec2 q = clamp(p + ivec2(floor(o + 0.5)), u_flow_min, u_flow_max - 1);
  return imageLoad(u_flow, q).xy;
}

// One step along the curve: o advances by the unit tangent, whose sign
// follows the previous step `dir` (the field is an orientation).
void flow_step(ivec2 p, inout vec2 o, inout vec2 dir) {
  vec2 t = flow_tangent(p, o);
  if (dot(t, dir) < 0.0) t = -t;
  dir = t;
  o += dir;
}
