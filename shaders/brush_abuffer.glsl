// brush_splats blending (b): the A-buffer. Per pixel of the clip rect a
// list of fragments (counted first, so the lists are packed and sized
// exactly), then sorted by depth and point id and blended front to back.
// The lists cover the clip rect only: pixel q is (q - u_list_origin) in a
// rect u_list_size wide and high; its list is fragments[row_base[row] +
// offsets[pixel] ...] with counts[pixel] entries.
struct Fragment {
  float depth;  // linear view depth
  uint id;      // point id (ties)
  uint rg;      // half floats: straight colour
  uint ba;      // blue, alpha
};
layout(std430, binding = 8) buffer Counts { uint counts[]; };
layout(std430, binding = 9) buffer Cursors { uint cursors[]; };      // cleared to 0 before PASS_STORE
layout(std430, binding = 10) buffer RowBase { uint row_base[]; };    // per row of the rect, the total, the longest list
layout(std430, binding = 11) buffer Fragments { Fragment fragments[]; };
layout(std430, binding = 12) buffer Offsets { uint offsets[]; };     // within the row
uniform ivec2 u_list_origin;
uniform ivec2 u_list_size;

uint pixel_of(ivec2 q) { return uint(q.y - u_list_origin.y) * uint(u_list_size.x) + uint(q.x - u_list_origin.x); }
uint list_start(ivec2 q) { return row_base[q.y - u_list_origin.y] + offsets[pixel_of(q)]; }

// Sums that saturate: a total past 2^32 - 1 reads as "too many".
uint add_saturating(uint a, uint b) { return a + b < a ? 0xFFFFFFFFu : a + b; }
