#pragma once
// Squared distances from a point to candidates held as three arrays, and how
// many fall below each of three squared limits: the kNN's inner loop, on the
// widest SIMD lanes the CPU has (Google Highway, chosen at run time).
#include <array>
#include <cstddef>

namespace pointnpr::geometry {

// d2[j] = (px - x[j])^2 + (py - y[j])^2 + (pz - z[j])^2 for j < n, summed in
// that order without FMA (every CPU gets the same bytes); below[t] counts
// the d2 < limit2[t].
void squared_distances(const float* x, const float* y, const float* z, size_t n, const std::array<float, 3>& p,
                       const std::array<float, 3>& limit2, float* d2, std::array<size_t, 3>& below);

}  // namespace pointnpr::geometry
