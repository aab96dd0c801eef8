// The brush_splats native kernels' rasterizer (compiled once per SIMD
// target by native_kernels.cpp): a splat's rows, its fragments' depth
// tests and brush, and what the depth pass keeps. (Highway's per-target
// include guard.)
#if defined(POINTNPR_BRUSH_NATIVE_RASTER_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef POINTNPR_BRUSH_NATIVE_RASTER_INL_H_
#undef POINTNPR_BRUSH_NATIVE_RASTER_INL_H_
#else
#define POINTNPR_BRUSH_NATIVE_RASTER_INL_H_
#endif

#include "marks/brush_splats/native_brush-inl.h"

HWY_BEFORE_NAMESPACE();
namespace pointnpr::brush_native::HWY_NAMESPACE {

// A splat's fragments that passed the depth tests, gathered (in the
// order the row loop meets them) so the brush is evaluated for many at a
// time. Each pixel appears once per splat, so deferring its write changes
// nothing another of the splat's fragments reads.
struct Fragments {
  static constexpr int kMax = 256;  // a multiple of the lanes, at least a row (a bin's side)
  static_assert(kMax % kMaxLanes == 0 && kMax >= kBinSide);
  int n = 0;
  uint32_t q[kMax + kMaxLanes];  // (slack: the lanes store a whole vector)
  alignas(32) float u[kMax + kMaxLanes], v[kMax + kMaxLanes], depth[kMax + kMaxLanes];
  // Pass::kBoth: |p|^2 of the pixel's point on the plane, and whether the
  // fragment is nearer than the surface (else only near it; nonzero: nearer).
  alignas(32) float length[kMax + kMaxLanes];
  int32_t nearer[kMax + kMaxLanes];
};

// A perspective splat's row: the numbers its pixels' lanes need.
struct RowLanes {
  float plane, d0, dx, u0, ux, v0, vx, cu, cv, near_d, far_d, offset;
  glm::vec3 hx, hr;
  int origin_x;
  const float* surface;  // the row's, by local x (the images hold a vector's slack past their end)
  size_t line;           // the row's first pixel, by local x
};

// The row's pixels [x0, x1) a vector at a time: on the quad, and nearer
// than the surface (depth pass) or near it (blend: within the offset moved
// toward the camera along the pixel's ray, at most to the camera: depth (1
// - offset / max(|p|, depth)) <= surface, as |p| (depth - surface) <= depth
// offset, squared). Those kept go to `f` in row order; returns whether one
// is nearer than the surface (Pass::kBoth keeps those near it, as the blend).
template <Pass P>
HWY_INLINE bool RowFragments(const RowLanes& r, int x0, int x1, Fragments& f) {
  constexpr bool kDepth = P == Pass::kDepth;
  const DF d;
  const DI di;
  const DU du;
  const int lanes = int(hn::Lanes(d));
  bool any_nearer = false;
  int kept = f.n;  // (a local: stores to the arrays of f could alias f.n)
  const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f), huge = hn::Set(d, 3.0e38f), half = hn::Set(d, 0.5f);
  const VF plane = hn::Set(d, r.plane), d0 = hn::Set(d, r.d0), dx = hn::Set(d, r.dx);
  const VF u0 = hn::Set(d, r.u0), ux = hn::Set(d, r.ux), cu = hn::Set(d, r.cu);
  const VF v0 = hn::Set(d, r.v0), vx = hn::Set(d, r.vx), cv = hn::Set(d, r.cv);
  const VF hrz = hn::Set(d, r.hr.z), hxz = hn::Set(d, r.hx.z);
  const VF near_d = hn::Set(d, r.near_d), far_d = hn::Set(d, r.far_d), offset = hn::Set(d, r.offset);
  const VI lane = hn::Iota(di, 0);
  for (int xs = x0; xs < x1; xs += lanes) {
    const VF xc = hn::Add(hn::ConvertTo(d, hn::Add(hn::Set(di, xs + r.origin_x), lane)), half);
    const VF t = hn::Div(plane, hn::Add(d0, hn::Mul(xc, dx)));
    const VF pz = hn::Mul(t, hn::Add(hrz, hn::Mul(xc, hxz)));
    const VF u = hn::Add(hn::Mul(t, hn::Add(u0, hn::Mul(xc, ux))), cu);
    const VF v = hn::Add(hn::Mul(t, hn::Add(v0, hn::Mul(xc, vx))), cv);
    const VF depth = hn::Min(far_d, hn::Max(near_d, hn::Neg(pz)));
    // Off the quad, or the plane seen edge on (not finite): nothing.
    MF keep = hn::And(FirstLanes(lane, x1 - xs), hn::Lt(hn::Abs(pz), huge));
    keep = hn::And(keep, hn::And(hn::Ge(u, zero), hn::Le(u, one)));
    keep = hn::And(keep, hn::And(hn::Ge(v, zero), hn::Le(v, one)));
    const VF surface = hn::LoadU(d, r.surface + xs);
    const MF nearer = hn::And(keep, hn::Lt(depth, surface));
    any_nearer |= !hn::AllFalse(d, nearer);
    VF length = zero;
    if (kDepth) {
      keep = nearer;
    } else {
      const VF px = hn::Mul(hn::Add(hn::Mul(hn::Set(d, r.hx.x), xc), hn::Set(d, r.hr.x)), t);
      const VF py = hn::Mul(hn::Add(hn::Mul(hn::Set(d, r.hx.y), xc), hn::Set(d, r.hr.y)), t);
      const VF pw = hn::Mul(hn::Add(hn::Mul(hxz, xc), hrz), t);
      length = hn::Add(hn::Add(hn::Mul(px, px), hn::Mul(py, py)), hn::Mul(pw, pw));
      const VF behind = hn::Sub(depth, surface), reach = hn::Mul(depth, offset);
      const MF moved = hn::And(hn::Le(hn::Sub(depth, offset), surface),
                               hn::Le(hn::Mul(hn::Mul(length, behind), behind), hn::Mul(reach, reach)));
      keep = hn::And(keep, hn::Or(hn::Le(depth, surface), moved));
    }
    if (hn::AllFalse(d, keep)) continue;
    const unsigned bits = MaskBits(keep);
    StorePacked(du, hn::Add(hn::Set(du, uint32_t(r.line + size_t(xs))), hn::BitCast(du, lane)), bits, f.q + kept);
    StorePacked(d, u, bits, f.u + kept);
    StorePacked(d, v, bits, f.v + kept);
    StorePacked(d, depth, bits, f.depth + kept);
    if (P == Pass::kBoth) {
      StorePacked(d, length, bits, f.length + kept);
      StorePacked(di, hn::VecFromMask(di, hn::RebindMask(di, nearer)), bits, f.nearer + kept);
    }
    const int count = __builtin_popcount(bits);
    kept += count;
  }
  f.n = kept;
  return any_nearer;
}

