#pragma once
// Feature lines as chains: the feature points that lie along a line, linked
// to their neighbours along it, so the feature strokes mark draws an edge as
// one line through them rather than a tick per point (seed 001 draws a
// stroke per point; its edges then read as dashes wherever the points'
// strokes do not overlap).
#include <cstdint>
#include <vector>

#include "geometry/local_points.h"
#include "geometry/neighbors.h"
#include "geometry/normals.h"

namespace pointnpr::geometry {

// A forest over `pts` (LocalPoints order; nb its kNN with the point itself
// first, pca over nb), after Pauly et al. 2003's feature graphs: the minimum
// spanning forest of the links between points that lie along lines (their
// line fit's linear_error below kChainLineLike) at most kChainLinkSpacings
// times their median distance to their nearest neighbour apart (the scan's
// own spacing among its feature points), those longer than kChainNearSpacings
// along both ends' lines (a link bridges missing samples of a line, never
// two parallel lines), a link costing its length times 1 + how far it runs
// across the line fits of its ends (so in a band of feature points the tree
// follows the band); then the twigs cut (branches from a leaf to a fork
// shorter than kChainTwigSpacings spacings: the tree filling a band's width)
// and trees shorter than that dropped. Each tree left is rooted at its first
// point; every other point links to its parent. to_parent: the offset to the
// parent (0: not in a chain, or a root); end: the link's free ends
// (kChainEnd: the point has no other link; kChainParentEnd: nor has its
// parent), which a stroke tapers to.
struct FeatureChains {
  std::vector<glm::vec3> to_parent;
  std::vector<uint8_t> end;
};
constexpr uint8_t kChainEnd = 1;
constexpr uint8_t kChainParentEnd = 2;
constexpr float kChainLineLike = 0.3f;  // linear_error below which a point lies along a line
constexpr float kChainLinkSpacings = 8.0f;
constexpr float kChainNearSpacings = 1.5f;  // a longer link runs along both its ends' lines,
constexpr float kChainAlong = 0.866f;       // |cos| of the angle to each at least this (30 degrees)
constexpr float kChainTwigSpacings = 8.0f;
constexpr int kChainCandidates = 48;  // the nearest neighbours a link may go to
FeatureChains feature_chains(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca);

}  // namespace pointnpr::geometry
