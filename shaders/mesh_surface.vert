// The mesh_surface mark (cpp/marks/mesh_surface.cpp): one vertex per
// triangle corner, read from buffers by gl_VertexID. Reversed Z as the
// GL_POINTS path (glClipControl 0..1, GL_GREATER); the linear view depth
// is interpolated for the segment's depth image.
layout(std430, binding = 0) readonly buffer Positions { float positions[]; };
layout(std430, binding = 1) readonly buffer Normals { uint normals_u[]; };
layout(std430, binding = 2) readonly buffer Colors { uint colors_u[]; };
layout(std430, binding = 3) readonly buffer Uvs { vec2 uvs[]; };

uniform mat4 u_view_from_mesh;  // composed in double on the CPU, then cast
uniform mat3 u_normal_matrix;
uniform mat4 u_projection;
uniform float u_near;
uniform float u_far;
uniform int u_ortho;
uniform int u_smooth;
uniform int u_color_source;  // resolved: 1 base colour, 2 colours, 3 texture, 4 constant

out vec3 v_view;
out float v_depth;
out vec3 v_normal;
out vec4 v_color;
out vec2 v_uv;

void main() {
  uint i = uint(gl_VertexID);
  vec4 v = u_view_from_mesh * vec4(positions[3u * i], positions[3u * i + 1u], positions[3u * i + 2u], 1.0);
  v_view = v.xyz;
  v_depth = -v.z;
  v_normal = u_smooth != 0 ? u_normal_matrix * unpackSnorm4x8(normals_u[i]).xyz : vec3(0.0);
  v_color = u_color_source == 2 ? unpackUnorm4x8(colors_u[i]) : vec4(1.0);
  v_uv = u_color_source == 3 ? uvs[i] : vec2(0.0);
  vec4 clip = u_projection * v;
  // Perspective: z_ndc = near / depth (1 at the near plane, toward 0 far
  // away); orthographic: 1 at near, 0 at far.
  float z = u_ortho != 0 ? (1.0 - (v_depth - u_near) / (u_far - u_near)) * clip.w : u_near;
  gl_Position = vec4(clip.xy, z, clip.w);
}
