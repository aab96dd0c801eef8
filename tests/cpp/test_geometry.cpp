// Geometry analysis: normals, curvature, resolution, features, outliers on
// shapes with known answers, and every degenerate input the issue lists.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numbers>
#include <random>

#include "core/error.h"
#include "geometry/analysis.h"
#include "scene/point_cloud.h"

using namespace pointnpr;
using namespace pointnpr::geometry;

namespace {

struct Shape {
  std::vector<double> xyz;
  std::vector<glm::dvec3> normal;  // analytic
  void add(glm::dvec3 p, glm::dvec3 n) {
    xyz.insert(xyz.end(), {p.x, p.y, p.z});
    normal.push_back(glm::normalize(n));
  }
  size_t size() const { return normal.size(); }
};

// Noise along the true normal, sigma relative to the sampling step.
Shape plane(int n, double noise, unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  Shape s;
  const glm::dvec3 nrm = glm::normalize(glm::dvec3(0.3, -0.2, 1.0));
  const glm::dvec3 t1 = glm::normalize(glm::cross(nrm, glm::dvec3(1, 0, 0))), t2 = glm::cross(nrm, t1);
  for (int i = 0; i < n; ++i) s.add(u(rng) * t1 + u(rng) * t2 + noise * g(rng) * nrm, nrm);
  return s;
}

Shape sphere(int n, double noise, unsigned seed = 2) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Shape s;
  for (int i = 0; i < n; ++i) {
    const glm::dvec3 d = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    s.add(d * (1.0 + noise * g(rng)), d);
  }
  return s;
}

Shape cylinder(int n, double noise, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, 1.0);
  Shape s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * u(rng);
    const glm::dvec3 d(std::cos(a), std::sin(a), 0.0);
    s.add(d * (1.0 + noise * g(rng)) + glm::dvec3(0, 0, 4 * u(rng) - 2), d);
  }
  return s;
}

// Two faces of a box meeting at a sharp edge along y (x = 0, z = 0).
Shape edge(int n, unsigned seed = 4) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Shape s;
  for (int i = 0; i < n; ++i) {
    if (i % 2) s.add({u(rng), 2 * u(rng) - 1, 0.0}, {0, 0, 1});
    else s.add({0.0, 2 * u(rng) - 1, u(rng)}, {-1, 0, 0});
  }
  return s;
}

double angle_deg(glm::dvec3 a, glm::dvec3 b) {
  return std::acos(std::clamp(std::abs(glm::dot(glm::normalize(a), glm::normalize(b))), 0.0, 1.0)) * 180.0 /
         std::numbers::pi;
}

std::vector<double> errors(const Shape& s, const std::vector<glm::vec3>& n) {
  std::vector<double> e;
  for (size_t i = 0; i < s.size(); ++i) e.push_back(angle_deg(glm::dvec3(n[i]), s.normal[i]));
  return e;
}
double mean(const std::vector<double>& v) {
  double t = 0;
  for (double x : v) t += x;
  return v.empty() ? 0.0 : t / double(v.size());
}
double pct(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[size_t(q * double(v.size() - 1))];
}

std::vector<glm::vec3> normals_of(const std::vector<double>& xyz, int k, Orientation o = Orientation::None,
                                  glm::dvec3 target = {}) {
  Analysis a(xyz);
  return *a.normals({k, o, target});
}

void expect_finite_unit(const std::vector<glm::vec3>& n) {
  for (const auto& v : n) {
    ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
    ASSERT_NEAR(glm::length(v), 1.0f, 1e-5f);
  }
}

}  // namespace