// Each row's first pixel and its end past the last (frame pixels; none:
// both 0), rows [lo_y, hi_y) a vector of rows at a time: the quad's edges
// met with the row through the pixel centres, a pixel wider each side (the
// uv test decides, so the slope's rounding moves no pixel on or off it).
constexpr int kRows = kBinSide + kMaxLanes;
HWY_INLINE void RowBounds(const Splat& sp, int origin_y, int lo_y, int hi_y, int32_t* row_x0, int32_t* row_x1) {
  float edge_x[4], edge_y[4], edge_lo[4], edge_hi[4], edge_slope[4], flat_min[4], flat_max[4];
  for (int e = 0; e < 4; ++e) {
    const float xa = sp.wx[e], ya = sp.wy[e], xb = sp.wx[(e + 1) & 3], yb = sp.wy[(e + 1) & 3];
    edge_x[e] = xa;
    edge_y[e] = ya;
    edge_lo[e] = std::min(ya, yb);
    edge_hi[e] = std::max(ya, yb);
    edge_slope[e] = ya == yb ? 0.0f : (xb - xa) / (yb - ya);
    // A level edge on the row: both its ends.
    flat_min[e] = ya == yb ? std::min(xa, xb) : kInf;
    flat_max[e] = ya == yb ? std::max(xa, xb) : -kInf;
  }
  const DF d;
  const DI di;
  const int lanes = int(hn::Lanes(d));
  const VF half = hn::Set(d, 0.5f);
  const VI lane = hn::Iota(di, 0);
  for (int y = lo_y; y < hi_y; y += lanes) {
    const VF yc = hn::Add(hn::ConvertTo(d, hn::Add(hn::Set(di, y + origin_y), lane)), half);
    VF x_min = hn::Set(d, kInf), x_max = hn::Set(d, -kInf);
    for (int e = 0; e < 4; ++e) {
      const MF meets = hn::And(hn::Le(hn::Set(d, edge_lo[e]), yc), hn::Le(yc, hn::Set(d, edge_hi[e])));
      const VF xc = hn::Add(hn::Set(d, edge_x[e]), hn::Mul(hn::Sub(yc, hn::Set(d, edge_y[e])), hn::Set(d, edge_slope[e])));
      x_min = hn::IfThenElse(meets, hn::Min(hn::Min(hn::Set(d, flat_min[e]), xc), x_min), x_min);
      x_max = hn::IfThenElse(meets, hn::Max(hn::Max(hn::Set(d, flat_max[e]), xc), x_max), x_max);
    }
    const auto none = hn::RebindMask(di, hn::Not(hn::Le(x_min, x_max)));  // (also NaN)
    hn::Store(hn::IfThenZeroElse(none, FloorInt(hn::Sub(x_min, half))), di, row_x0 + (y - lo_y));
    hn::Store(hn::IfThenZeroElse(none, hn::Add(FloorInt(hn::Sub(x_max, half)), hn::Set(di, 2))), di,
              row_x1 + (y - lo_y));
  }
}

