#include "geometry/features.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.h"
#include "core/progress.h"
#include "geometry/feature_chains.h"

namespace pointnpr::geometry {

namespace {
// LocalResolution::sparse_r of r (0 where it is not positive and finite).
float sparse_spacing(std::vector<float> r) {
  if (r.empty()) return 0.0f;
  const size_t at = size_t(double(r.size() - 1) * 0.9);
  std::nth_element(r.begin(), r.begin() + long(at), r.end());
  return r[at] > 0.0f && std::isfinite(r[at]) ? r[at] : 0.0f;
}
}  // namespace

LocalResolution local_resolution(const Neighborhoods& nb) {
  const size_t n = nb.k ? nb.index.size() / size_t(nb.k) : 0;
  LocalResolution out;
  out.r.assign(n, 0.0f);
  out.eps.assign(n, 0.0f);
  check_cancelled(current_progress());
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
  advance(current_progress(), n);
  if (n > 0) {
    std::vector<float> sorted = out.r;
    std::nth_element(sorted.begin(), sorted.begin() + long(n / 2), sorted.end());
    const float median = sorted[n / 2];
    out.median_r = median > 0.0f && std::isfinite(median) ? median : 0.0f;
  }
  out.sparse_r = sparse_spacing(out.r);
  return out;
}

LocalResolution surface_resolution(const LocalResolution& raw, const Neighborhoods& nb) {
  LocalResolution out = raw;
  const size_t n = raw.r.size();
  const int m = nb.k - 1;  // the first entry is the point itself
  if (m <= 0) return out;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    std::vector<float> around(static_cast<size_t>(m));
    for (size_t i = range.begin(); i < range.end(); ++i) {
      const uint32_t* idx = nb.at(i);
      for (int j = 1; j <= m; ++j) around[size_t(j - 1)] = raw.r[idx[j]];
      std::nth_element(around.begin(), around.begin() + m / 2, around.end());
      const float cap = 2.0f * around[size_t(m / 2)];
      if (cap > 0.0f && raw.r[i] > cap) {
        out.eps[i] = raw.eps[i] * (cap / raw.r[i]);
        out.r[i] = cap;
      }
    }
  });
  advance(current_progress(), n);
  out.sparse_r = sparse_spacing(out.r);  // of the capped r: outliers do not widen it
  return out;
}

float median_plane_deviation(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca) {
  const size_t n = pts.size();
  const int m = nb.k - 1;  // the first entry is the point itself
  if (n < 3 || m <= 0) return 0.0f;
  std::vector<float> deviation(n, 0.0f);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const uint32_t* idx = nb.at(i);
    const glm::vec3 normal = pca.normal[i], p = pts.points[i];
    double s2 = 0.0;
    for (int j = 1; j <= m; ++j) {
      const double along = glm::dot(normal, pts.points[idx[j]] - p);
      s2 += along * along;
    }
    deviation[i] = float(std::sqrt(s2 / m));
  });
  advance(current_progress(), n);
  std::nth_element(deviation.begin(), deviation.begin() + long(n / 2), deviation.end());
  const float median = deviation[n / 2];
  return std::isfinite(median) ? median : 0.0f;
}

