// brush_splats: the rims of brushes in front of another surface, written
// once for the GL passes (brush_rims.comp) and the native ones
// (cpp/marks/brush_splats/native.cpp) in the subset of cpp/core/glsl.h.
//
// Where a brush covers at least kSurfaceCut of a pixel it is the pixel's
// surface, and the splats behind it (beyond their depth tolerance) are cut
// away; a brush's rim in front of another surface (a tree crown over the
// ground, a statue over its hedge) then leaves the pixel partly covered by
// the rim alone: a pale crack around every such edge. A partly covered
// pixel from which a march through partly covered pixels of its own surface
// meets a surface behind it (one whose splats the blend would cut there:
// farther, less their own blend offset, than this surface continued over
// the step, which may turn up to kSteepestSurfaceSlope from the view) takes that
// surface under its rim, as the splats cut away would have laid it. A rim
// against nothing (the silhouette's outside), or within its own surface
// (neighbouring splats within each other's offsets), keeps its coverage.
// The includer defines rim_color(p) (straight colour and coverage, alpha 0
// where nothing is), rim_depth(p) (linear view depth), rim_offset(p) (the
// blend offset of the pixel's surface splat, 0 where no brush is the
// surface) and rim_in(p) (within the images).
#ifndef BRUSH_RIMS_GLSL
#define BRUSH_RIMS_GLSL

struct RimRule {
  float footprint0;  // a pixel's size at view depth d: footprint0 + d footprint1
  float footprint1;
  float grazing;     // kSteepestSurfaceSlope
  int reach;         // px: the longest march (a brush's reach on screen)
};

// Coverage that shows as whole (within half of 1/255): no rim to fill.
const float kRimOpaque = 1.0f - 0.5f / 255.0f;

// One of the 8 directions around a pixel (odd: the diagonals).
ivec2 rim_direction(int i) {
  int x = (i == 0 || i == 1 || i == 7) ? 1 : ((i == 3 || i == 4 || i == 5) ? -1 : 0);
  int y = (i == 1 || i == 2 || i == 3) ? 1 : ((i == 5 || i == 6 || i == 7) ? -1 : 0);
  return ivec2(x, y);
}

vec4 rim_fill(ivec2 q, RimRule r) {
  vec4 c = rim_color(q);
  if (!(c.w > 0.0f && c.w < kRimOpaque)) return c;
  float d = rim_depth(q);
  int nearest = r.reach + 1;  // the march that met a surface behind soonest (ties: the first direction)
  vec4 behind = vec4(0.0f);
  for (int i = 0; i < 8; ++i) {
    ivec2 dir = rim_direction(i);
    float run = (i & 1) != 0 ? 1.41421356f : 1.0f;  // a step's length
    float last = d;
    for (int k = 1; k < nearest; ++k) {
      ivec2 p = q + dir * k;
      if (!rim_in(p)) break;
      vec4 o = rim_color(p);
      if (!(o.w > 0.0f)) break;  // the silhouette's outside
      float od = rim_depth(p);
      float reach = (r.footprint0 + last * r.footprint1) * r.grazing * run + rim_offset(p);
      if (od > last + reach) {  // a surface behind this one
        nearest = k;
        behind = o;
        break;
      }
      if (od < last - reach || o.w >= kRimOpaque) break;  // a nearer surface, or this one covered
      last = od;
    }
  }
  if (nearest > r.reach) return c;
  float a = c.w + (1.0f - c.w) * behind.w;
  vec3 rgb = (vec3(c) * c.w + vec3(behind) * ((1.0f - c.w) * behind.w)) / a;
  return vec4(rgb, a);
}

#endif
