// The brush_splats native kernels' lanes (compiled once per SIMD target by
// native_kernels.cpp): the vector types, the bins' surface bounds and the
// brush. Every kernel runs the scalar code's float operations in its order
// (no FMA: the file is compiled with -ffp-contract=off and calls no MulAdd;
// min and max with their operands in the order that makes x86's minps and
// maxps std::min and std::max: the targets differ only for a NaN, which no
// kept lane holds), so every target draws the same bytes. (Highway's
// per-target include guard.)
#if defined(POINTNPR_BRUSH_NATIVE_BRUSH_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef POINTNPR_BRUSH_NATIVE_BRUSH_INL_H_
#undef POINTNPR_BRUSH_NATIVE_BRUSH_INL_H_
#else
#define POINTNPR_BRUSH_NATIVE_BRUSH_INL_H_
#endif

#include <algorithm>

#include <hwy/highway.h>

#include "marks/brush_splats/brush_splats.h"
#include "marks/brush_splats/native_types.h"

HWY_BEFORE_NAMESPACE();
namespace pointnpr::brush_native::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// At most kMaxLanes floats (8: one register of the brush's pieces); the
// scalar target has one.
using DF = hn::CappedTag<float, kMaxLanes>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;
using MF = hn::Mask<DF>;

// floor_int() of each lane: i - (float(i) > v), |v| < 2^31 (callers bound it).
HWY_INLINE VI FloorInt(VF v) {
  const DF d;
  const DI di;
  const VI i = hn::ConvertTo(di, v);
  return hn::Sub(i, hn::IfThenElseZero(hn::RebindMask(di, hn::Gt(hn::ConvertTo(d, i), v)), hn::Set(di, 1)));
}
// For each mask of up to 8 lanes, the lanes it keeps in order (then
// zeros): the permutation that packs them to the front.
struct PackTable {
  alignas(32) int32_t lanes[256][8];
  constexpr PackTable() : lanes{} {
    for (int m = 0; m < 256; ++m) {
      int k = 0;
      for (int i = 0; i < 8; ++i)
        if (m >> i & 1) lanes[m][k++] = i;
    }
  }
};
inline constexpr PackTable kPack;

// The lanes of `v` whose bit is set in `bits`, packed to the front of p's
// whole vector (the rest is slack the arrays hold). A permutation from a
// static table: Highway 1.0's Compress copies its 1 KiB table to the
// stack on every call on AVX2, and AVX-512's compressing store to memory
// is microcoded.
template <class D>
HWY_INLINE void StorePacked(D d, hn::Vec<D> v, unsigned bits, hn::TFromD<D>* p) {
  const hn::RebindToSigned<D> di;
  hn::StoreU(hn::TableLookupLanes(v, hn::IndicesFromVec(d, hn::Load(di, kPack.lanes[bits]))), d, p);
}
// Lanes [0, n) of `lane` (Iota(di, 0), made once per call: Highway 1.0
// makes Iota, and FirstN on AVX2, through the stack, a store-forwarding
// stall each time).
HWY_INLINE MF FirstLanes(VI lane, int n) { return hn::RebindMask(DF(), hn::Lt(lane, hn::Set(DI(), n))); }
// The lanes' mask bits (lane i: bit i).
HWY_INLINE unsigned MaskBits(MF m) {
  uint8_t bits[8] = {};
  hn::StoreMaskBits(DF(), m, bits);
  return bits[0];
}

// The farthest surface of each 8 x 8 block of a bin, or a bound beyond
// it: a splat whose nearest depth lies behind it under its box has no
// fragment nearer than the surface (depth pass), or near it (blend: behind
// by more than its offset), so it is dropped. The surface only comes
// nearer, so a block's farthest depth stays a bound; it is recomputed once
// kRescan of its rows were touched since (for small splats a rescan costs
// about what rasterizing one does), which drops no splat that the exact
// farthest surface would keep and so changes no byte, only the work.
struct BlockDepths {
  static constexpr int kSide = 8, kBlocks = kBinSide / kSide;  // blocks per axis
  static_assert(kBlocks * kBlocks == 64);
  static constexpr uint8_t kRescan = 4;
  float far[kBlocks * kBlocks];
  uint8_t touched[kBlocks * kBlocks];  // rows touched since the last scan (kRescan: scan at the next look)
  Rect area;
  const Images* im = nullptr;