TEST(GeometryNormals, NoisyShapesHaveBoundedAngularError) {
  struct Case {
    const char* name;
    Shape s;
    double mean_deg, p95_deg;
  };
  // 1% noise relative to the shape size; bounds measured with margin.
  Case cases[] = {{"plane", plane(4000, 0.005), 4.0, 8.0},
                  {"sphere", sphere(4000, 0.003), 4.0, 8.0},
                  {"cylinder", cylinder(4000, 0.003), 4.0, 8.0}};
  for (auto& c : cases) {
    const auto n = normals_of(c.s.xyz, 16);
    expect_finite_unit(n);
    const auto e = errors(c.s, n);
    EXPECT_LT(mean(e), c.mean_deg) << c.name;
    EXPECT_LT(pct(e, 0.95), c.p95_deg) << c.name;
    std::printf("%s: mean %.2f deg, p95 %.2f deg\n", c.name, mean(e), pct(e, 0.95));
  }
}

TEST(GeometryNormals, NoiselessPlaneIsExactEvenWhenNearlyFlat) {
  // A 1 km plane sampled every ~3 m with 1 micrometre noise: the covariance
  // is nearly singular (l0/l1 ~ 1e-13), where closed-form 3x3 solvers lose
  // the smallest eigenvector.
  Shape s = plane(20000, 0.0);
  for (double& v : s.xyz) v *= 500.0;
  std::mt19937 rng(9);
  std::normal_distribution<double> g(0.0, 1e-6);
  for (double& v : s.xyz) v += g(rng);
  const auto e = errors(s, normals_of(s.xyz, 12));
  EXPECT_LT(pct(e, 1.0), 0.01);
}

TEST(GeometryNormals, NearlyIsotropicNeighbourhoodsGiveUnitNormals) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> xyz;
  for (int i = 0; i < 3000; ++i) xyz.insert(xyz.end(), {u(rng), u(rng), u(rng)});
  Analysis a(xyz);
  expect_finite_unit(*a.normals({16, Orientation::None, {}}));
  for (float c : *a.curvature(16)) {
    EXPECT_GT(c, 0.02f);  // a volume: all three eigenvalues comparable
    EXPECT_LE(c, 1.0f / 3.0f + 1e-5f);
  }
}

TEST(GeometryNormals, SharpEdgeFacesAwayFromTheEdgeAreExact) {
  const Shape s = edge(6000);
  const auto n = normals_of(s.xyz, 12);
  std::vector<double> far;
  for (size_t i = 0; i < s.size(); ++i) {
    const double x = s.xyz[3 * i], z = s.xyz[3 * i + 2];
    if (std::max(x, z) > 0.15) far.push_back(angle_deg(glm::dvec3(n[i]), s.normal[i]));
  }
  EXPECT_LT(pct(far, 1.0), 1e-3);
}

TEST(GeometryNormals, OrientationTowardAPointAlongADirectionAndConsistent) {
  const Shape s = sphere(3000, 0.0);
  for (const auto& n : {normals_of(s.xyz, 12, Orientation::TowardPoint, glm::dvec3(0.0)),
                        normals_of(s.xyz, 12, Orientation::Consistent)}) {
    int inward = 0, outward = 0;
    for (size_t i = 0; i < s.size(); ++i) (glm::dot(glm::dvec3(n[i]), s.normal[i]) > 0 ? outward : inward)++;
    EXPECT_TRUE(inward == 0 || outward == 0) << inward << " inward, " << outward << " outward";
  }
  // Toward the centre: all inward. Consistent: the top points up, so outward.
  auto n = normals_of(s.xyz, 12, Orientation::TowardPoint, glm::dvec3(0.0));
  EXPECT_LT(glm::dot(glm::dvec3(n[0]), s.normal[0]), 0.0);
  n = normals_of(s.xyz, 12, Orientation::Consistent);
  EXPECT_GT(glm::dot(glm::dvec3(n[0]), s.normal[0]), 0.0);
  n = normals_of(plane(500, 0.001).xyz, 8, Orientation::Direction, glm::dvec3(0, 0, -1));
  for (const auto& v : n) EXPECT_LE(v.z, 0.0f);
}

