// How much a mark grows where its points lie too sparse on screen for the
// ink it should give: `need` is that ink over what one mark per point gives
// (a ratio of areas), so the mark grows by its square root, along and
// across, at most MAX_SPARSE_GROWTH times (a lone point's mark stays near
// its size). The stipples' dots, the hatching's strokes and the feature
// strokes' marks grow by it; shared with the native backends (the subset of
// cpp/core/glsl.h), and the marks' extents read the cap
// (cpp/core/sparse_growth.h).
#ifndef SPARSE_GROWTH_GLSL
#define SPARSE_GROWTH_GLSL
#define MAX_SPARSE_GROWTH 3.0f
float sparse_growth(float need) { return need > 1.0f ? min(sqrt(need), MAX_SPARSE_GROWTH) : 1.0f; }
#endif