// The covering fragments of a shaded group: they move the surface (the
// depth pass; kBoth: those nearer than it) and, with `out`, join the
// candidates, packed in order.
template <Pass P>
HWY_INLINE void KeepCovering(const Splat& sp, Fragments& f, const float* a1, const float* a2, const Images& im,
                             Candidates* out) {
  const DF d;
  const DI di;
  const DU du;
  const int lanes = int(hn::Lanes(d)), n = f.n;
  const VF cut = hn::Set(d, kBrushCut), surface_cut = hn::Set(d, kSurfaceCut), one = hn::Set(d, 1.0f);
  const VI lane = hn::Iota(di, 0);
  size_t recorded = out ? out->count : 0;
  for (int j = 0; j < n; j += lanes) {
    const VF a = hn::Load(d, a1 + j);
    MF covers = hn::Ge(a, cut);
    VF total = a, b = hn::Zero(d);
    if (sp.two) {  // (neither layer reached the cut alone, in the depth pass: both sums are whole)
      b = hn::Load(d, a2 + j);
      total = hn::Add(b, hn::Mul(a, hn::Sub(one, b)));
      covers = hn::Or(covers, hn::Or(hn::Ge(b, cut), hn::Ge(total, cut)));
    }
    covers = hn::And(covers, FirstLanes(lane, n - j));
    if (hn::AllFalse(d, covers)) continue;
    MF moves = hn::And(covers, hn::Ge(total, surface_cut));
    if (P == Pass::kBoth)
      moves = hn::And(moves, hn::RebindMask(d, hn::Ne(hn::LoadU(di, f.nearer + j), hn::Zero(di))));
    for (unsigned m = MaskBits(moves); m != 0; m &= m - 1) {
      const int i = j + __builtin_ctz(m);
      im.surface[f.q[i]] = f.depth[i];
      im.offset[f.q[i]] = sp.offset;
    }
    if (!out) continue;
    const unsigned bits = MaskBits(covers);
    StorePacked(du, hn::LoadU(du, f.q + j), bits, out->q.get() + recorded);
    StorePacked(d, hn::Load(d, f.depth + j), bits, out->depth.get() + recorded);
    StorePacked(d, hn::Load(d, f.length + j), bits, out->length.get() + recorded);
    StorePacked(d, a, bits, out->a1.get() + recorded);
    StorePacked(d, b, bits, out->a2.get() + recorded);
    recorded += size_t(__builtin_popcount(bits));
  }
  if (out) out->count = recorded;
  f.n = 0;
}