TEST(GeometryNormals, TowardPointWorksForGeoreferencedScanners) {
  Shape s = plane(2000, 0.001);
  for (size_t i = 0; i < s.size(); ++i) {
    s.xyz[3 * i] += 650000.0;
    s.xyz[3 * i + 1] += 6860000.0;
  }
  const auto n = normals_of(s.xyz, 10, Orientation::TowardPoint, glm::dvec3(650000.0, 6860000.0, -50.0));
  for (const auto& v : n) EXPECT_LT(glm::dot(glm::dvec3(v), s.normal[0]), 0.0);
}

TEST(GeometryHardCases, DuplicatedPointsGiveTheSameNormals) {
  const Shape s = sphere(1500, 0.0);
  std::vector<double> twice(s.xyz);
  twice.insert(twice.end(), s.xyz.begin(), s.xyz.end());
  // With every point doubled, 2k neighbours cover the same k distinct points.
  const auto n1 = normals_of(s.xyz, 8);
  const auto n2 = normals_of(twice, 16);
  expect_finite_unit(n2);
  for (size_t i = 0; i < s.size(); ++i) {
    EXPECT_LT(angle_deg(glm::dvec3(n1[i]), glm::dvec3(n2[i])), 1e-2);
    EXPECT_LT(angle_deg(glm::dvec3(n2[i]), glm::dvec3(n2[i + s.size()])), 1e-3);
  }
  Analysis a(twice);
  const auto& r = *a.local_resolution(1);  // the nearest other point is the duplicate
  for (float v : r.r) EXPECT_EQ(v, 0.0f);
}

TEST(GeometryHardCases, AllPointsIdentical) {
  std::vector<double> xyz;
  for (int i = 0; i < 50; ++i) xyz.insert(xyz.end(), {3.0, -2.0, 1e6});
  Analysis a(xyz);
  for (const auto& v : *a.normals({16, Orientation::Consistent, {}})) EXPECT_EQ(v, glm::vec3(0, 0, 1));
  for (float c : *a.curvature(16)) EXPECT_EQ(c, 0.0f);
  const auto& r = *a.local_resolution(8);
  for (size_t i = 0; i < 50; ++i) {
    EXPECT_EQ(r.r[i], 0.0f);
    EXPECT_EQ(r.eps[i], 0.0f);
  }
  for (float f : *a.feature_degree(8, {0.5f})) EXPECT_EQ(f, 0.0f);
  for (uint8_t keep : a.inliers(8, 2.0f)) EXPECT_EQ(keep, 1);
  const LineFit lf = a.line_fit({}, 8);
  for (size_t i = 0; i < 50; ++i) {
    EXPECT_EQ(lf.direction[i], glm::vec3(0.0f));
    EXPECT_EQ(lf.error[i], 1.0f);
  }
  const Components cc = a.connected_components(8, 1);
  EXPECT_EQ(cc.count, 1);
  for (int32_t l : cc.labels) EXPECT_EQ(l, 0);
}

TEST(GeometryHardCases, CollinearPoints) {
  std::vector<double> xyz;
  const glm::dvec3 dir = glm::normalize(glm::dvec3(1, 2, 3));
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 p = dir * (0.01 * i);
    xyz.insert(xyz.end(), {p.x, p.y, p.z});
  }
  Analysis a(xyz);
  for (const auto& v : *a.normals({10, Orientation::Consistent, {}})) {
    EXPECT_NEAR(glm::length(v), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(glm::dvec3(v), dir), 0.0, 1e-4);  // perpendicular to the line
  }
  for (float c : *a.curvature(10)) EXPECT_NEAR(c, 0.0f, 1e-6f);
  const LineFit lf = a.line_fit({}, 6);
  for (size_t i = 0; i < 200; ++i) {
    EXPECT_NEAR(std::abs(glm::dot(glm::dvec3(lf.direction[i]), dir)), 1.0, 1e-5);
    EXPECT_NEAR(lf.error[i], 0.0f, 1e-6f);
  }
}

