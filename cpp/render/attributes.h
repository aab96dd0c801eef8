#pragma once
// The per-point attributes a mark may read, owned here in C++: each mark
// declares the set its current parameters need; the GPU cache computes
// (through the cloud's geometry cache), uploads and keeps exactly those, and
// the host reads from its scene only the *source* attributes of that set.
#include <compare>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace pointnpr {

enum class AttributeKind : uint8_t {
  Color,            // source: packed RGBA8 display sRGB
  Intensity,        // source: float, the cloud's median at middle grey (render/gpu_cloud.h)
  Classification,   // source: uint (ASPRS class)
  AutoColor,        // source: the first of Color, Intensity, Classification the cloud has (uploaded as that one)
  PointId,          // source: the cloud's stable point ids (uint)
  Normal,           // the cloud's own (source), else estimated from k neighbours; snorm8 x3
  Curvature,        // surface variation from k neighbours (lambda0 / sum), float
  LocalResolution,  // mean distance to the k nearest neighbours, float
  FeatureDegree,    // seed 001 feature degree, float in [0, 1]; k packs its neighbours and colour weight,
                    // see feature_degree_key()
  QueueOrder,       // continuous resolution queue (seed 001 section 6.3): per chunk, its points' chunk-local
                    // indices in a stable seeded random order (by a hash of the point id), uint; k = 0
  FeatureLine,      // seed 001 eq. 2 line fit among feature points, uint x3: snorm8 x3 direction + unorm8 error;
                    // the chain link (geometry/feature_chains.h): snorm8 x3 unit direction to the parent + flags
                    // (kFeatureChainLinked | kChainEnd | kChainParentEnd); the link's length, float bits;
                    // k packs both neighbourhoods, the feature threshold and the colour weight, see feature_line_key()
  ResolutionDeviation,  // deviation eps of the distance to the k nearest neighbours (seed 004's r + eps), float
  PrincipalAxis,    // unit eigenvector of the largest eigenvalue of the k-neighbour covariance (seed 004's CM frame); snorm8 x3
  RadiusNormal,     // the cloud's own normals, else least squares within 3r (seed 004; r: 8-neighbour resolution), oriented over k neighbours; snorm8 x3
  ClusterShape,     // seed 004 colour region-growing cluster over k neighbours: uint x4 (snorm8 main axis, elongation float bits, size, label)
  SplatRadius,      // a Gaussian splat's footprint, float, scene units: 2 sqrt of the product of its two largest
                    // scales (its 2-sigma ellipse's mean radius); plain points: the mean distance to their k nearest neighbours
  SplatOpacity,     // a Gaussian splat's opacity in [0, 1], float; plain points: 1; k = 0
};

// FeatureLine's chain flags: the point links to a parent (the low bits:
// geometry::kChainEnd, kChainParentEnd).
constexpr uint32_t kFeatureChainLinked = 4u;

// An attribute and, for computed ones, the neighbourhood size it uses.
struct AttributeKey {
  AttributeKind attribute = AttributeKind::Color;
  int k = 0;  // 0 for source attributes
  auto operator<=>(const AttributeKey&) const = default;
};
using AttributeSet = std::set<AttributeKey>;

// The FeatureDegree key: the degree of `feature_neighbors` neighbours whose
// colour part weighs `color_weight` (geometry::FeatureOptions::edge_weight)
// rounded down to a multiple of 0.05 (at most 21 variants, however it is
// animated); k = feature_neighbors + 100 weight step (neighbours <= 99).
AttributeKey feature_degree_key(int feature_neighbors, double color_weight);
// The FeatureLine key: lines through the `line_neighbors` nearest feature
// points, feature points those whose feature degree (feature_degree_key) is
// >= threshold rounded down to a multiple of 0.05 (at most 21 variants);
// k = line_neighbors + 100 feature_neighbors + 10000 step + 210000 weight
// step (both neighbour counts <= 99).
AttributeKey feature_line_key(int line_neighbors, int feature_neighbors, double threshold, double color_weight);
// What a FeatureDegree key's k (or the part of a FeatureLine key's k past its
// line neighbours, k / 100) holds.
struct FeatureDegreeSpec {
  int neighbors = 8;
  float color_weight = 0.5f;
};
FeatureDegreeSpec feature_degree_spec(const AttributeKey& key);
// What a FeatureLine key's k holds besides its feature degree's.
struct FeatureLineSpec {
  int line_neighbors = 48;
  float threshold = 0.0f;  // feature points: degree >= this (a multiple of 0.05)
  FeatureDegreeSpec degree;
};
FeatureLineSpec feature_line_spec(const AttributeKey& key);

// Name used by the bindings and the add-on ("colors", "normals", ...).
const char* attribute_name(AttributeKind attribute);
// Attributes a host can supply with the points (read from its scene).
bool is_source_attribute(AttributeKind attribute);
// Names of the source attributes in `set`, each once (normals included:
// a host that has them saves the estimation).
std::vector<std::string> source_attribute_names(const AttributeSet& set);
// "normals:16", "colors", ... for messages and tests.
std::string to_string(const AttributeKey& key);

}  // namespace pointnpr
