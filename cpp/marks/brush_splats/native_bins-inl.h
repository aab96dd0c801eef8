// The brush_splats native kernels' screen bins (compiled once per SIMD
// target by native_kernels.cpp): a bin's depth pass, its blend of the
// candidates it kept, or its blend pass. (Highway's per-target include
// guard.)
#if defined(POINTNPR_BRUSH_NATIVE_BINS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef POINTNPR_BRUSH_NATIVE_BINS_INL_H_
#undef POINTNPR_BRUSH_NATIVE_BINS_INL_H_
#else
#define POINTNPR_BRUSH_NATIVE_BINS_INL_H_
#endif

#include <bit>

#include "core/radix_sort.h"
#include "marks/brush_splats/native_raster-inl.h"

HWY_BEFORE_NAMESPACE();
namespace pointnpr::brush_native::HWY_NAMESPACE {

// The test of one run (one splat's candidates, each on its own pixel)
// against the final surface, a vector at a time; the kept ones blend one
// by one, in order.
void BlendRun(const Splat& sp, const Settings& s, const Images& im, const Candidates& c, uint32_t begin, uint32_t end) {
  const DF d;
  const DI di;
  const DU du;
  const uint32_t lanes = uint32_t(hn::Lanes(d));
  const VF offset = hn::Set(d, sp.offset);
  const VI lane = hn::Iota(di, 0);
  const MF ortho = FirstLanes(lane, s.ortho ? int(lanes) : 0);
  // (Locals: the blend's stores must not make the compiler fetch them again.)
  const uint32_t* const qs = c.q.get();
  const float *const depths = c.depth.get(), *const lengths = c.length.get(), *const a1 = c.a1.get(), *const a2 = c.a2.get();
  for (uint32_t i = begin; i < end; i += lanes) {
    const MF live = FirstLanes(lane, int(end - i));
    // (A lane past the run reads pixel 0's surface.)
    const VI q = hn::BitCast(di, hn::IfThenElseZero(hn::RebindMask(du, live), hn::LoadU(du, qs + i)));
    const VF depth = hn::LoadU(d, depths + i), length = hn::LoadU(d, lengths + i);
    const VF surface = hn::GatherIndex(d, im.surface, q);
    const VF behind = hn::Sub(depth, surface), reach = hn::Mul(depth, offset);
    const MF near = hn::Or(ortho, hn::Le(hn::Mul(hn::Mul(length, behind), behind), hn::Mul(reach, reach)));
    const MF keep = hn::Or(hn::Le(depth, surface), hn::And(hn::Le(hn::Sub(depth, offset), surface), near));
    for (unsigned m = MaskBits(hn::And(keep, live)); m != 0; m &= m - 1) {
      const uint32_t k = i + uint32_t(__builtin_ctz(m));
      blend(sp, s, im, qs[k], depths[k], a1[k], a2[k]);
    }
  }
}

// The blend of a bin's candidates against its final surface, splats in
// point order (the bin's list of n): the blend pass's tests and float
// operations, so its bytes.
void BlendCandidates(const BinInputs& in, const uint32_t* list, size_t n, Candidates& c) {
  std::vector<uint32_t>& run_at = c.run_at;  // by place, past the runs: none
  run_at.assign(n, uint32_t(c.runs.size()));
  for (size_t r = 0; r < c.runs.size(); ++r) run_at[c.runs[r].place] = uint32_t(r);
  for (size_t place = 0; place < n; ++place) {
    if (run_at[place] == c.runs.size()) continue;
    const Candidates::Run& run = c.runs[run_at[place]];
    BlendRun(in.splats[list[place]], *in.s, *in.im, c, run.begin, run.end);
  }
}

template <Pass P>
void RasterizeSplat(uint32_t place, const Splat& sp, const Settings& s, const Rect& area, const Images& im,
                    BlockDepths& blocks, Candidates* out) {
  if (s.ortho) Rasterize<P, true>(place, sp, s, area, im, blocks, out);
  else Rasterize<P, false>(place, sp, s, area, im, blocks, out);
}

// The blend pass over a bin: in point order, splats behind the surface by
// more than their offset dropped.
void BlendPass(const BinInputs& in, const Rect& area, const uint32_t* list, size_t n, BlockDepths& blocks) {
  blocks.rescan_all();
  for (size_t j = 0; j < n; ++j) {
    const SplatKey& key = in.keys[list[j]];
    if (key.near - key.offset > blocks.under(key.lo, key.hi)) continue;
    RasterizeSplat<Pass::kBlend>(list[j], in.splats[list[j]], *in.s, area, *in.im, blocks, nullptr);
  }
}

// The depth pass over a bin (kBoth: then the blend of the candidates it
// kept; true where they overflowed and the blend ran as a pass of its own).
// The nearest depth does not depend on the order: near splats first leave
// most later fragments behind it, unshaded. Sorted as keys of the nearest
// depth (positive, beyond the near plane: its bits sort as it) over the
// place in the list (in point order), read in point order, not through
// the splats.
template <Pass P>
bool DepthPass(const BinInputs& in, const Rect& area, const uint32_t* list, size_t n, BinScratch& scratch,
               BlockDepths& blocks) {
  std::vector<uint64_t>& near = scratch.near;
  std::vector<SplatKey>& listed = scratch.listed;  // the bin's keys in list order,
  std::vector<SplatKey>& sorted = scratch.sorted;  // then in depth order
  near.resize(n);
  listed.resize(n);
  float max_offset = 0.0f;
  for (size_t j = 0; j < n; ++j) {
    const SplatKey& key = listed[j] = in.keys[list[j]];
    near[j] = uint64_t(std::bit_cast<uint32_t>(key.near)) << 32 | j;
    max_offset = std::max(max_offset, key.offset);
  }
  stable_sort_by_high_words(near, scratch.sort_scratch);  // (ties: in list order, as std::sort)
  // Their keys in that order, gathered at once (from the bin's copy): the
  // loop below reads them in turn.
  sorted.resize(n);
  for (size_t j = 0; j < n; ++j) sorted[j] = listed[uint32_t(near[j])];
  Candidates& candidates = scratch.candidates;
  candidates.clear();
  // Once the splats since cover the bin's area (so the scan costs at most
  // what they did), the bin's farthest surface: every later splat (sorted)
  // behind it (by more than the offsets, kBoth) is dropped.
  float bin_far = kInf;
  const size_t bin_area = size_t(area.size().x) * size_t(area.size().y);
  size_t painted = 0;
  for (size_t j = 0; j < n; ++j) {
    // In depth order the splats are far apart in memory: fetched ahead.
    if (j + 8 < n) {
      const char* ahead = reinterpret_cast<const char*>(&in.splats[list[uint32_t(near[j + 8])]]);
      for (size_t line = 0; line < sizeof(Splat); line += 64) __builtin_prefetch(ahead + line);
    }
    const uint32_t place = uint32_t(near[j]);
    const SplatKey& key = sorted[j];
    const glm::ivec2 box = glm::min(key.hi, area.max) - glm::max(key.lo, area.min);
    painted += size_t(std::max(box.x, 0)) * size_t(std::max(box.y, 0));
    if (painted >= bin_area) {
      painted = 0;
      bin_far = blocks.under(area.min, area.max);
    }
    // Behind the blocks' bound, or (narrow boxes) behind the surface under the box.
    const bool narrow = box.x <= 8;
    if (P == Pass::kDepth) {
      if (key.near >= bin_far) break;
      if (key.near >= blocks.under(key.lo, key.hi)) continue;
      if (narrow && key.near >= blocks.under_exactly(key.lo, key.hi)) continue;
    } else {
      if (key.near - max_offset > bin_far) break;
      if (key.near - key.offset > blocks.under(key.lo, key.hi)) continue;
      if (narrow && key.near - key.offset > blocks.under_exactly(key.lo, key.hi)) continue;
    }
    RasterizeSplat<P>(place, in.splats[list[place]], *in.s, area, *in.im, blocks, &candidates);
  }
  if (P == Pass::kDepth) return false;
  if (!candidates.full) {
    BlendCandidates(in, list, n, candidates);
    return false;
  }
  BlendPass(in, area, list, n, blocks);
  return true;
}

// Kernels::draw_bin.
bool DrawBin(Pass pass, const BinInputs& in, const Rect& area, const uint32_t* list, size_t n, BinScratch& scratch) {
  BlockDepths blocks;
  blocks.area = area;
  blocks.im = in.im;
  switch (pass) {
    case Pass::kDepth: return DepthPass<Pass::kDepth>(in, area, list, n, scratch, blocks);
    case Pass::kBoth: return DepthPass<Pass::kBoth>(in, area, list, n, scratch, blocks);
    case Pass::kBlend: break;
  }
  BlendPass(in, area, list, n, blocks);
  return false;
}

}  // namespace pointnpr::brush_native::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
