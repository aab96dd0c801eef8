in vec3 v_view;
in float v_depth;
in vec3 v_normal;
in vec4 v_color;
in vec2 v_uv;
layout(location = 0) out vec4 o_color;
layout(location = 1) out float o_depth;

uniform sampler2D u_points_depth;  // what the segment's point mark drew (linear depth, +inf empty)
uniform sampler2D u_texture;
uniform float u_far;
uniform int u_color_source;
uniform int u_shading;  // 0 none, 1 flat, 2 smooth
uniform float u_shading_strength;
uniform vec3 u_light_dir;  // towards the light, view space
uniform vec4 u_base_color;
uniform vec4 u_constant_color;

void main() {
  if (v_depth > u_far) discard;
  // The segment's own points in front win this pixel.
  if (texelFetch(u_points_depth, ivec2(gl_FragCoord.xy), 0).r <= v_depth) discard;
  vec4 c = u_color_source == 1 ? u_base_color
         : u_color_source == 2 ? v_color
         : u_color_source == 3 ? texture(u_texture, v_uv)
                               : u_constant_color;
  if (u_shading != 0) {
    vec3 face = cross(dFdx(v_view), dFdy(v_view));
    vec3 n = u_shading == 2 && dot(v_normal, v_normal) > 1e-6 ? v_normal : face;
    n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
    // Two-sided: the side facing the camera is lit.
    if (dot(n, -v_view) < 0.0) n = -n;
    float lambert = max(dot(n, u_light_dir), 0.0);
    c.rgb *= 1.0 - u_shading_strength * (1.0 - lambert);
  }
  o_color = vec4(c.rgb, 1.0);
  o_depth = v_depth;
}
