// Watercolor (cpp/filters/watercolor.cpp), five passes. The abstraction
// runs at half resolution: half pixel h covers frame pixels 2h and 2h + 1;
// index i of its images is half pixel i + u_half_min.
// PASS_DOWN:       2x2 mean of the covered pixels' colours, and the covered share.
// PASS_ABSTRACT_X: sums along x: A = bilateral (rgb*c*w, c*w), B = Gaussian at the rim's sigma (rgb*c*g, c*g).
// PASS_ABSTRACT_Y: along y, then writes (abstracted rgb, coverage f) and (plain rgb, f).
// PASS_FIELDS:     every NODE px: the slow fields fixed to the surface (wobble, dispersion, wetness) and the
//                  wet-in-wet bleed colour, with the node's depth.
// PASS_COMPOSE:    full resolution: wobble, edge darkening, wet-in-wet, dispersion, granulation, dry brush.
#include "filter_common.glsl"
layout(local_size_x = 16, local_size_y = 16) in;
layout(rgba32f, binding = 0) uniform readonly image2D u_in;
layout(rgba32f, binding = 1) uniform writeonly image2D u_out;
const int NODE = 4;  // spacing of the slow fields' nodes (px); the fields vary over 8 px and more
const int MAX_RADIUS = 16;
uniform ivec2 u_half_min;
uniform int u_radius;  // half pixels
uniform float u_fill_norm;

#ifdef PASS_DOWN
void main() {
  ivec2 i;
  if (!rect_pixel(i)) return;
  ivec2 first = 2 * (i + u_half_min) - u_origin;  // the tile's pixel
  ivec2 size = imageSize(u_in);
  vec4 sum = vec4(0.0);
  for (int j = 0; j <= 1; ++j)
    for (int k = 0; k <= 1; ++k) {
      ivec2 q = first + ivec2(k, j);
      if (!in_image(q, size)) continue;
      vec4 c = imageLoad(u_in, q);
      if (covered(c)) sum += vec4(c.rgb, 1.0);
    }
  imageStore(u_out, i, vec4(sum.w > 0.0 ? sum.rgb / sum.w : vec3(0.0), 0.25 * sum.w));
}
#endif

#if defined(PASS_ABSTRACT_X) || defined(PASS_ABSTRACT_Y)
layout(rgba32f, binding = 2) uniform writeonly image2D u_out_a;
layout(rgba32f, binding = 3) uniform writeonly image2D u_out_b;
layout(rgba32f, binding = 4) uniform readonly image2D u_in_a;
layout(rgba32f, binding = 5) uniform readonly image2D u_in_b;
uniform float u_tolerance;  // range sigma of the bilateral weights (sRGB units)
uniform float u_w_abstract[MAX_RADIUS + 1];  // spatial weights by |offset|
uniform float u_w_fill[MAX_RADIUS + 1];

// The colour and covered share a pass sees at i: the downsampled input (x),
// or the x pass's normalized sums (y).
vec4 source(ivec2 i) {
#ifdef PASS_ABSTRACT_X
  return imageLoad(u_in, i);
#else
  vec4 a = imageLoad(u_in_a, i);
  return a.w > 0.0 ? vec4(a.rgb / a.w, a.w) : vec4(0.0);
#endif
}

