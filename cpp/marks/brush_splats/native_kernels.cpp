// The brush_splats native path's kernels, compiled once per SIMD target
// by Highway's foreach_target (this file includes itself): setup, the
// screen bins' passes and the blur, one source for every target. kernels()
// hands out the best target's, or the baseline's (the scalar one on
// x86-64) that tests compare them with.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "marks/brush_splats/native_kernels.cpp"
#include "render/point_color.h"  // diffuse_shaded(), the shaders' light

#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "marks/brush_splats/native_bins-inl.h"
#include "marks/brush_splats/native_blur-inl.h"
#include "marks/brush_splats/native_setup-inl.h"

HWY_BEFORE_NAMESPACE();
namespace pointnpr::brush_native::HWY_NAMESPACE {

Kernels TargetKernels() { return {&SetUp, &DrawBin, &BlurX, &BlurY, int(hn::Lanes(DF()))}; }

}  // namespace pointnpr::brush_native::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pointnpr::brush_native {
HWY_EXPORT(TargetKernels);

// (Chosen per call, not kept: a test may mock the CPU's targets.)
Kernels kernels(bool baseline) {
  return baseline ? HWY_STATIC_DISPATCH(TargetKernels)() : HWY_DYNAMIC_DISPATCH(TargetKernels)();
}
}  // namespace pointnpr::brush_native
#endif
