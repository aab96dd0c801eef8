// Triangle meshes (scene/triangle_mesh.h): validation, precision, normals,
// stable surface sampling.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "scene/point_cloud.h"
#include "scene/triangle_mesh.h"

using namespace pointnpr;

namespace {

// A unit cube [0,1]^3 + offset, outward-facing triangles.
struct Cube {
  std::vector<double> positions;
  std::vector<uint32_t> indices;
  explicit Cube(glm::dvec3 offset = glm::dvec3(0.0)) {
    for (int i = 0; i < 8; ++i)
      positions.insert(positions.end(), {offset.x + (i & 1), offset.y + ((i >> 1) & 1), offset.z + ((i >> 2) & 1)});
    const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) indices.insert(indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  }
  TriangleMeshInput input() const {
    TriangleMeshInput in;
    in.positions = positions;
    in.indices = indices;
    return in;
  }
};

std::string error_of(const TriangleMeshInput& in) {
  try {
    TriangleMesh mesh(in);
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TriangleMesh, RejectsBadInputWithMessagesThatSayWhat) {
  Cube cube;
  TriangleMeshInput in = cube.input();
  std::vector<uint32_t> bad_index = cube.indices;
  bad_index[7] = 8;
  in.indices = bad_index;
  EXPECT_NE(error_of(in).find("triangle 2 uses vertex 8 of 8"), std::string::npos) << error_of(in);
  in = cube.input();
  std::vector<double> nan_pos = cube.positions;
  nan_pos[4] = std::nan("");
  in.positions = nan_pos;
  EXPECT_NE(error_of(in).find("vertex 1 has a non-finite coordinate"), std::string::npos);
  in = cube.input();
  std::vector<uint8_t> colors(7 * 4, 255);
  in.colors = colors;
  EXPECT_NE(error_of(in).find("one row per vertex (8)"), std::string::npos);
  in = cube.input();
  std::vector<uint8_t> texture(5, 0);
  in.texture = texture;
  in.texture_size = {1, 1};
  EXPECT_NE(error_of(in).find("RGBA"), std::string::npos);
  in.texture_size = {kMaxMeshTextureSide + 1, 1};
  EXPECT_NE(error_of(in).find("pixels per side"), std::string::npos);
  in = cube.input();
  std::vector<uint32_t> partial = {0, 1};
  in.indices = partial;
  EXPECT_NE(error_of(in).find("T x 3"), std::string::npos);
  EXPECT_EQ(error_of(cube.input()), "");
}

TEST(TriangleMesh, GeoreferencedMeshesKeepMillimetresAndNormalsPointOutward) {
  const glm::dvec3 offset(637000.123, 5.0e6, 120.5);
  Cube cube(offset);
  TriangleMesh mesh(cube.input());
  for (size_t i = 0; i < mesh.num_vertices(); ++i)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(mesh.origin()[c] + double(mesh.local_positions()[i][c]), cube.positions[3 * i + size_t(c)], 1e-6);
  const std::vector<glm::vec3> normals = mesh.vertex_normals();
  for (size_t i = 0; i < normals.size(); ++i) {
    EXPECT_NEAR(glm::length(normals[i]), 1.0f, 1e-5f);
    // The origin is the cube's centre: corners' normals point away from it.
    EXPECT_GT(glm::dot(normals[i], mesh.local_positions()[i]), 0.8f);
  }
}

TEST(TriangleMesh, SurfaceSamplesAreSeededByTriangleOnTheSurfaceAndAtTheDensity) {
  Cube cube;
  TriangleMesh a(cube.input()), b(cube.input());
  const SurfaceSamples sa = sample_surface(a, 5000.0), sb = sample_surface(b, 5000.0);
  ASSERT_EQ(sa.positions, sb.positions);  // same data, same points: no popping between frames or processes
  ASSERT_EQ(sa.ids, sb.ids);
  const double n = double(sa.ids.size());
  EXPECT_NEAR(n, 30000.0, 4.0 * std::sqrt(30000.0));  // 6 m^2 at 5000 / m^2
  size_t per_face[6] = {0, 0, 0, 0, 0, 0};
  for (size_t i = 0; i < sa.ids.size(); ++i) {
    const double* p = &sa.positions[3 * i];
    // On the surface: one coordinate at 0 or 1, the others inside.
    int on = -1;
    for (int c = 0; c < 3; ++c)
      if (std::abs(p[c]) < 1e-6 || std::abs(p[c] - 1.0) < 1e-6) on = c * 2 + (p[c] > 0.5 ? 1 : 0);
    ASSERT_GE(on, 0) << p[0] << " " << p[1] << " " << p[2];
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(p[c] >= -1e-6 && p[c] <= 1.0 + 1e-6);
    ++per_face[on];
  }
  for (size_t f : per_face) EXPECT_NEAR(double(f), n / 6.0, 4.0 * std::sqrt(n / 6.0));  // uniform in area
  // No colour source: no colours (the point mark's constant colour then).
  EXPECT_TRUE(sa.colors.empty());
  // A denser sampling keeps each triangle's first points: only more are
  // added (a density slider does not reshuffle the marks).
  const SurfaceSamples half = sample_surface(a, 2500.0);
  std::set<std::array<double, 3>> dense;
  for (size_t i = 0; i < sa.ids.size(); ++i) dense.insert({sa.positions[3 * i], sa.positions[3 * i + 1], sa.positions[3 * i + 2]});
  for (size_t i = 0; i < half.ids.size(); ++i)
    ASSERT_TRUE(dense.count({half.positions[3 * i], half.positions[3 * i + 1], half.positions[3 * i + 2]}));
}

TEST(TriangleMesh, SamplingIsCappedNotUnbounded) {
  Cube cube;
  TriangleMesh mesh(cube.input());
  // 6e9 points asked for, 1000 allowed: the cap holds, and says so.
  const SurfaceSamples s = sample_surface(mesh, 1.0e9, 1000);
  EXPECT_TRUE(s.capped);
  EXPECT_LE(s.ids.size(), 1000u);
  EXPECT_GT(s.ids.size(), 900u);
  EXPECT_FALSE(sample_surface(mesh, 100.0, 1000).capped);
}

TEST(TriangleMesh, VertexCloudHasTheVerticesAndTheirNormals) {
  Cube cube;
  TriangleMesh mesh(cube.input());
  const auto cloud = mesh.vertex_cloud();
  EXPECT_EQ(cloud->size(), 8u);
  EXPECT_TRUE(cloud->has(Attribute::Normal));
  EXPECT_EQ(mesh.vertex_cloud().get(), cloud.get());  // made once
}