// Separable bilateral filter over covered pixels (Pham and van Vliet 2005):
// abstraction that keeps colour edges; plus a plain Gaussian of the colour
// and coverage (the rim, colour edges and the bleed read it).
void main() {
  ivec2 i;
  if (!rect_pixel(i)) return;
#ifdef PASS_ABSTRACT_X
  const ivec2 axis = ivec2(1, 0);
#else
  const ivec2 axis = ivec2(0, 1);
#endif
  vec3 centre = source(i).rgb;
  float inv_range = 1.0 / (2.0 * u_tolerance * u_tolerance);
  vec4 a = vec4(0.0), b = vec4(0.0);
  for (int k = -u_radius; k <= u_radius; ++k) {
    ivec2 q = i + k * axis;
    vec4 s = source(q);
    vec3 d = s.rgb - centre;
    float w = u_w_abstract[abs(k)] * exp(-dot(d, d) * inv_range);
    float g = u_w_fill[abs(k)];
#ifdef PASS_ABSTRACT_X
    a += w * vec4(s.rgb * s.w, s.w);
    b += g * vec4(s.rgb * s.w, s.w);
#else
    a += w * imageLoad(u_in_a, q);
    b += g * imageLoad(u_in_b, q);
#endif
  }
#ifdef PASS_ABSTRACT_X
  imageStore(u_out_a, i, a);
  imageStore(u_out_b, i, b);
#else
  float f = b.w / u_fill_norm;
  imageStore(u_out, i, vec4(a.w > 0.0 ? a.rgb / a.w : vec3(0.0), f));
  imageStore(u_out_b, i, vec4(b.w > 0.0 ? b.rgb / b.w : vec3(0.0), f));
#endif
}
#endif

#if defined(PASS_FIELDS) || defined(PASS_COMPOSE)
layout(r32f, binding = 2) uniform readonly image2D u_depth;  // linear view depth, +inf = empty
uniform ivec2 u_node_min;   // the frame node of the fields images' (0, 0)
uniform ivec2 u_abs_min;    // the abstracted images are valid in [u_abs_min, u_abs_max)
uniform ivec2 u_abs_max;
uniform uint u_seed;
#endif

#ifdef PASS_FIELDS
layout(rgba32f, binding = 3) uniform writeonly image2D u_fields;  // wobble x, y in [-1,1], dispersion, wetness
layout(rgba32f, binding = 5) uniform writeonly image2D u_bleed;   // bleed rgb, node depth (0: no surface)
layout(rgba32f, binding = 6) uniform readonly image2D u_plain;
uniform float u_wobble_scale;
uniform float u_density_scale;

// Each node (frame pixel n * NODE + NODE / 2) takes the nearest surface in
// an 8 px window (so gaps and wobbled borders get the fields of the surface
// around them), evaluates the slow fields at its surface point, and
// averages the plain colour over +-NODE px (the wet-in-wet bleed; with the
// bilinear lookup between nodes it spreads over about 3 NODE px).
void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  ivec2 node = p + u_node_min;
  ivec2 centre = node * NODE + NODE / 2 - u_origin;  // local pixel right of / above the node's centre
  ivec2 size = imageSize(u_depth);
  float d = INF;
  for (int j = -4; j <= 2; j += 2)  // every other pixel of the 8x8 window around the centre
    for (int i = -4; i <= 2; i += 2) {
      ivec2 q = centre + ivec2(i, j);
      if (in_image(q, size)) d = min(d, imageLoad(u_depth, q).r);
    }
  vec4 bleed = vec4(0.0);
  ivec2 half_centre = (node * NODE + NODE / 2) / 2 - u_half_min;
  for (int j = -1; j <= 1; ++j)
    for (int i = -1; i <= 1; ++i) {
      ivec2 q = half_centre + (NODE / 2) * ivec2(i, j);
      if (any(lessThan(q, u_abs_min)) || any(greaterThanEqual(q, u_abs_max))) continue;
      vec4 s = imageLoad(u_plain, q);
      bleed += vec4(s.rgb * s.a, s.a);
    }
  if (isinf(d)) {
    imageStore(u_fields, p, vec4(0.0));
    imageStore(u_bleed, p, vec4(0.0));
    return;
  }
  vec2 pos = vec2(node * NODE + NODE / 2);
  vec3 x = surface_point(pos, d);
  float px = surface_pixel(d);
  vec4 fields;
  fields.x = clamp(0.4 * surface_fbm(x, px, 0.25 * u_wobble_scale, 3, u_seed + 11u), -1.0, 1.0);
  fields.y = clamp(0.4 * surface_fbm(x, px, 0.25 * u_wobble_scale, 3, u_seed + 23u), -1.0, 1.0);
  fields.z = clamp(0.45 * surface_fbm(x, px, 0.125 * u_density_scale, 4, u_seed + 37u), -1.0, 1.0);
  fields.w = smoothstep(0.0, 1.2, surface_fbm(x, px, 0.5 * u_density_scale, 2, u_seed + 71u));
  imageStore(u_fields, p, fields);
  imageStore(u_bleed, p, vec4(bleed.a > 0.0 ? bleed.rgb / bleed.a : vec3(0.0), d));
}
#endif