float percentile99(std::vector<float> v) {
  if (v.empty()) return 0.0f;
  const size_t at = std::min(v.size() - 1, size_t(double(v.size() - 1) * 0.99));
  std::nth_element(v.begin(), v.begin() + long(at), v.end());
  return v[at];
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

// Divides by the 99th percentile, but never by less than `floor`: a cloud
// without strong features (a plane, whose variations are rounding noise)
// must not have its faintest ones stretched to 1.
void normalise_p99(std::vector<float>& v, float floor) {
  const float scale = std::max(percentile99(v), floor);
  for (float& x : v) x = std::clamp(x / scale, 0.0f, 1.0f);
}

// sRGB (8-bit, display-referred) to CIELAB under D65.
glm::vec3 srgb8_to_lab(uint32_t packed) {
  const auto linear = [](uint32_t v) {
    const double c = double(v & 255) / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  const double r = linear(packed), g = linear(packed >> 8), b = linear(packed >> 16);
  const double x = (0.4124564 * r + 0.3575761 * g + 0.1804375 * b) / 0.95047;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = (0.0193339 * r + 0.1191920 * g + 0.9503041 * b) / 1.08883;
  const auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  const double fx = f(x), fy = f(y), fz = f(z);
  return glm::vec3(float(116.0 * fy - 16.0), float(500.0 * (fx - fy)), float(200.0 * (fy - fz)));
}
}  // namespace

template <int C>
std::vector<float> edge_strength(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca,
                                 const std::vector<std::array<float, C>>& field) {
  const size_t n = pts.size();
  std::vector<float> out(n, 0.0f);
  if (field.size() != n) throw Error("edge_strength: one value per point");
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    if (pca.degenerate[i]) return;
    // Tangent axes: the major axis and the one across it.
    const glm::dvec3 t1(pca.major[i]), t2 = glm::cross(glm::dvec3(pca.normal[i]), t1);
    const glm::dvec3 p0(pts.points[i]);
    double su[2] = {0, 0}, suu[3] = {0, 0, 0}, sf[C] = {}, suf[C][2] = {};
    for (int j = 0; j < nb.k; ++j) {
      const uint32_t o = nb.at(i)[j];
      const glm::dvec3 d = glm::dvec3(pts.points[o]) - p0;
      const double u = glm::dot(d, t1), v = glm::dot(d, t2);
      su[0] += u;
      su[1] += v;
      suu[0] += u * u;
      suu[1] += u * v;
      suu[2] += v * v;
      for (int c = 0; c < C; ++c) {
        // Relative to the point's own value: a uniform field sums to exactly 0.
        const double f = double(field[o][size_t(c)]) - double(field[i][size_t(c)]);
        sf[c] += f;
        suf[c][0] += u * f;
        suf[c][1] += v * f;
      }
    }
    const double k = double(nb.k), mu = su[0] / k, mv = su[1] / k;
    double a00 = suu[0] - k * mu * mu, a01 = suu[1] - k * mu * mv, a11 = suu[2] - k * mv * mv;
    const double trace = a00 + a11;
    if (!(trace > 0.0)) return;
    // A little ridge keeps the fit finite where the neighbours line up.
    a00 += 1e-6 * trace;
    a11 += 1e-6 * trace;
    const double det = a00 * a11 - a01 * a01;
    // Di Zenzo: the structure tensor of the channels' gradients.
    double s00 = 0, s01 = 0, s11 = 0;
    for (int c = 0; c < C; ++c) {
      const double mf = sf[c] / k;
      const double b0 = suf[c][0] - k * mu * mf, b1 = suf[c][1] - k * mv * mf;
      const double g0 = (a11 * b0 - a01 * b1) / det, g1 = (a00 * b1 - a01 * b0) / det;
      s00 += g0 * g0;
      s01 += g0 * g1;
      s11 += g1 * g1;
    }
    const double half = 0.5 * (s00 + s11), diff = 0.5 * (s00 - s11);
    const double largest = half + std::sqrt(diff * diff + s01 * s01);
    out[i] = float(std::sqrt(std::max(0.0, largest)) * std::sqrt(2.0 * trace / k));
  });
  return out;
}
template std::vector<float> edge_strength<1>(const LocalPoints&, const Neighborhoods&, const PcaResult&,
                                             const std::vector<std::array<float, 1>>&);
template std::vector<float> edge_strength<3>(const LocalPoints&, const Neighborhoods&, const PcaResult&,
                                             const std::vector<std::array<float, 3>>&);

std::vector<float> color_edges(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca,
                               const std::vector<uint32_t>& colors) {
  std::vector<std::array<float, 3>> lab(colors.size());
  for (size_t i = 0; i < colors.size(); ++i) {
    const glm::vec3 v = srgb8_to_lab(colors[i]);
    lab[i] = {v.x, v.y, v.z};
  }
  return edge_strength<3>(pts, nb, pca, lab);
}