TEST(GeometryHardCases, FewerPointsThanKAndSinglePointAndEmpty) {
  const Shape s = plane(5, 0.0);
  Analysis a(s.xyz);
  EXPECT_EQ(a.knn(16)->k, 5);  // k larger than the cloud: every point sees all
  const auto e = errors(s, *a.normals({16, Orientation::None, {}}));
  EXPECT_LT(pct(e, 1.0), 1e-3);
  EXPECT_EQ(a.local_resolution(100)->r.size(), 5u);

  Analysis one(std::vector<double>{1e6, 2e6, 3.0});
  EXPECT_EQ((*one.normals({16, Orientation::Consistent, {}}))[0], glm::vec3(0, 0, 1));
  EXPECT_EQ((*one.local_resolution(8)).r[0], 0.0f);
  EXPECT_EQ(one.inliers(8, 1.0f)[0], 1);
  EXPECT_EQ(one.connected_components(10, 1).labels[0], 0);

  Analysis none(std::vector<double>{});
  EXPECT_TRUE(none.normals({16, Orientation::Consistent, {}})->empty());
  EXPECT_TRUE(none.curvature(8)->empty());
  EXPECT_TRUE(none.connected_components(8, 1).labels.empty());
  EXPECT_THROW(none.knn(0), Error);
}

TEST(GeometryHardCases, OffsetByAMillionMetresChangesNothing) {
  const Shape s = sphere(3000, 0.003);
  std::vector<double> far(s.xyz);
  for (size_t i = 0; i < s.size(); ++i) {
    far[3 * i] += 1e6;
    far[3 * i + 1] += 1e6;
    far[3 * i + 2] += 1e6;
  }
  Analysis a(s.xyz), b(far);
  const auto& na = *a.normals({16, Orientation::Consistent, {}});
  const auto& nb = *b.normals({16, Orientation::Consistent, {}});
  const auto& ra = *a.local_resolution(8);
  const auto& rb = *b.local_resolution(8);
  const auto& ca = *a.curvature(16);
  const auto& cb = *b.curvature(16);
  for (size_t i = 0; i < s.size(); ++i) {
    EXPECT_GT(glm::dot(na[i], nb[i]), 0.99999f);
    EXPECT_NEAR(ra.r[i], rb.r[i], 1e-6f);
    EXPECT_NEAR(ca[i], cb[i], 1e-5f);
  }
  EXPECT_EQ(a.connected_components(6, 5).labels, b.connected_components(6, 5).labels);
}

TEST(GeometryFeatures, LocalResolutionOfAGrid) {
  std::vector<double> xyz;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) xyz.insert(xyz.end(), {0.5 * i, 0.5 * j, 7.0});
  Analysis a(xyz);
  const auto& r = *a.local_resolution(4);
  const size_t interior = 15 * 30 + 15;
  EXPECT_NEAR(r.r[interior], 0.5f, 1e-6f);
  EXPECT_NEAR(r.eps[interior], 0.0f, 1e-6f);
}

TEST(GeometryFeatures, FeatureDegreeIsHighAtTheEdgeAndLowOnTheFaces) {
  const Shape s = edge(8000);
  Analysis a(s.xyz);
  const auto& f = *a.feature_degree(16, {0.0f});
  double near_sum = 0, far_sum = 0;
  int near_n = 0, far_n = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    EXPECT_GE(f[i], 0.0f);
    EXPECT_LE(f[i], 1.0f);
    const double d = std::max(s.xyz[3 * i], s.xyz[3 * i + 2]);
    if (d < 0.03) near_sum += f[i], ++near_n;
    if (d > 0.3) far_sum += f[i], ++far_n;
  }
  EXPECT_GT(near_sum / near_n, 0.3);
  EXPECT_LT(far_sum / far_n, 0.02);
}

