// The mesh_surface mark's pixels: coverage, linear depth, colour and
// normal from the triangle's corners at the frame pixel's centre
// (mesh_surface_common.glsl), the depth test's value written as
// gl_FragDepth. Reversed Z as the GL_POINTS path (GL_GREATER).
#include "mesh_surface_common.glsl"

layout(std430, binding = 1) readonly buffer Normals { uint normals_u[]; };
layout(std430, binding = 2) readonly buffer Colors { uint colors_u[]; };
layout(std430, binding = 3) readonly buffer Uvs { vec2 uvs[]; };

flat in uint v_triangle;
flat in mat3 v_edges;
flat in float v_det;
flat in mat3 v_views;
layout(location = 0) out vec4 o_color;
layout(location = 1) out float o_depth;

uniform mat3 u_normal_matrix;
uniform sampler2D u_points_depth;  // what the segment's point mark drew (linear depth, +inf empty)
uniform sampler2D u_texture;
uniform float u_near;
uniform float u_far;
uniform int u_ortho;
uniform int u_smooth;
uniform int u_color_source;  // resolved: 1 base colour, 2 colours, 3 texture, 4 constant
uniform int u_shading;       // 0 none, 1 flat, 2 smooth
uniform float u_shading_strength;
uniform vec3 u_light_dir;  // towards the light, view space
uniform vec4 u_base_color;
uniform vec4 u_constant_color;

void main() {
  uint i0 = 3u * v_triangle, i1 = i0 + 1u, i2 = i0 + 2u;
  // The frame pixel's centre: exact in float in any tile.
  vec2 pixel = gl_FragCoord.xy + vec2(u_origin);
  vec3 e = edges_at(v_edges, pixel);
  if (!covers(e, v_det)) discard;
  vec3 w = weights(e);
  vec3 view = v_views * w;
  float depth = -view.z;
  if (depth < u_near || depth > u_far) discard;
  // The segment's own points in front win this pixel.
  if (texelFetch(u_points_depth, ivec2(gl_FragCoord.xy), 0).r <= depth) discard;
  vec4 color = u_constant_color;
  if (u_color_source == 1) {
    color = u_base_color;
  } else if (u_color_source == 2) {
    color = w.x * unpackUnorm4x8(colors_u[i0]) + w.y * unpackUnorm4x8(colors_u[i1]) +
            w.z * unpackUnorm4x8(colors_u[i2]);
  } else if (u_color_source == 3) {
    // The mip level from the UVs one pixel over, not from the quad's
    // neighbours (which a tile's edge would change).
    vec3 wx = weights(edges_at(v_edges, pixel + vec2(1.0, 0.0)));
    vec3 wy = weights(edges_at(v_edges, pixel + vec2(0.0, 1.0)));
    mat3x2 uv = mat3x2(uvs[i0], uvs[i1], uvs[i2]);
    vec2 at = uv * w;
    color = textureGrad(u_texture, at, uv * wx - at, uv * wy - at);
  }
  if (u_shading != 0) {
    vec3 n = cross(v_views[1] - v_views[0], v_views[2] - v_views[0]);
    if (u_shading == 2 && u_smooth != 0) {
      vec3 smooth_n = u_normal_matrix * (w.x * unpackSnorm4x8(normals_u[i0]).xyz +
                                         w.y * unpackSnorm4x8(normals_u[i1]).xyz +
                                         w.z * unpackSnorm4x8(normals_u[i2]).xyz);
      if (dot(smooth_n, smooth_n) > 1e-6) n = smooth_n;
    }
    n = dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0);
    // Two-sided: the side facing the camera is lit.
    if (dot(n, -view) < 0.0) n = -n;
    float lambert = max(dot(n, u_light_dir), 0.0);
    color.rgb *= 1.0 - u_shading_strength * (1.0 - lambert);
  }
  o_color = vec4(color.rgb, 1.0);
  o_depth = depth;
  // Perspective: near / depth (1 at the near plane, toward 0 far away);
  // orthographic: 1 at near, 0 at far.
  gl_FragDepth = u_ortho != 0 ? 1.0 - (depth - u_near) / (u_far - u_near) : u_near / depth;
}