#ifdef PASS_COMPOSE
layout(rgba32f, binding = 3) uniform readonly image2D u_fields;
layout(rgba32f, binding = 4) uniform readonly image2D u_abstract;
layout(rgba32f, binding = 5) uniform readonly image2D u_bleed;
layout(rgba32f, binding = 6) uniform readonly image2D u_plain;
uniform float u_wobble;
uniform float u_edge_darkening;
uniform float u_density;
uniform float u_granulation;
uniform float u_wet;
uniform float u_paper_scale;
uniform sampler2D u_paper;   // height map, white = peaks (when u_paper_image)
uniform int u_paper_image;
uniform vec3 u_plane_weights;  // the paper image's planes (yz, xz, xy) by the view direction
uniform float u_dry_brush;
uniform vec4 u_paper_color;

// Paper height in [0,1] (1 = a peak of the grain) at surface point x whose
// pixel spans px units: procedural fractal noise with its finest feature
// u_paper_scale px, or the image tiled at u_paper_scale px per texel, on
// the three axis planes weighted by the view direction; both at powers of
// two of the surface's units, cross-faded (surface_fbm).
float paper_height(vec3 x, float px) {
  if (u_paper_image == 0) return clamp(0.5 + 0.22 * surface_fbm(x, px, u_paper_scale, 2, u_seed + 53u), 0.0, 1.0);
  float level = log2(max(u_paper_scale * px, 1e-30));
  float l0 = floor(level), t = level - l0;
  vec2 texels = vec2(textureSize(u_paper, 0));
  float sum = 0.0, norm2 = 0.0;
  for (int j = 0; j <= 1; ++j) {
    float wl = j == 0 ? 1.0 - t : t;
    if (wl <= 0.0) continue;
    float cell = exp2(l0 + float(j));
    vec2 uv[3] = vec2[3](x.yz, x.xz, x.xy);
    for (int k = 0; k < 3; ++k) {
      float w = wl * u_plane_weights[k];
      if (w <= 1e-3) continue;
      sum += w * (textureLod(u_paper, uv[k] / (cell * texels), 0.0).r - 0.5);
      norm2 += w * w;
    }
  }
  return clamp(0.5 + sum / sqrt(max(norm2, 1e-12)), 0.0, 1.0);
}

// Bilinear over the valid nodes around frame position x: fields, and the
// bleed colour and depth (w = the valid nodes' weight, 0: none near).
struct Slow {
  vec4 fields;
  vec3 bleed;
  float depth, w;
};
Slow sample_slow(vec2 x) {
  vec2 s = x / float(NODE) - 0.5;
  ivec2 base = ivec2(floor(s));
  vec2 t = s - vec2(base);
  Slow r = Slow(vec4(0.0), vec3(0.0), 0.0, 0.0);
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i) {
      ivec2 q = base + ivec2(i, j) - u_node_min;
      vec4 b = imageLoad(u_bleed, q);
      if (b.a <= 0.0) continue;
      float w = (i == 1 ? t.x : 1.0 - t.x) * (j == 1 ? t.y : 1.0 - t.y);
      r.fields += w * imageLoad(u_fields, q);
      r.bleed += w * b.rgb;
      r.depth += w * b.a;
      r.w += w;
    }
  if (r.w > 0.0) {
    r.fields /= r.w;
    r.bleed /= r.w;
    r.depth /= r.w;
  }
  return r;
}