TEST(GeometryFeatures, ColourEdgesRaiseTheFeatureDegreeOnAFlatPlane) {
  const Shape s = plane(4000, 0.0);
  std::vector<uint32_t> colors(s.size());
  for (size_t i = 0; i < s.size(); ++i) colors[i] = s.xyz[3 * i] < 0.0 ? 0xff000000u : 0xffffffffu;
  Analysis a(s.xyz, colors);
  const auto& f = *a.feature_degree(12, {1.0f});
  double border = 0, inside = 0;
  int nb = 0, ni = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const double x = s.xyz[3 * i];
    if (std::abs(x) < 0.01) border += f[i], ++nb;
    if (std::abs(x) > 0.3) inside += f[i], ++ni;
  }
  EXPECT_GT(border / nb, 0.5);
  EXPECT_EQ(inside, 0.0);
}

namespace {
// A jittered grid on a tilted plane (spacing 0.02), its points' tangent x.
struct TiltedGrid {
  std::vector<double> xyz;
  std::vector<double> u;  // coordinate across the future edge
};
TiltedGrid tilted_grid(int side, unsigned seed = 8) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.004, 0.004);
  const glm::dvec3 t1 = glm::normalize(glm::dvec3(1, 0, 0.5)), t2 = glm::normalize(glm::dvec3(0, 1, -0.3));
  TiltedGrid g;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j) {
      const double a = 0.02 * (i - side / 2) + jitter(rng), b = 0.02 * (j - side / 2) + jitter(rng);
      const glm::dvec3 p = a * t1 + b * t2 + glm::dvec3(100.0, -50.0, 20.0);
      g.xyz.insert(g.xyz.end(), {p.x, p.y, p.z});
      g.u.push_back(a);
    }
  return g;
}
uint32_t rgb(int r, int g, int b) { return uint32_t(r) | uint32_t(g) << 8 | uint32_t(b) << 16 | 0xff000000u; }
}  // namespace

TEST(GeometryFeatures, EdgeDetectorMeasuresTheStepAcrossTheNeighbourhood) {
  // A lightness step of 40 across a line: a disc straddling a step of D
  // fits a slope of 8D/(3 pi R), times its RMS extent R: 0.85 D.
  const TiltedGrid g = tilted_grid(60);
  std::vector<float> intensity;
  for (double a : g.u) intensity.push_back(a < 0.0 ? 30.0f : 70.0f);
  Analysis a(g.xyz, {}, intensity);
  const LocalPoints& lp = a.points();
  const std::vector<float> sorted = lp.to_sorted(std::span<const float>(intensity));
  // Intensities 30 and 70 of a 99th percentile of 70: lightness 42.9 and 100.
  const std::vector<float> e = lp.to_original(intensity_edges(lp, *a.knn(24), *a.pca(24), sorted));
  std::vector<double> at_edge;
  for (size_t i = 0; i < g.u.size(); ++i) {
    if (std::abs(g.u[i]) < 0.004) at_edge.push_back(e[i]);
    if (std::abs(g.u[i]) > 0.15) {
      EXPECT_EQ(e[i], 0.0f);
    }
  }
  const double step = 100.0 - 100.0 * 30.0 / 70.0;
  EXPECT_NEAR(pct(at_edge, 0.5) / step, 8.0 / (3.0 * std::numbers::pi), 0.12);
}

