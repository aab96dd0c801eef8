#include "geometry/features.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace pointnpr::geometry {

LocalResolution local_resolution(const Neighborhoods& nb) {
  const size_t n = nb.k ? nb.index.size() / size_t(nb.k) : 0;
  LocalResolution out;
  out.r.assign(n, 0.0f);
  out.eps.assign(n, 0.0f);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const float* d2 = nb.d2_at(i);
    const int m = nb.k - 1;  // the first entry is the point itself (distance 0)
    if (m <= 0) return;
    double s = 0.0, s2 = 0.0;
    for (int j = 1; j <= m; ++j) {
      const double d = std::sqrt(double(d2[j]));
      s += d;
      s2 += d * d;
    }
    const double mean = s / m;
    out.r[i] = float(mean);
    out.eps[i] = float(std::sqrt(std::max(0.0, s2 / m - mean * mean)));
  });
  return out;
}

namespace {
// Standard deviation of v over each neighbourhood.
std::vector<float> variation(const Neighborhoods& nb, const std::vector<float>& v) {
  const size_t n = v.size();
  std::vector<float> out(n, 0.0f);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    double s = 0.0, s2 = 0.0;
    for (int j = 0; j < nb.k; ++j) {
      const double x = v[nb.at(i)[j]];
      s += x;
      s2 += x * x;
    }
    const double mean = s / std::max(nb.k, 1);
    out[i] = float(std::sqrt(std::max(0.0, s2 / std::max(nb.k, 1) - mean * mean)));
  });
  return out;
}

void normalise_p99(std::vector<float>& v) {
  if (v.empty()) return;
  std::vector<float> tmp(v);
  const size_t at = std::min(tmp.size() - 1, size_t(double(tmp.size() - 1) * 0.99));
  std::nth_element(tmp.begin(), tmp.begin() + long(at), tmp.end());
  float scale = tmp[at];
  if (!(scale > 0.0f)) scale = *std::max_element(v.begin(), v.end());
  if (!(scale > 0.0f)) {
    std::fill(v.begin(), v.end(), 0.0f);
    return;
  }
  for (float& x : v) x = std::clamp(x / scale, 0.0f, 1.0f);
}
}  // namespace

std::vector<float> feature_degree(const Neighborhoods& nb, const std::vector<float>& curvature,
                                  const std::vector<uint32_t>& colors, float w) {
  if (!(w >= 0.0f && w <= 1.0f)) throw Error("color_weight must be in [0, 1]");
  std::vector<float> g = variation(nb, curvature);
  normalise_p99(g);
  if (colors.empty() || colors.size() != g.size() || w == 0.0f) return g;
  std::vector<float> lum(colors.size());
  for (size_t i = 0; i < colors.size(); ++i) {
    const uint32_t c = colors[i];
    lum[i] = (0.2126f * float(c & 255) + 0.7152f * float((c >> 8) & 255) + 0.0722f * float((c >> 16) & 255)) / 255.0f;
  }
  std::vector<float> cv = variation(nb, lum);
  normalise_p99(cv);
  for (size_t i = 0; i < g.size(); ++i) g[i] = (1.0f - w) * g[i] + w * cv[i];
  return g;
}

LineFit line_fit(const LocalPoints& pts, const std::vector<uint8_t>& mask, int k) {
  if (k < 1) throw Error("k must be at least 1");
  const size_t n = pts.size();
  if (!mask.empty() && mask.size() != n) throw Error("mask must have one value per point");
  LineFit out;
  out.direction.assign(n, glm::vec3(0.0f));
  out.error.assign(n, 1.0f);
  // The masked points, in Morton order.
  LocalPoints sub;
  sub.origin = pts.origin;
  sub.grid_min = pts.grid_min;
  sub.grid_scale = pts.grid_scale;
  for (size_t s = 0; s < n; ++s)
    if (mask.empty() || mask[pts.original[s]]) {
      sub.points.push_back(pts.points[s]);
      sub.original.push_back(pts.original[s]);
      sub.code.push_back(pts.code[s]);
    }
  if (sub.size() == 0) return out;
  const Neighborhoods nb = knn_all(sub, k);
  const PcaResult p = pca(sub, nb);
  for (size_t s = 0; s < sub.size(); ++s) {
    if (p.degenerate[s]) continue;
    out.direction[sub.original[s]] = p.major[s];
    out.error[sub.original[s]] = p.linear_error[s];
  }
  return out;
}

std::vector<uint8_t> inlier_mask(const Neighborhoods& nb, float std_ratio) {
  const size_t n = nb.k ? nb.index.size() / size_t(nb.k) : 0;
  std::vector<uint8_t> keep(n, 1);
  if (n == 0 || nb.k < 2) return keep;
  std::vector<double> d(n);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    double s = 0.0;
    for (int j = 1; j < nb.k; ++j) s += std::sqrt(double(nb.d2_at(i)[j]));
    d[i] = s / (nb.k - 1);
  });
  double s = 0.0, s2 = 0.0;
  for (double x : d) {
    s += x;
    s2 += x * x;
  }
  const double mean = s / double(n);
  const double sd = n > 1 ? std::sqrt(std::max(0.0, (s2 - s * mean) / double(n - 1))) : 0.0;
  const double limit = mean + double(std_ratio) * sd;
  for (size_t i = 0; i < n; ++i) keep[i] = d[i] <= limit * (1.0 + 1e-12) ? 1 : 0;
  return keep;
}

}  // namespace pointnpr::geometry