// The brush of a splat's gathered fragments, then their depth (depth
// pass), blend, or both: depth, and the candidates that cover.
template <Pass P>
void Shade(const Splat& sp, const Settings& s, const Layer& first, const Layer& second, Fragments& f,
           const Images& im, Candidates* out) {
  const int n = f.n;
  if (n == 0) return;
  const int padded = (n + kMaxLanes - 1) & ~(kMaxLanes - 1);  // whole vectors
  for (int j = n; j < padded; ++j) f.u[j] = f.v[j] = f.depth[j] = f.length[j] = 0.0f;
  alignas(32) float a1[Fragments::kMax], a2[Fragments::kMax];
  BrushAlphas(s, first, f.u, f.v, n, a1);
  // Weighed as the fragment shaders do: each layer's alpha times the weight.
  if (sp.weight != 1.0f)
    for (int j = 0; j < n; ++j) a1[j] *= sp.weight;
  if (sp.two) {
    alignas(32) float u2[Fragments::kMax], v2[Fragments::kMax];
    for (int j = 0; j < padded; ++j) {
      u2[j] = (f.u[j] - 0.5f) / s.layer_scale + 0.5f;
      v2[j] = (f.v[j] - 0.5f) / s.layer_scale + 0.5f;
    }
    BrushAlphas(s, second, u2, v2, n, a2);
    if (sp.weight != 1.0f)
      for (int j = 0; j < n; ++j) a2[j] *= sp.weight;
  }
  if (P == Pass::kBlend) {
    for (int j = 0; j < n; ++j) blend(sp, s, im, f.q[j], f.depth[j], a1[j], sp.two ? a2[j] : 0.0f);
    f.n = 0;
    return;
  }
  // Room for the candidates, or none kept from here on.
  if (P == Pass::kBoth && !out->full && out->count + size_t(n) > Candidates::kMax) out->full = true;
  if (P == Pass::kBoth && !out->full) out->reserve(out->count + size_t(n));
  KeepCovering<P>(sp, f, a1, a2, im, P == Pass::kBoth && !out->full ? out : nullptr);
}

