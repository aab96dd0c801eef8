#include "geometry/feature_chains.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include "core/progress.h"

namespace pointnpr::geometry {

namespace {

struct Link {
  float cost;     // its length, more where it runs across its ends' lines
  uint32_t a, b;  // a < b
  bool operator<(const Link& o) const { return std::tie(cost, a, b) < std::tie(o.cost, o.a, o.b); }
};

uint32_t find_root(std::vector<uint32_t>& up, uint32_t i) {
  while (up[i] != i) {
    up[i] = up[up[i]];
    i = up[i];
  }
  return i;
}

// The scan's spacing along its feature lines: the median distance from a
// point to its nearest other point.
float median_nearest(const Neighborhoods& nb, size_t n) {
  std::vector<float> d;
  d.reserve(n);
  for (size_t s = 0; s < n && nb.k > 1; ++s) {
    const float d2 = nb.d2_at(s)[1];
    if (std::isfinite(d2)) d.push_back(d2);
  }
  if (d.empty()) return 0.0f;
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return std::sqrt(d[d.size() / 2]);
}

}  // namespace

FeatureChains feature_chains(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca) {
  const size_t n = pts.size();
  FeatureChains out;
  out.to_parent.assign(n, glm::vec3(0.0f));
  out.end.assign(n, 0);
  check_cancelled(current_progress());
  const float spacing = median_nearest(nb, n);
  const float max_link = kChainLinkSpacings * spacing, twig = kChainTwigSpacings * spacing;
  if (n == 0 || !(max_link > 0.0f)) return out;

  // Candidate links, each pair once. A link costs its length, more where it
  // runs across its ends' lines (the line fit's direction): in a band of
  // feature points the tree follows the band.
  std::vector<Link> links;
  const int m = std::min(nb.k, kChainCandidates + 1);
  auto line_like = [&](size_t s) { return !pca.degenerate[s] && pca.linear_error[s] < kChainLineLike; };
  for (size_t s = 0; s < n; ++s) {
    if (!line_like(s)) continue;
    for (int j = 1; j < m; ++j) {
      const uint32_t t = nb.at(s)[j];
      const float d2 = nb.d2_at(s)[j];
      if (t == s || !(d2 > 0.0f) || d2 > max_link * max_link || !line_like(t)) continue;
      const float d = std::sqrt(d2);
      const glm::vec3 e = (pts.points[t] - pts.points[s]) / d;
      const float across_s = pca.degenerate[s] ? 1.0f : 1.0f - std::abs(glm::dot(e, pca.major[s]));
      const float across_t = pca.degenerate[t] ? 1.0f : 1.0f - std::abs(glm::dot(e, pca.major[t]));
      // Past a neighbour's distance, only along both lines: a gap in a line is bridged, parallel lines are not.
      if (d > kChainNearSpacings * spacing && std::max(across_s, across_t) > 1.0f - kChainAlong) continue;
      links.push_back({d * (1.0f + across_s + across_t), uint32_t(std::min<size_t>(s, t)),
                       uint32_t(std::max<size_t>(s, t))});
    }
  }
  std::sort(links.begin(), links.end());
  links.erase(std::unique(links.begin(), links.end(),
                          [](const Link& x, const Link& y) { return x.a == y.a && x.b == y.b; }),
              links.end());

  // Kruskal: the cheapest links first, none closing a loop.
  std::vector<uint32_t> up(n);
  std::iota(up.begin(), up.end(), 0u);
  std::vector<std::vector<uint32_t>> tree(n);
  for (const Link& l : links) {
    const uint32_t ra = find_root(up, l.a), rb = find_root(up, l.b);
    if (ra == rb) continue;
    up[std::max(ra, rb)] = std::min(ra, rb);
    tree[l.a].push_back(l.b);
    tree[l.b].push_back(l.a);
  }
  auto length = [&](uint32_t a, uint32_t b) { return glm::length(pts.points[a] - pts.points[b]); };

  // Twigs (Pauly et al. 2003): a branch from a leaf to a fork shorter than
  // `twig` is the spanning tree filling a band's width, not a line. The
  // shortest first, and only while its fork keeps two other branches, so a
  // line's own end beyond a spur stays.
  struct Twig {
    float walked;
    uint32_t leaf, fork;
    std::vector<uint32_t> path;
  };
  std::vector<Twig> twigs;
  for (size_t leaf = 0; leaf < n; ++leaf) {
    if (tree[leaf].size() != 1) continue;
    Twig t{0.0f, uint32_t(leaf), 0, {uint32_t(leaf)}};
    uint32_t prev = uint32_t(leaf), cur = tree[leaf][0];
    t.walked = length(prev, cur);
    while (tree[cur].size() == 2 && t.walked < twig) {
      t.path.push_back(cur);
      const uint32_t next = tree[cur][0] == prev ? tree[cur][1] : tree[cur][0];
      t.walked += length(cur, next);
      prev = cur;
      cur = next;
    }
    t.fork = cur;
    if (tree[cur].size() >= 3 && t.walked < twig) twigs.push_back(std::move(t));
  }
  std::sort(twigs.begin(), twigs.end(),
            [](const Twig& a, const Twig& b) { return std::tie(a.walked, a.leaf) < std::tie(b.walked, b.leaf); });
  std::vector<uint32_t> branches(n);
  for (size_t s = 0; s < n; ++s) branches[s] = uint32_t(tree[s].size());
  std::vector<uint8_t> cut(n, 0);
  for (const Twig& t : twigs) {
    if (branches[t.fork] < 3) continue;
    --branches[t.fork];
    for (uint32_t s : t.path) cut[s] = 1;
  }
  for (size_t s = 0; s < n; ++s) {
    auto& t = tree[s];
    t.erase(std::remove_if(t.begin(), t.end(), [&](uint32_t o) { return cut[o] || cut[s]; }), t.end());
  }

  // Each remaining tree at least a twig long is rooted at its first point;
  // parents by breadth-first search.
  std::vector<uint8_t> seen(n, 0);
  std::vector<uint32_t> queue, parent(n);
  for (size_t r = 0; r < n; ++r) {
    if (seen[r] || tree[r].empty()) continue;
    queue.assign(1, uint32_t(r));
    seen[r] = 1;
    float total = 0.0f;
    for (size_t q = 0; q < queue.size(); ++q)
      for (uint32_t t : tree[queue[q]])
        if (!seen[t]) {
          seen[t] = 1;
          parent[t] = queue[q];
          total += length(queue[q], t);
          queue.push_back(t);
        }
    if (total < twig) continue;
    for (size_t q = 1; q < queue.size(); ++q) {
      const uint32_t t = queue[q], s = parent[t];
      out.to_parent[t] = pts.points[s] - pts.points[t];
      out.end[t] = uint8_t((tree[t].size() == 1 ? kChainEnd : 0) | (tree[s].size() == 1 ? kChainParentEnd : 0));
    }
  }
  return out;
}

}  // namespace pointnpr::geometry
