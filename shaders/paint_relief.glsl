// Paint relief (impasto after Hertzmann 2002's fast paint texture, as
// Semmo et al. 2016 light their paint): a height field, bound at 2 (x =
// height, w > 0 where painted), lit as a bump map by a light from the upper
// left. Flat paint keeps its colour; slopes facing the light brighten,
// the others darken, and ridges catch a specular highlight.
layout(rgba32f, binding = 2) uniform readonly image2D u_height;

float height_at(ivec2 q, float fallback) {
  if (!in_image(q, imageSize(u_height))) return fallback;
  vec4 h = imageLoad(u_height, q);
  return h.w > 0.0 ? h.x : fallback;
}

// Central differences of the height at p (unpainted neighbours: flat).
vec2 relief_slope(ivec2 p) {
  float h = height_at(p, 0.0);
  float dx = height_at(p + ivec2(1, 0), h) - height_at(p - ivec2(1, 0), h);
  float dy = height_at(p + ivec2(0, 1), h) - height_at(p - ivec2(0, 1), h);
  return vec2(dx, dy);
}

// `rgb` lit through the relief's slope scaled by `relief`, with a Phong
// highlight of weight `gloss` (none on flat paint).
vec3 lit_paint(vec3 rgb, vec2 slope, float relief, float gloss) {
  vec3 n = normalize(vec3(-slope.x * relief, -slope.y * relief, 1.0));
  vec3 l = normalize(vec3(-1.0, 1.0, 1.5));  // light from the upper left
  float diffuse = max(dot(n, l), 0.0) / l.z;  // 1 on flat paint
  float specular = pow(max(reflect(-l, n).z, 0.0), 24.0) - pow(reflect(-l, vec3(0.0, 0.0, 1.0)).z, 24.0);
  return clamp(rgb * diffuse + gloss * max(specular, 0.0), 0.0, 1.0);
}