// A splat's fragments over `area` in pass P (kBoth: its candidates to
// `out`, as one run, by its place in the bin's list). The depth passes
// mark the blocks of the rows where a fragment was nearer than the surface.
template <Pass P, bool kOrtho>
void Rasterize(uint32_t place, const Splat& sp, const Settings& s, const Rect& area, const Images& im,
               BlockDepths& blocks, Candidates* out) {
  constexpr bool kDepth = P == Pass::kDepth;
  const glm::ivec2 lo = glm::max(sp.lo, area.min), hi = glm::min(sp.hi, area.max);
  if (lo.x >= hi.x || lo.y >= hi.y) return;
  const size_t begin = P == Pass::kBoth ? out->count : 0;
  Fragments frags;
  // The layers at the first fragments that need the brush (most of a
  // depth pass's splats have none: they lie behind).
  Layer first, second;
  bool layers_ready = false;
  auto flush = [&] {
    if (frags.n == 0) return;
    if (!layers_ready) {
      layers_ready = true;
      first = layer(s, sp.cs, sp.sn);
      if (sp.two) {
        float cs[3], sn[3];  // turned by the layer angle: cos(t + l), sin(t + l)
        for (int c = 0; c < 3; ++c) {
          cs[c] = sp.cs[c] * s.layer_cos - sp.sn[c] * s.layer_sin;
          sn[c] = sp.sn[c] * s.layer_cos + sp.cs[c] * s.layer_sin;
        }
        second = layer(s, cs, sn);
      }
    }
    Shade<P>(sp, s, first, second, frags, im, out);
  };
  const float plane = glm::dot(sp.center, sp.normal);
  const glm::vec4 col_x = s.view_from_pixel[0], col_y = s.view_from_pixel[1], col_w = s.view_from_pixel[3];
  // Perspective: the pixel's ray h (homogeneous, linear in the frame pixel)
  // meets the plane at p = h.xyz t, t = plane / dot(h.xyz, n) (h.w cancels):
  // the ray's dot products with n, the axes and z are linear along a row.
  const glm::vec3 hx(col_x);
  const float dx = glm::dot(hx, sp.normal), ux = glm::dot(hx, sp.u_axis), vx = glm::dot(hx, sp.v_axis);
  const float cu = 0.5f - glm::dot(sp.center, sp.u_axis), cv = 0.5f - glm::dot(sp.center, sp.v_axis);
  const float near_d = sp.depth_range.x, far_d = sp.depth_range.y;
  alignas(32) int32_t row_x0[kRows], row_x1[kRows];
  RowBounds(sp, s.origin.y, lo.y, hi.y, row_x0, row_x1);
  for (int y = lo.y; y < hi.y; ++y) {
    const float yc = float(y + s.origin.y) + 0.5f;
    const int x0 = std::max(lo.x, row_x0[y - lo.y] - s.origin.x);
    const int x1 = std::min(hi.x, row_x1[y - lo.y] - s.origin.x);
    if (x0 >= x1) continue;
    // Room for a whole row (at most the area's width) before it is walked.
    if (frags.n + (x1 - x0) > Fragments::kMax) flush();
    const glm::vec4 row = col_y * yc + col_w;
    const glm::vec3 hr(row);
    const size_t line = size_t(y - im.min.y) * size_t(im.stride) - size_t(im.min.x);
    if (kOrtho) {
      for (int x = x0; x < x1; ++x) {
        // plane_point(): along -z through the pixel.
        const glm::vec4 h = col_x * (float(x + s.origin.x) + 0.5f) + row;
        const glm::vec3 on_ray = glm::vec3(h) / h.w;
        const glm::vec3 p(on_ray.x, on_ray.y, on_ray.z + glm::dot(sp.center - on_ray, sp.normal) / sp.normal.z);
        if (!(std::abs(p.z) < 3.0e38f)) continue;  // the plane seen edge on
        const glm::vec3 rel = p - sp.center;
        const float u = glm::dot(rel, sp.u_axis) + 0.5f, v = glm::dot(rel, sp.v_axis) + 0.5f;
        if (!(u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f)) continue;  // off the quad
        const float depth = std::clamp(-p.z, near_d, far_d), surface = im.surface[line + size_t(x)];
        // Orthographic rays are parallel: the move toward the camera is the offset itself.
        const bool nearer = depth < surface;
        const bool keep = kDepth ? nearer : (depth <= surface || depth - sp.offset <= surface);
        const int k = frags.n;
        frags.q[k] = uint32_t(line + size_t(x));
        frags.u[k] = u;
        frags.v[k] = v;
        frags.depth[k] = depth;
        frags.length[k] = 0.0f;
        frags.nearer[k] = nearer;
        frags.n += keep;
      }
      if (P != Pass::kBlend) blocks.touch(y, x0, x1);
      continue;
    }
    const float d0 = glm::dot(hr, sp.normal), u0 = glm::dot(hr, sp.u_axis), v0 = glm::dot(hr, sp.v_axis);
    const RowLanes r{plane, d0, dx, u0, ux, v0, vx, cu, cv, near_d, far_d, sp.offset, hx, hr,
                     s.origin.x, im.surface + line, line};
    if (RowFragments<P>(r, x0, x1, frags) && P != Pass::kBlend) blocks.touch(y, x0, x1);
  }
  flush();
  if (P == Pass::kBoth && out->count > begin) out->runs.push_back({place, uint32_t(begin), uint32_t(out->count)});
}

}  // namespace pointnpr::brush_native::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