// The abstracted and plain colours times coverage, and coverage f,
// bilinear (between half pixels) at frame position x.
void sample_abstract(vec2 x, out vec3 abstract_f, out vec3 plain_f, out float f) {
  vec2 s = 0.5 * x - 0.5;
  ivec2 base = ivec2(floor(s));
  vec2 t = s - vec2(base);
  abstract_f = plain_f = vec3(0.0);
  f = 0.0;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i) {
      ivec2 q = base + ivec2(i, j) - u_half_min;
      if (any(lessThan(q, u_abs_min)) || any(greaterThanEqual(q, u_abs_max))) continue;
      vec4 a = imageLoad(u_abstract, q);
      float w = (i == 1 ? t.x : 1.0 - t.x) * (j == 1 ? t.y : 1.0 - t.y) * a.a;
      abstract_f += w * a.rgb;
      plain_f += w * imageLoad(u_plain, q).rgb;
      f += w;
    }
}

// Bousseau's pigment density model: d > 1 darkens, d < 1 lightens.
vec3 density(vec3 c, float d) { return clamp(c - (c - c * c) * (d - 1.0), 0.0, 1.0); }

void main() {
  ivec2 p;
  if (!rect_pixel(p)) return;
  vec2 pos = vec2(p + u_origin) + 0.5;  // frame pixel: tiles match the frame
  vec4 c = imageLoad(u_in, p);
  Slow slow = sample_slow(pos);
  vec3 abstract_f, plain_f;
  float f;
  sample_abstract(pos + u_wobble * slow.fields.xy, abstract_f, plain_f, f);
  vec3 rgb;
  float edge = 0.0, f_wet = 1.0, wet = u_wet * slow.fields.w;
  if (f >= 0.5) {
    // A wash: the abstracted colour; pigment gathers at colour edges (where
    // the plain blur differs from the edge-keeping one) and where the
    // coverage falls off towards the region's border. Wet-in-wet: in wet
    // patches colours run into each other and leave no hard edge.
    rgb = abstract_f / f;
    vec3 plain = plain_f / f;
    float colour_edge = clamp(3.0 * length(plain - rgb), 0.0, 1.0);
    float rim = 1.0 - smoothstep(0.5, 0.9, f);
    f_wet = f;
    edge = max(colour_edge * (1.0 - wet), rim);
    if (slow.w > 0.0) rgb = mix(rgb, slow.bleed, wet);
  } else {
    vec3 a0, p0;
    float f0;
    if (covered(c)) sample_abstract(pos, a0, p0, f0);
    if (!covered(c) || f0 >= 0.5) {
      imageStore(u_out, p, c);
      return;
    }
    rgb = c.rgb;  // a lone point: no wobble, no rim
  }
  // The pixel's own surface point (or the nearest surface's, in a gap or a
  // wobbled border) carries the paper and the pigment's variation.
  float d = imageLoad(u_depth, p).r;
  if (isinf(d)) d = slow.w > 0.0 ? slow.depth : INF;
  float height = isinf(d) ? 0.5 : paper_height(surface_point(pos, d), surface_pixel(d));
  float dispersion = slow.fields.z;
  rgb = density(rgb, 1.0 + u_edge_darkening * edge);
  rgb = density(rgb, 1.0 + u_density * dispersion);
  // Granulation: pigment settles in the valleys (low height): denser there.
  rgb = density(rgb, 1.0 + u_granulation * (1.0 - 2.0 * height));
  if (u_dry_brush > 0.0) {
    // Drier along borders and in patches; only peaks above the threshold
    // take pigment.
    float dry_rim = 1.0 - smoothstep(0.5, 0.99, f_wet);  // reaches ~2 edge widths in
    float dryness = u_dry_brush * clamp(0.35 + 0.65 * dry_rim + 0.5 * dispersion, 0.0, 1.0);
    float threshold = mix(-0.1, 0.8, dryness);
    float pigment = smoothstep(threshold - 0.06, threshold + 0.06, height);
    rgb = mix(u_paper_color.rgb, rgb, pigment);
  }
  imageStore(u_out, p, vec4(rgb, 1.0));
}
#endif
