// brush_splats A-buffer: where each pixel's list starts. PASS_ROWS: one
// invocation per row, the exclusive prefix of the counts along it and the
// row's total; PASS_TOTAL: one invocation, the prefix over rows and the
// rect's total (row_base[rows]). Sequential sums: deterministic.
#include "brush_abuffer.glsl"
#ifdef PASS_ROWS
layout(local_size_x = 64) in;
#else
layout(local_size_x = 1) in;
#endif
uniform ivec2 u_rect_min;
uniform ivec2 u_rect_max;

void main() {
#ifdef PASS_ROWS
  int y = u_rect_min.y + int(gl_GlobalInvocationID.x);
  if (y >= u_rect_max.y) return;
  uint sum = 0u;
  for (int x = u_rect_min.x; x < u_rect_max.x; ++x) {
    uint p = pixel_of(ivec2(x, y));
    offsets[p] = sum;
    sum = add_saturating(sum, counts[p]);
  }
  row_base[y - u_list_origin.y] = sum;
#else
  uint running = 0u;
  for (int y = u_rect_min.y; y < u_rect_max.y; ++y) {
    uint total = row_base[y - u_list_origin.y];
    row_base[y - u_list_origin.y] = running;
    running = add_saturating(running, total);
  }
  row_base[u_list_size.y] = running;
#endif
}
