// The brush_splats native kernels' blur (compiled once per SIMD target by
// native_kernels.cpp): brush_blur.comp's two passes, a vector of pixels at
// a time where no tap reaches past the row's ends, else pixel by pixel
// with the shader's clamped taps: the same float operations in its order.
// Only the covered pixels (each row's span of them) are read and written:
// the others stay as they are (transparent), and no covered pixel reads
// their sums. (Highway's per-target include guard.)
#if defined(POINTNPR_BRUSH_NATIVE_BLUR_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef POINTNPR_BRUSH_NATIVE_BLUR_INL_H_
#undef POINTNPR_BRUSH_NATIVE_BLUR_INL_H_
#else
#define POINTNPR_BRUSH_NATIVE_BLUR_INL_H_
#endif

#include "marks/brush_splats/native_brush-inl.h"

HWY_BEFORE_NAMESPACE();
namespace pointnpr::brush_native::HWY_NAMESPACE {

// A neighbour at depth dq counts for a pixel at depth d: not infinite (a
// NaN counts), not beyond the tolerance.
inline bool BlurCounts(float dq, float d, float tolerance) {
  return !(std::isinf(dq) || std::abs(dq - d) > tolerance * d);
}
HWY_INLINE MF NotInf(VF v) { return hn::Not(hn::Eq(hn::Abs(v), hn::Set(DF(), kInf))); }
HWY_INLINE MF BlurCounts(VF dq, VF d, VF tolerance) {
  return hn::AndNot(hn::Gt(hn::Abs(hn::Sub(dq, d)), hn::Mul(tolerance, d)), NotInf(dq));
}

// Kernels::blur_x: rgb * w and w of the taps along x (w: the tap's weight
// times alpha), tap by tap, into the planar sums (one plane per channel).
void BlurX(const Settings& s, const float* color, const float* depth, const glm::ivec2* row_span, glm::ivec2 size,
           float* const* planes, int y0, int y1) {
  const DF d;
  const int lanes = int(hn::Lanes(d)), radius = s.blur_radius;
  const float* weight = s.blur_weight.data() + radius;  // by tap, -radius..radius
  const VF tolerance = hn::Set(d, s.blur_tolerance);
  for (int y = y0; y < y1; ++y) {
    const glm::ivec2 span = row_span[y];
    const size_t row = size_t(y) * size_t(size.x);
    const float* color_row = color + 4 * row;
    const float* depth_row = depth + row;
    float* const out[4] = {planes[0] + row, planes[1] + row, planes[2] + row, planes[3] + row};
    for (int x = span.x; x <= span.y;) {
      if (x + lanes <= span.y + 1 && x - radius >= 0 && x + lanes - 1 + radius <= size.x - 1) {
        const VF dx = hn::LoadU(d, depth_row + x);
        // (Named vectors: SVE's have no arrays.)
        VF sum_r = hn::Zero(d), sum_g = hn::Zero(d), sum_b = hn::Zero(d), sum_w = hn::Zero(d);
        for (int k = -radius; k <= radius; ++k) {
          const MF counts = BlurCounts(hn::LoadU(d, depth_row + x + k), dx, tolerance);
          VF r, g, b, a;
          hn::LoadInterleaved4(d, color_row + 4 * (x + k), r, g, b, a);
          const VF w = hn::Mul(hn::Set(d, weight[k]), a);
          sum_r = hn::Add(sum_r, hn::IfThenElseZero(counts, hn::Mul(r, w)));
          sum_g = hn::Add(sum_g, hn::IfThenElseZero(counts, hn::Mul(g, w)));
          sum_b = hn::Add(sum_b, hn::IfThenElseZero(counts, hn::Mul(b, w)));
          sum_w = hn::Add(sum_w, hn::IfThenElseZero(counts, w));
        }
        const MF live = NotInf(dx);
        hn::StoreU(hn::IfThenElseZero(live, sum_r), d, out[0] + x);
        hn::StoreU(hn::IfThenElseZero(live, sum_g), d, out[1] + x);
        hn::StoreU(hn::IfThenElseZero(live, sum_b), d, out[2] + x);
        hn::StoreU(hn::IfThenElseZero(live, sum_w), d, out[3] + x);
        x += lanes;
        continue;
      }
      const float dp = depth_row[x];
      float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      if (!std::isinf(dp)) {
        for (int k = -radius; k <= radius; ++k) {
          const int q = std::clamp(x + k, 0, size.x - 1);
          if (!BlurCounts(depth_row[q], dp, s.blur_tolerance)) continue;
          const float w = weight[k] * color_row[4 * q + 3];
          for (int ch = 0; ch < 3; ++ch) sum[ch] += color_row[4 * q + ch] * w;
          sum[3] += w;
        }
      }
      for (int ch = 0; ch < 4; ++ch) out[ch][x] = sum[ch];
      ++x;
    }
  }
}

// Kernels::blur_y: the planar sums of the rows within the radius (clamped
// to the frame), then each covered pixel's rgb as their ratio (alpha
// unchanged), in place.
void BlurY(const Settings& s, float* color, const float* depth, const glm::ivec2* row_span, glm::ivec2 size,
           const float* const* planes, int y0, int y1) {
  const DF d;
  const int lanes = int(hn::Lanes(d)), radius = s.blur_radius;
  const float* weight = s.blur_weight.data() + radius;
  const VF tolerance = hn::Set(d, s.blur_tolerance);
  auto at = [&](int x, int y) { return size_t(y) * size_t(size.x) + size_t(x); };
  for (int y = y0; y < y1; ++y) {
    const glm::ivec2 span = row_span[y];
    for (int x = span.x; x <= span.y;) {
      if (x + lanes <= span.y + 1) {
        const size_t i = at(x, y);
        const VF dx = hn::LoadU(d, depth + i);
        VF sum_r = hn::Zero(d), sum_g = hn::Zero(d), sum_b = hn::Zero(d), sum_w = hn::Zero(d);
        for (int k = -radius; k <= radius; ++k) {
          const size_t q = at(x, std::clamp(y + k, 0, size.y - 1));
          const MF counts = BlurCounts(hn::LoadU(d, depth + q), dx, tolerance);
          const VF w = hn::Set(d, weight[k]);
          sum_r = hn::Add(sum_r, hn::IfThenElseZero(counts, hn::Mul(w, hn::LoadU(d, planes[0] + q))));
          sum_g = hn::Add(sum_g, hn::IfThenElseZero(counts, hn::Mul(w, hn::LoadU(d, planes[1] + q))));
          sum_b = hn::Add(sum_b, hn::IfThenElseZero(counts, hn::Mul(w, hn::LoadU(d, planes[2] + q))));
          sum_w = hn::Add(sum_w, hn::IfThenElseZero(counts, hn::Mul(w, hn::LoadU(d, planes[3] + q))));
        }
        const MF covered = hn::And(NotInf(dx), hn::Gt(sum_w, hn::Zero(d)));
        x += lanes;
        if (hn::AllFalse(d, covered)) continue;
        alignas(32) float ratio[3][kMaxLanes];
        hn::Store(hn::Div(sum_r, sum_w), d, ratio[0]);
        hn::Store(hn::Div(sum_g, sum_w), d, ratio[1]);
        hn::Store(hn::Div(sum_b, sum_w), d, ratio[2]);
        for (unsigned m = MaskBits(covered); m != 0; m &= m - 1) {
          const int p = __builtin_ctz(m);
          float* c = color + 4 * (i + size_t(p));
          for (int ch = 0; ch < 3; ++ch) c[ch] = ratio[ch][p];
        }
        continue;
      }
      const size_t i = at(x++, y);
      const float dp = depth[i];
      float* c = &color[4 * i];  // (read before written: the pixel's own)
      if (std::isinf(dp)) continue;
      float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      for (int k = -radius; k <= radius; ++k) {
        const size_t q = at(x - 1, std::clamp(y + k, 0, size.y - 1));
        if (!BlurCounts(depth[q], dp, s.blur_tolerance)) continue;
        for (int ch = 0; ch < 4; ++ch) sum[ch] += weight[k] * planes[ch][q];
      }
      for (int ch = 0; ch < 3; ++ch) c[ch] = sum[3] > 0.0f ? sum[ch] / sum[3] : c[ch];
    }
  }
}

}  // namespace pointnpr::brush_native::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
