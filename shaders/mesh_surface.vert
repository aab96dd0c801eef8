// The mesh_surface mark (cpp/marks/mesh_surface.cpp): every triangle is
// drawn as a slightly larger triangle set up for it on the CPU (its edges
// moved out by a fraction of a pixel, or, for a triangle reaching behind
// the camera or too thin, one around the rectangle of the pixels it may
// cover), so GL draws every pixel whose centre it covers in any tile; the
// fragments decide which of them it covers. Three vertices by
// gl_VertexID, no vertex buffers.
#include "mesh_surface_common.glsl"

uniform uint u_first;  // the batch's first triangle

flat out uint v_triangle;  // in the mesh (its corners' attributes)
// The triangle's TriangleRaster, as flat varyings: set up once per
// triangle by the GL, not loaded per fragment.
flat out mat3 v_edges;
flat out float v_det;
flat out mat3 v_views;

void main() {
  uint local = uint(gl_VertexID) / 3u;
  uint corner = uint(gl_VertexID) % 3u;
  v_triangle = u_first + local;
  TriangleRaster t = triangles[local];
  v_edges = edges_of(t);
  v_det = t.edge[0].w;
  v_views = mat3(t.view[0].xyz, t.view[1].xyz, t.view[2].xyz);
  vec2 at = corner == 0u ? t.corners[0].xy : corner == 1u ? t.corners[0].zw : t.corners[1].xy;
  gl_Position = vec4(at * 2.0 / u_frame - 1.0, 0.5, 1.0);
}