TEST(GeometryFeatures, ColourEdgesAreColourNotJustLuminance) {
  // Red against green of the same CIE lightness (L* 53.2 and 53.6): a
  // luminance edge detector sees nothing; the CIELAB one sees a Delta E of
  // about 170, far beyond the default contrast.
  const TiltedGrid g = tilted_grid(50);
  std::vector<uint32_t> colors;
  for (double a : g.u) colors.push_back(a < 0.0 ? rgb(255, 0, 0) : rgb(0, 165, 0));
  Analysis a(g.xyz, colors);
  const auto& f = *a.feature_degree(16, {1.0f});
  double border = 0, inside = 0;
  int nb = 0;
  for (size_t i = 0; i < g.u.size(); ++i) {
    if (std::abs(g.u[i]) < 0.005) border += f[i], ++nb;
    if (std::abs(g.u[i]) > 0.15) inside = std::max(inside, double(f[i]));
  }
  EXPECT_GT(border / nb, 0.95);
  EXPECT_EQ(inside, 0.0);
  // A faint edge (Delta E about 5) stays faint; contrast sets the scale.
  std::vector<uint32_t> faint;
  for (double u : g.u) faint.push_back(u < 0.0 ? rgb(120, 120, 120) : rgb(132, 132, 132));
  Analysis b(g.xyz, faint);
  double faint_border = 0, sharp_border = 0;
  const auto& f25 = *b.feature_degree(16, {1.0f, 25.0f});
  const auto& f5 = *b.feature_degree(16, {1.0f, 5.0f});
  for (size_t i = 0; i < g.u.size(); ++i)
    if (std::abs(g.u[i]) < 0.005) faint_border += f25[i], sharp_border += f5[i];
  EXPECT_LT(faint_border / nb, 0.3);
  EXPECT_GT(sharp_border / nb, 0.6);
}

TEST(GeometryFeatures, IntensityEdgesWhereThereAreNoColours) {
  const TiltedGrid g = tilted_grid(50);
  std::vector<float> intensity;
  for (double u : g.u) intensity.push_back(u < 0.0 ? 400.0f : 2400.0f);
  Analysis a(g.xyz, {}, intensity);
  const auto& f = *a.feature_degree(16, {0.5f});
  double border = 0;
  int nb = 0;
  for (size_t i = 0; i < g.u.size(); ++i) {
    if (std::abs(g.u[i]) < 0.005) border += f[i], ++nb;
    if (std::abs(g.u[i]) > 0.15) {
      EXPECT_LT(f[i], 0.26f);  // the flat plane: the geometric half only
    }
  }
  EXPECT_GT(border / nb, 0.45);
  EXPECT_THROW(a.feature_degree(16, {0.5f, 0.0f}), Error);
  EXPECT_THROW(a.feature_degree(16, {1.5f}), Error);
}

TEST(GeometryFeatures, LineFitSeparatesDirectionalFromScatteredFeaturePoints) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> xyz;
  std::vector<uint8_t> mask;
  for (int i = 0; i < 300; ++i) {  // a noisy line (feature points)...
    xyz.insert(xyz.end(), {0.01 * i, 0.001 * u(rng), 0.001 * u(rng)});
    mask.push_back(1);
  }
  for (int i = 0; i < 300; ++i) {  // ...a scattered blob (feature points)...
    xyz.insert(xyz.end(), {10 + u(rng), u(rng), u(rng)});
    mask.push_back(1);
  }
  for (int i = 0; i < 100; ++i) {  // ...and non-feature points on the line.
    xyz.insert(xyz.end(), {0.01 * i + 0.005, 0.0, 0.0});
    mask.push_back(0);
  }
  Analysis a(xyz);
  const LineFit lf = a.line_fit(mask, 8);
  for (int i = 10; i < 290; ++i) {
    EXPECT_LT(lf.error[size_t(i)], 0.05f);
    EXPECT_GT(std::abs(lf.direction[size_t(i)].x), 0.99f);
  }
  int scattered = 0;
  for (int i = 300; i < 600; ++i) scattered += lf.error[size_t(i)] > 0.1f;
  EXPECT_GT(scattered, 250);
  for (int i = 600; i < 700; ++i) EXPECT_EQ(lf.error[size_t(i)], 1.0f);
}