  BlockDepths() { rescan_all(); }
  void rescan_all() { std::fill(touched, touched + kBlocks * kBlocks, kRescan); }
  // (The surface holds no NaN: the maximum does not depend on the order.)
  float block(int bx, int by) {
    const int b = by * kBlocks + bx;
    if (touched[b] >= kRescan) {
      touched[b] = 0;
      const DF d;
      const int lanes = int(hn::Lanes(d));
      const int x0 = area.min.x + bx * kSide, x1 = std::min(x0 + kSide, area.max.x);
      const int y0 = area.min.y + by * kSide, y1 = std::min(y0 + kSide, area.max.y);
      VF m_lanes = hn::Set(d, -kInf);
      float m = -kInf;
      for (int y = y0; y < y1; ++y) {
        const float* line = im->surface + size_t(y - im->min.y) * size_t(im->stride) - size_t(im->min.x);
        int x = x0;
        for (; x + lanes <= x1; x += lanes) m_lanes = hn::Max(m_lanes, hn::LoadU(d, line + x));
        for (; x < x1; ++x) m = std::max(m, line[x]);
      }
      far[b] = std::max(m, hn::GetLane(hn::MaxOfLanes(d, m_lanes)));
    }
    return far[b];
  }
  // The farthest surface under the pixels [lo, hi) (within the area).
  float under(glm::ivec2 lo, glm::ivec2 hi) {
    lo = glm::max(lo, area.min) - area.min;
    hi = glm::min(hi, area.max) - area.min;
    float m = -kInf;
    for (int by = lo.y / kSide; by <= (hi.y - 1) / kSide; ++by)
      for (int bx = lo.x / kSide; bx <= (hi.x - 1) / kSide; ++bx) m = std::max(m, block(bx, by));
    return m;
  }
  // The farthest surface under the pixels [lo, hi) exactly, for boxes at
  // most 8 pixels wide (the area's rows hold them; the images have
  // kMaxLanes of slack past their end).
  float under_exactly(glm::ivec2 lo, glm::ivec2 hi) const {
    const DF d;
    const VI lane = hn::Iota(DI(), 0);
    const int lanes = int(hn::Lanes(d));
    lo = glm::max(lo, area.min);
    hi = glm::min(hi, area.max);
    const VF none = hn::Set(d, -kInf);
    VF m = none;
    for (int y = lo.y; y < hi.y; ++y) {
      const float* line = im->surface + size_t(y - im->min.y) * size_t(im->stride) + size_t(lo.x - im->min.x);
      for (int x = 0; x < hi.x - lo.x; x += lanes)
        m = hn::Max(m, hn::IfThenElse(FirstLanes(lane, hi.x - lo.x - x), hn::LoadU(d, line + x), none));
    }
    return hn::GetLane(hn::MaxOfLanes(d, m));
  }
  void touch(int y, int x0, int x1) {  // row y's pixels [x0, x1) may have come nearer
    const int by = (y - area.min.y) / kSide;
    for (int bx = (x0 - area.min.x) / kSide; bx <= (x1 - 1 - area.min.x) / kSide; ++bx) {
      uint8_t& t = touched[by * kBlocks + bx];
      t = uint8_t(std::min(t + 1, int(kRescan)));
    }
  }
};

// One layer of a splat's brush: its columns' angles, and each Gaussian's
// centre turned by its column's angle (R c), so a fragment's q of every
// Gaussian is a few products.
struct Layer {
  float rcx[9], rcy[9];
  float column_cs[3], column_sn[3];
};
inline Layer layer(const Settings& s, const float* cs, const float* sn) {
  Layer l;
  std::copy(cs, cs + 3, l.column_cs);
  std::copy(sn, sn + 3, l.column_sn);
  for (int k = 0; k < s.gaussians; ++k) {
    const int c = s.column[k];
    l.rcx[k] = cs[c] * s.cx[k] - sn[c] * s.cy[k];
    l.rcy[k] = sn[c] * s.cx[k] + cs[c] * s.cy[k];
  }
  return l;
}

// row[i] of each lane's i (0 <= i < kPieces): a register permutation where
// the vector holds all kPieces (a constant on fixed-width targets), else a
// gather.
HWY_INLINE VF PieceCoefficient(const float* row, VI i) {
  const DF d;
  if (hn::Lanes(d) == kPieces) return hn::TableLookupLanes(hn::Load(d, row), hn::IndicesFromVec(d, i));
  return hn::GatherIndex(d, row, i);
}

// falloff() on the lanes, with the pieces of degree kD (0: the table); a
// lane out of reach (`in` clear) reads entry 0. The degree is a constant
// so that the Horner steps unroll and the brush's falloffs interleave.
template <int kD>
HWY_INLINE VF Falloff(const Settings& s, VF q, MF in) {
  const DF d;
  const DI di;
  VF t = hn::Mul(q, hn::Set(d, s.inv_reach));
  if (s.sqrt_index) t = hn::Sqrt(t);
  if constexpr (kD > 0) {
    const VF x = hn::Mul(t, hn::Set(d, float(kPieces)));
    const VI i = hn::IfThenElseZero(hn::RebindMask(di, in), hn::Min(hn::ConvertTo(di, x), hn::Set(di, kPieces - 1)));
    const VF f = hn::Sub(x, hn::ConvertTo(d, i));
    VF r = PieceCoefficient(s.poly[kD], i);
    for (int k = kD - 1; k >= 0; --k) r = hn::Add(hn::Mul(r, f), PieceCoefficient(s.poly[k], i));
    return r;
  }
  const VF at = hn::Mul(t, hn::Set(d, float(kTable)));
  const VI i = hn::IfThenElseZero(hn::RebindMask(di, in), hn::ConvertTo(di, at));
  const VF f = hn::Sub(at, hn::ConvertTo(d, i));
  const VF a = hn::GatherIndex(d, s.table.data(), i), b = hn::GatherIndex(d, s.table.data() + 1, i);
  return hn::Add(a, hn::Mul(f, hn::Sub(b, a)));
}

