// Helpers for the filter library (cpp/filters/): colour spaces, a
// deterministic paper/noise generator and Gaussian weights.
#include "common.glsl"

bool in_image(ivec2 q, ivec2 size) { return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)); }

bool covered(vec4 c) { return c.a > 0.0; }

vec3 linear_to_srgb(vec3 c) {
  c = max(c, vec3(0.0));
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

// Oklab (Ottosson 2020): perceptual lightness L in [0,1], opponent a, b.
vec3 linear_to_oklab(vec3 c) {
  vec3 lms = mat3(0.4122214708, 0.2119034982, 0.0883024619,
                  0.5363325363, 0.6806995451, 0.2817188376,
                  0.0514459929, 0.1073969566, 0.6299787005) * c;
  lms = sign(lms) * pow(abs(lms), vec3(1.0 / 3.0));
  return mat3(0.2104542553, 1.9779984951, 0.0259040371,
              0.7936177850, -2.4285922050, 0.7827717662,
              -0.0040720468, 0.4505937099, -0.8086757660) * lms;
}

vec3 oklab_to_linear(vec3 lab) {
  vec3 lms = mat3(1.0, 1.0, 1.0,
                  0.3963377774, -0.1055613458, -0.0894841775,
                  0.2158037573, -0.0638541728, -1.2914855480) * lab;
  lms = lms * lms * lms;
  return mat3(4.0767416621, -1.2684380046, -0.0041960863,
              -3.3077115913, 2.6097574011, -0.7034186147,
              0.2309699292, -0.3413193965, 1.7076147010) * lms;
}

vec3 srgb_to_oklab(vec3 c) { return linear_to_oklab(srgb_to_linear(c)); }
vec3 oklab_to_srgb(vec3 lab) { return clamp(linear_to_srgb(oklab_to_linear(lab)), 0.0, 1.0); }

// Perceptual lightness of a display sRGB colour, [0,1].
float lightness(vec3 c) { return srgb_to_oklab(clamp(c, 0.0, 1.0)).x; }

// Uniform [0,1) from integer lattice coordinates and a seed.
float hash01(ivec2 q, uint seed) {
  uint h = hash_u32(uint(q.x) * 0x8da6b343u ^ hash_u32(uint(q.y) * 0xd8163841u ^ seed * 0xcb1ab31fu));
  return float(h >> 8) * (1.0 / 16777216.0);
}

// Smooth value noise on a lattice of `cell` pixels, [0,1].
float value_noise(vec2 p, float cell, uint seed) {
  vec2 x = p / cell;
  ivec2 i = ivec2(floor(x));
  vec2 f = x - vec2(i);
  vec2 u = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
  float a = hash01(i, seed), b = hash01(i + ivec2(1, 0), seed);
  float c = hash01(i + ivec2(0, 1), seed), d = hash01(i + ivec2(1, 1), seed);
  return mix(mix(a, b, u.x), mix(c, d, u.x), u.y);
}

// Fractal sum of `octaves` value noises, finest cell `cell`, [0,1].
float fbm(vec2 p, float cell, int octaves, uint seed) {
  float sum = 0.0, amp = 0.5, norm = 0.0;
  float s = cell * exp2(float(octaves - 1));
  for (int o = 0; o < octaves; ++o) {
    sum += amp * value_noise(p, s, seed + uint(o) * 101u);
    norm += amp;
    amp *= 0.5;
    s *= 0.5;
  }
  return sum / norm;
}

// Gradient (Perlin) noise in 3-D with quintic fade: smooth, no lattice
// blocks like value noise's; zero mean, within [-1.2, 1.2] (std 0.33,
// GRADIENT_NOISE_STD). One hash per lattice corner; its gradient is one of
// the 8 diagonals (+-1, +-1, +-1) (Perlin 2002 uses 12 edges; the diagonals
// need no table and the same dot product costs only additions).
const float GRADIENT_NOISE_STD = 0.33;
float corner(ivec3 q, uint seed, vec3 f) {
  uint h = hash_u32(uint(q.x) * 0x8da6b343u + uint(q.y) * 0xd8163841u + uint(q.z) * 0xcb1ab31fu + seed * 0x9e3779b9u);
  return ((h & 1u) != 0u ? f.x : -f.x) + ((h & 2u) != 0u ? f.y : -f.y) + ((h & 4u) != 0u ? f.z : -f.z);
}

float gradient_noise(vec3 x, uint seed) {
  vec3 i = floor(x), f = x - i;
  ivec3 q = ivec3(i);
  vec3 u = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
  float n000 = corner(q, seed, f);
  float n100 = corner(q + ivec3(1, 0, 0), seed, f - vec3(1, 0, 0));
  float n010 = corner(q + ivec3(0, 1, 0), seed, f - vec3(0, 1, 0));
  float n110 = corner(q + ivec3(1, 1, 0), seed, f - vec3(1, 1, 0));
  float n001 = corner(q + ivec3(0, 0, 1), seed, f - vec3(0, 0, 1));
  float n101 = corner(q + ivec3(1, 0, 1), seed, f - vec3(1, 0, 1));
  float n011 = corner(q + ivec3(0, 1, 1), seed, f - vec3(0, 1, 1));
  float n111 = corner(q + ivec3(1, 1, 1), seed, f - vec3(1, 1, 1));
  return mix(mix(mix(n000, n100, u.x), mix(n010, n110, u.x), u.y), mix(mix(n001, n101, u.x), mix(n011, n111, u.x), u.y),
             u.z);
}

// Fractal gradient noise fixed to the surface (a dynamic solid texture,
// Benard et al. 2009): `x` is the pixel's surface point, `px` how many of
// its units one pixel spans there. `octaves` octaves of ratio 2, amplitude
// halving towards the finest, whose feature is `cell` pixels on screen.
// The cells are powers of two in the surface's units, so a point keeps its
// pattern while the camera moves; as the distance changes the pattern
// cross-fades to the next power (a fraction t of an octave), so the size on
// screen holds. Each scale is its own noise (seeded by its power), so the
// sum is the same pattern at any pixel. Zero mean, unit variance.
float surface_fbm(vec3 x, float px, float cell, int octaves, uint seed) {
  float level = log2(max(cell * px, 1e-30));
  float l0 = floor(level), t = level - l0;
  float sum = 0.0, norm2 = 0.0;
  for (int j = 0; j <= octaves; ++j) {
    float here = j < octaves ? exp2(float(j - octaves + 1)) : 0.0;
    float below = j >= 1 ? exp2(float(j - octaves)) : 0.0;
    float w = (1.0 - t) * here + t * below;
    if (w <= 0.0) continue;
    int power = int(l0) + j;
    sum += w * gradient_noise(x * exp2(-float(power)), seed + uint(power) * 0x2c1b3c6du);
    norm2 += w * w;
  }
  return sum / (GRADIENT_NOISE_STD * sqrt(norm2));
}

float gauss(float d2, float sigma) { return exp(-d2 / (2.0 * sigma * sigma)); }

// A band's transfer curve, x = (L - level) / step in [-0.5, 0.5]: Winnemoeller
// et al.'s tanh(k x), scaled to reach +-0.5 at the band's borders, so the
// staircase is continuous for every k and k sets only its hardness: the
// identity (no bands) at k = 0, flat bands as k grows.
float soft_step(float k, float x) {
  if (k < 1e-3) return x;
  return 0.5 * tanh(k * x) / tanh(0.5 * k);
}

// CIELAB (D65), L in [0,100]: the space Winnemoeller et al. 2006 smooth in.
vec3 linear_to_lab(vec3 c) {
  vec3 xyz = mat3(0.4124564, 0.2126729, 0.0193339,
                  0.3575761, 0.7151522, 0.1191920,
                  0.1804375, 0.0721750, 0.9503041) * c / vec3(0.95047, 1.0, 1.08883);
  vec3 f = mix(xyz / (3.0 * 0.04280618) + 4.0 / 29.0, pow(max(xyz, vec3(0.0)), vec3(1.0 / 3.0)),
               greaterThan(xyz, vec3(0.00885645)));
  return vec3(116.0 * f.y - 16.0, 500.0 * (f.x - f.y), 200.0 * (f.y - f.z));
}

vec3 lab_to_linear(vec3 lab) {
  float fy = (lab.x + 16.0) / 116.0;
  vec3 f = vec3(fy + lab.y / 500.0, fy, fy - lab.z / 200.0);
  vec3 xyz = mix(3.0 * 0.04280618 * (f - 4.0 / 29.0), f * f * f, greaterThan(f, vec3(6.0 / 29.0)));
  xyz *= vec3(0.95047, 1.0, 1.08883);
  return mat3(3.2404542, -0.9692660, 0.0556434,
              -1.5371385, 1.8760108, -0.2040259,
              -0.4985314, 0.0415560, 1.0572252) * xyz;
}

vec3 srgb_to_lab(vec3 c) { return linear_to_lab(srgb_to_linear(clamp(c, 0.0, 1.0))); }
vec3 lab_to_srgb(vec3 lab) { return clamp(linear_to_srgb(lab_to_linear(lab)), 0.0, 1.0); }

// Surface points (cpp/render/filter.h, SurfaceFrame; set_surface_uniforms):
// the segment's anchor-frame position of pixel centre `q` at linear depth d.
uniform vec3 u_surface_x0, u_surface_x1, u_surface_y0, u_surface_y1;
uniform mat4 u_object_from_view;
vec3 surface_point(vec2 q, float d) {
  vec3 h = vec3(q, 1.0);
  vec3 view = vec3(dot(u_surface_x0, h) + d * dot(u_surface_x1, h), dot(u_surface_y0, h) + d * dot(u_surface_y1, h), -d);
  return (u_object_from_view * vec4(view, 1.0)).xyz;
}

// View units one pixel spans at depth d (the view-space x of pixel q at
// depth d is dot(x0, q) + d dot(x1, q)).
float pixel_size(float d) { return abs(u_surface_x0.x + d * u_surface_x1.x); }
// The same in object units: times the anchor frame's scale.
float surface_pixel(float d) { return pixel_size(d) * length(u_object_from_view[0].xyz); }