TEST(GeometryFeatures, StatisticalOutlierRemovalDropsIsolatedPoints) {
  Shape s = plane(3000, 0.0);
  s.add({5, 5, 5}, {0, 0, 1});
  s.add({-4, 3, 8}, {0, 0, 1});
  Analysis a(s.xyz);
  const auto keep = a.inliers(10, 2.0f);
  EXPECT_EQ(keep[3000], 0);
  EXPECT_EQ(keep[3001], 0);
  size_t kept = 0;
  for (uint8_t k : keep) kept += k;
  EXPECT_GT(kept, 2900u);
}

TEST(GeometryCache, ACloudComputesNothingUntilAskedThenOnce) {
  const Shape s = sphere(2000, 0.0);
  PointCloudInput in;
  in.positions = s.xyz;
  PointCloud cloud(in, 512);
  EXPECT_TRUE(cloud.analysis().computed().empty());
  const auto n1 = cloud.analysis().normals({12, Orientation::Consistent, {}});
  const auto n2 = cloud.analysis().normals({12, Orientation::Consistent, {}});
  EXPECT_EQ(n1.get(), n2.get());  // cached, not recomputed
  const auto names = cloud.analysis().computed();
  EXPECT_NE(std::find(names.begin(), names.end(), "normals:12:consistent"), names.end());
  // A smaller k is served from the cached neighbourhoods.
  EXPECT_EQ(cloud.analysis().knn(5)->k, 5);
  EXPECT_EQ(cloud.analysis().knn(5)->index[0], cloud.analysis().knn(12)->index[0]);
  // Results follow the cloud's internal order.
  const auto pos = cloud.positions_double();
  for (size_t i = 0; i < cloud.size(); ++i) {
    const glm::dvec3 p(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    EXPECT_GT(glm::dot(glm::dvec3((*n1)[i]), glm::normalize(p)), 0.99);
  }
}

// Marks size themselves from surface_resolution: a stray point far off a
// surface gets the size of its neighbourhood, not of the gap around it;
// the surface's own points keep their spacing.
TEST(Analysis, SurfaceResolutionCapsAStrayPointAtItsNeighbours) {
  std::vector<double> xyz;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 30; ++x) xyz.insert(xyz.end(), {x * 0.1, y * 0.1, 0.0});
  xyz.insert(xyz.end(), {1.5, 1.5, 5.0});  // 5 units above a 0.1 grid
  Analysis a(xyz);
  const auto& raw = *a.local_resolution(8);
  const auto& surface = *a.surface_resolution(8);
  const size_t stray = 900;
  EXPECT_GT(raw.r[stray], 4.9f);
  EXPECT_LE(surface.r[stray], 2.0f * 0.15f);  // twice its grid neighbours' (0.1 to 0.14)
  EXPECT_NEAR(surface.eps[stray] / surface.r[stray], raw.eps[stray] / raw.r[stray], 1e-5f);
  for (size_t i = 0; i < stray; ++i) {
    EXPECT_EQ(surface.r[i], raw.r[i]) << i;
    EXPECT_EQ(surface.eps[i], raw.eps[i]) << i;
  }
  EXPECT_EQ(surface.median_r, raw.median_r);
}

// The scan's depth noise (what the brush's depth tolerance reaches at
// least): on a plane with Gaussian noise of sigma along its normal, the
// median RMS of a point's neighbours off its plane is about sigma (the
// plane's fit takes a little up); on a clean plane, nothing.
TEST(Analysis, PlaneDeviationMeasuresTheScansDepthNoise) {
  const double sigma = 0.01;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> noisy, clean;
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      noisy.insert(noisy.end(), {x * 0.1, y * 0.1, noise(rng)});
      clean.insert(clean.end(), {x * 0.1, y * 0.1, 0.0});
    }
  Analysis a(noisy), b(clean);
  EXPECT_NEAR(a.plane_deviation(16), sigma, 0.2 * sigma);
  EXPECT_LT(b.plane_deviation(16), 1e-6f);
}
