// The mesh_surface mark's triangles, shared by its passes
// (cpp/marks/mesh_surface.cpp). Coverage, depth and every attribute are
// evaluated per pixel from the frame pixel (not the window) in homogeneous
// 2D (Olano and Greer 1997): a frame drawn in tiles gets the bytes of the
// whole frame, which GL's own rasterization does not guarantee (its
// window coordinates round differently with a tile's viewport), and
// triangles crossing the camera plane need no clipping.

// What a triangle's pixels need, computed once per triangle and frame on
// the CPU (cpp/marks/mesh_surface.cpp, TriangleRaster: the same layout).
struct TriangleRaster {
  vec4 corners[2];  // the triangle GL draws around it, frame pixels: xy, zw of [0]; xy of [1]
  vec4 edge[3];  // xyz: an edge function's coefficients (b x c, c x a, a x b); edge[0].w: their determinant
  vec4 view[3];  // xyz: the corners in view space
};

layout(std430, binding = 4) readonly buffer Triangles { TriangleRaster triangles[]; };

uniform vec2 u_frame;    // the whole frame's size, pixels
uniform ivec2 u_origin;  // the frame pixel of the images' (0, 0)

mat3 edges_of(TriangleRaster t) { return mat3(t.edge[0].xyz, t.edge[1].xyz, t.edge[2].xyz); }

// The three homogeneous edge functions at a frame position (pixels): all
// share the sign of their sum where the position is inside, and the sum
// has the sign of the determinant in front of the camera.
vec3 edges_at(mat3 edges, vec2 frame_position) {
  return transpose(edges) * vec3(frame_position * 2.0 / u_frame - 1.0, 1.0);
}

// Perspective-correct barycentric weights (sum 1), wherever the plane is.
vec3 weights(vec3 e) {
  float sum = e.x + e.y + e.z;
  return sum != 0.0 ? e / sum : vec3(1.0 / 3.0);
}

// Inside the triangle (edges included, so shared edges leave no gaps) and
// in front of the camera.
bool covers(vec3 e, float det) {
  float sum = e.x + e.y + e.z;
  return sum * det > 0.0 && e.x * sum >= 0.0 && e.y * sum >= 0.0 && e.z * sum >= 0.0;
}