// brush_alpha() of brush_texture.glsl for fragments [0, n) of one layer
// (u, v aligned, padded to kMaxLanes): clamp(amplitude sum, 0, 1), the
// Gaussians in order; one with either axis beyond the reach adds nothing.
template <int kD>
void BrushAlphasOfDegree(const Settings& s, const Layer& l, const float* u, const float* v, int n, float* out) {
  const DF d;
  const int lanes = int(hn::Lanes(d));
  const VF inv_sx = hn::Set(d, s.inv_sx), inv_sy = hn::Set(d, s.inv_sy);
  const VF reach = hn::Set(d, s.reach), amplitude = hn::Set(d, s.amplitude);
  const VF zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const int columns = std::min(s.gaussians, 3);
  for (int j = 0; j < n; j += lanes) {
    const VF uj = hn::Load(d, u + j), vj = hn::Load(d, v + j);
    // Each column's rotated coordinates R (u, v), once for its Gaussians
    // (named vectors: SVE's have no arrays).
    auto along_x = [&](int c) {
      return hn::Sub(hn::Mul(hn::Set(d, l.column_cs[c]), uj), hn::Mul(hn::Set(d, l.column_sn[c]), vj));
    };
    auto along_y = [&](int c) {
      return hn::Add(hn::Mul(hn::Set(d, l.column_sn[c]), uj), hn::Mul(hn::Set(d, l.column_cs[c]), vj));
    };
    const VF x0 = along_x(0), y0 = along_y(0);
    const VF x1 = columns > 1 ? along_x(1) : zero, y1 = columns > 1 ? along_y(1) : zero;
    const VF x2 = columns > 2 ? along_x(2) : zero, y2 = columns > 2 ? along_y(2) : zero;
    VF sum = zero;
    for (int k = 0; k < s.gaussians; ++k) {
      const int c = s.column[k];
      const VF ax = c == 0 ? x0 : c == 1 ? x1 : x2, ay = c == 0 ? y0 : c == 1 ? y1 : y2;
      const VF qx = hn::Mul(hn::Abs(hn::Sub(ax, hn::Set(d, l.rcx[k]))), inv_sx);
      const VF qy = hn::Mul(hn::Abs(hn::Sub(ay, hn::Set(d, l.rcy[k]))), inv_sy);
      const MF in = hn::And(hn::Le(qx, reach), hn::Le(qy, reach));  // (NaN: out)
      if (hn::AllFalse(d, in)) continue;
      sum = hn::Add(sum, hn::IfThenElseZero(in, hn::Mul(Falloff<kD>(s, qx, in), Falloff<kD>(s, qy, in))));
    }
    hn::Store(hn::Min(hn::Max(hn::Mul(amplitude, sum), zero), one), d, out + j);
  }
}
inline void BrushAlphas(const Settings& s, const Layer& l, const float* u, const float* v, int n, float* out) {
  switch (s.pieces ? s.degree : 0) {
    case 3: return BrushAlphasOfDegree<3>(s, l, u, v, n, out);
    case 4: return BrushAlphasOfDegree<4>(s, l, u, v, n, out);
    case 5: return BrushAlphasOfDegree<5>(s, l, u, v, n, out);
    case 6: return BrushAlphasOfDegree<6>(s, l, u, v, n, out);
    case 7: return BrushAlphasOfDegree<7>(s, l, u, v, n, out);
    default: return BrushAlphasOfDegree<0>(s, l, u, v, n, out);
  }
}

// A fragment's blend of its brush's alpha a (a2: the second layer's) at its depth.
inline void blend(const Splat& sp, const Settings& s, const Images& im, size_t q, float depth, float a, float a2) {
  glm::vec3 rgb = sp.rgb;
  if (sp.two) {
    const glm::vec3 rgb2 = s.layer_tint >= 0.0f ? rgb * (1.0f - s.layer_tint) + glm::vec3(s.layer_tint)
                                                : rgb * (1.0f + s.layer_tint);
    const float total = a2 + a * (1.0f - a2);
    rgb = total > 0.0f ? (rgb2 * a2 + rgb * a * (1.0f - a2)) / total : rgb;
    a = total;
  }
  if (!(a >= kBrushCut)) return;
  float* acc = im.accum + 4 * q;
  acc[0] += rgb.r * a;
  acc[1] += rgb.g * a;
  acc[2] += rgb.b * a;
  acc[3] += a;
  im.reveal[q] *= 1.0f - a;
  im.nearest[q] = std::min(im.nearest[q], depth);
}

}  // namespace pointnpr::brush_native::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