std::vector<float> intensity_edges(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca,
                                   const std::vector<float>& intensity) {
  // As a lightness: 0 to 100 at the 99th percentile.
  const float top = percentile99(intensity);
  std::vector<std::array<float, 1>> lightness(intensity.size());
  for (size_t i = 0; i < intensity.size(); ++i)
    lightness[i] = {top > 0.0f ? std::min(100.0f, 100.0f * intensity[i] / top) : 0.0f};
  return edge_strength<1>(pts, nb, pca, lightness);
}

std::vector<float> feature_degree(const LocalPoints& pts, const Neighborhoods& nb, const PcaResult& pca,
                                  const std::vector<uint32_t>& colors, const std::vector<float>& intensity,
                                  const FeatureOptions& o) {
  if (!(o.edge_weight >= 0.0f && o.edge_weight <= 1.0f)) throw Error("color_weight must be in [0, 1]");
  if (!(o.contrast > 0.0f) || !std::isfinite(o.contrast)) throw Error("contrast must be > 0");
  check_cancelled(current_progress());
  // A standard deviation of the surface variation of 0.02 is a clear
  // feature (scanner noise on a plane stays below it; leaves and sharp
  // edges reach 0.05 to 0.1).
  constexpr float kClearFeature = 0.02f;
  std::vector<float> g = variation(nb, pca.curvature);
  normalise_p99(g, kClearFeature);
  const bool with_colors = !colors.empty(), with_intensity = !intensity.empty();
  if (o.edge_weight > 0.0f && (with_colors || with_intensity)) {
    std::vector<float> edges(g.size(), 0.0f);
    if (with_colors) edges = color_edges(pts, nb, pca, colors);
    if (with_intensity) {
      const std::vector<float> e = intensity_edges(pts, nb, pca, intensity);
      for (size_t i = 0; i < edges.size(); ++i) edges[i] = std::max(edges[i], e[i]);
    }
    // An edge saturates at `contrast`, or where the scan's colours vary
    // everywhere (a textured cloth, a poster, grass) at kTextureMedians
    // times its own median edge: texture then stays below the feature
    // threshold and its edges above it (five medians is about the top 3 %
    // of an exponential spread of edge strengths).
    constexpr float kTextureMedians = 5.0f;
    std::vector<float> sorted = edges;
    std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 2), sorted.end());
    const float median = sorted.empty() ? 0.0f : sorted[sorted.size() / 2];
    const float saturate = std::max(o.contrast, kTextureMedians * (std::isfinite(median) ? median : 0.0f));
    const float w = o.edge_weight;
    for (size_t i = 0; i < g.size(); ++i) g[i] = (1.0f - w) * g[i] + w * std::min(1.0f, edges[i] / saturate);
  }
  advance(current_progress(), pts.size());
  return g;
}

LineFit line_fit(const LocalPoints& pts, const std::vector<uint8_t>& mask, int k) {
  if (k < 1) throw Error("k must be at least 1");
  const size_t n = pts.size();
  if (!mask.empty() && mask.size() != n) throw Error("mask must have one value per point");
  LineFit out;
  out.direction.assign(n, glm::vec3(0.0f));
  out.error.assign(n, 1.0f);
  out.to_parent.assign(n, glm::vec3(0.0f));
  out.chain_end.assign(n, 0);
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
  // Progress: two passes over the masked points, planned as two over all.
  advance(current_progress(), 2 * (n - sub.size()));
  if (sub.size() == 0) return out;
  const Neighborhoods nb = knn_all(sub, k);
  const PcaResult p = pca(sub, nb);
  for (size_t s = 0; s < sub.size(); ++s) {
    if (p.degenerate[s]) continue;
    out.direction[sub.original[s]] = p.major[s];
    out.error[sub.original[s]] = p.linear_error[s];
  }
  const FeatureChains chains = feature_chains(sub, nb, p);
  for (size_t s = 0; s < sub.size(); ++s) {
    out.to_parent[sub.original[s]] = chains.to_parent[s];
    out.chain_end[sub.original[s]] = chains.end[s];
  }
  return out;
}

std::vector<uint8_t> inlier_mask(const Neighborhoods& nb, float std_ratio) {
  const size_t n = nb.k ? nb.index.size() / size_t(nb.k) : 0;
  std::vector<uint8_t> keep(n, 1);
  check_cancelled(current_progress());
  advance(current_progress(), n);
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
