#include "scene/triangle_mesh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/hash.h"
#include "scene/point_cloud.h"

namespace pointnpr {

namespace {

std::atomic<uint64_t> g_next_mesh_id{1};

uint32_t pack_rgba(const uint8_t* c, int channels) {
  const uint32_t a = channels == 4 ? c[3] : 255u;
  return uint32_t(c[0]) | (uint32_t(c[1]) << 8) | (uint32_t(c[2]) << 16) | (a << 24);
}

glm::vec4 unpack_rgba(uint32_t c) {
  return glm::vec4(float(c & 255u), float((c >> 8) & 255u), float((c >> 16) & 255u), float(c >> 24)) / 255.0f;
}

float unit_float(uint32_t h) { return float(h >> 8) * (1.0f / 16777216.0f); }  // [0, 1)

constexpr uint32_t kSampleSeed = 0x5a3f1e5u;

}  // namespace

TriangleMesh::TriangleMesh(const TriangleMeshInput& in) : id_(g_next_mesh_id++) {
  if (in.positions.size() % 3 != 0) throw ParameterError("mesh positions must be a V x 3 array");
  if (in.indices.size() % 3 != 0) throw ParameterError("mesh triangles must be a T x 3 array of vertex indices");
  const size_t v = in.positions.size() / 3, corners = in.indices.size();
  if (v > kMaxMeshVertices)
    throw ParameterError("mesh has " + std::to_string(v) + " vertices, more than the limit of " +
                         std::to_string(kMaxMeshVertices));
  if (corners / 3 > kMaxMeshTriangles)
    throw ParameterError("mesh has " + std::to_string(corners / 3) + " triangles, more than the limit of " +
                         std::to_string(kMaxMeshTriangles));
  for (size_t c = 0; c < corners; ++c)
    if (in.indices[c] >= v)
      throw ParameterError("mesh triangle " + std::to_string(c / 3) + " uses vertex " + std::to_string(in.indices[c]) +
                           " of " + std::to_string(v));
  auto domain_size = [&](MeshDomain d) { return d == MeshDomain::Corner ? corners : v; };
  auto domain_name = [](MeshDomain d) { return d == MeshDomain::Corner ? "triangle corner" : "vertex"; };
  if (!in.colors.empty()) {
    if (in.color_channels != 3 && in.color_channels != 4) throw ParameterError("mesh colors must have 3 or 4 channels");
    if (in.colors.size() != domain_size(in.color_domain) * size_t(in.color_channels))
      throw ParameterError(std::string("mesh colors must have one row per ") + domain_name(in.color_domain) + " (" +
                           std::to_string(domain_size(in.color_domain)) + ")");
  }
  if (!in.uvs.empty() && in.uvs.size() != domain_size(in.uv_domain) * 2)
    throw ParameterError(std::string("mesh uvs must have one (u, v) per ") + domain_name(in.uv_domain) + " (" +
                         std::to_string(domain_size(in.uv_domain)) + ")");
  for (float x : in.uvs)
    if (!std::isfinite(x)) throw ParameterError("mesh uvs must be finite");
  if (!in.texture.empty()) {
    const glm::ivec2 s = in.texture_size;
    if (s.x < 1 || s.y < 1 || s.x > kMaxMeshTextureSide || s.y > kMaxMeshTextureSide)
      throw ParameterError("mesh texture must be between 1 and " + std::to_string(kMaxMeshTextureSide) +
                           " pixels per side");
    if (in.texture.size() != size_t(s.x) * size_t(s.y) * 4)
      throw ParameterError("mesh texture must be an H x W x 4 RGBA image");
  }
  for (int c = 0; c < 4; ++c)
    if (!std::isfinite(in.base_color[c])) throw ParameterError("mesh base colour must be finite");

  const double* p = in.positions.data();
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (size_t i = 0; i < v; ++i) {
    const glm::dvec3 q(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
      throw ParameterError("mesh vertex " + std::to_string(i) + " has a non-finite coordinate");
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  if (v == 0) lo = hi = glm::dvec3(0.0);
  // The origin at the centre: float offsets stay small whatever the
  // mesh's georeferenced position.
  origin_ = 0.5 * (lo + hi);
  local_positions_.resize(v);
  for (size_t i = 0; i < v; ++i)
    local_positions_[i] = glm::vec3(glm::dvec3(p[3 * i], p[3 * i + 1], p[3 * i + 2]) - origin_);
  local_min_ = glm::vec3(lo - origin_);
  local_max_ = glm::vec3(hi - origin_);
  indices_.assign(in.indices.begin(), in.indices.end());
  if (!in.colors.empty()) {
    const size_t n = domain_size(in.color_domain);
    colors_.resize(n);
    for (size_t i = 0; i < n; ++i) colors_[i] = pack_rgba(&in.colors[i * size_t(in.color_channels)], in.color_channels);
    color_domain_ = in.color_domain;
  }
  if (!in.uvs.empty()) {
    uvs_.resize(in.uvs.size() / 2);
    for (size_t i = 0; i < uvs_.size(); ++i) uvs_[i] = {in.uvs[2 * i], in.uvs[2 * i + 1]};
    uv_domain_ = in.uv_domain;
  }
  if (!in.texture.empty()) {
    texture_size_ = in.texture_size;
    texture_.resize(size_t(texture_size_.x) * size_t(texture_size_.y));
    for (size_t i = 0; i < texture_.size(); ++i) texture_[i] = pack_rgba(&in.texture[4 * i], 4);
  }
  has_base_color_ = in.has_base_color;
  base_color_ = glm::clamp(in.base_color, 0.0f, 1.0f);
}

std::vector<glm::vec3> TriangleMesh::vertex_normals() const {
  std::vector<glm::vec3> n(local_positions_.size(), glm::vec3(0.0f));
  for (size_t t = 0; t < num_triangles(); ++t) {
    const uint32_t a = indices_[3 * t], b = indices_[3 * t + 1], c = indices_[3 * t + 2];
    // The cross product's length is twice the area: area weighting for free.
    const glm::vec3 f = glm::cross(local_positions_[b] - local_positions_[a], local_positions_[c] - local_positions_[a]);
    n[a] += f;
    n[b] += f;
    n[c] += f;
  }
  for (glm::vec3& x : n) {
    const float len = glm::length(x);
    x = len > 0.0f && std::isfinite(len) ? x / len : glm::vec3(0.0f);
  }
  return n;
}

uint32_t TriangleMesh::texel(glm::vec2 uv) const {
  const glm::vec2 f = uv - glm::floor(uv);
  const int x = std::clamp(int(f.x * float(texture_size_.x)), 0, texture_size_.x - 1);
  const int y = std::clamp(int(f.y * float(texture_size_.y)), 0, texture_size_.y - 1);
  return texture_[size_t(y) * size_t(texture_size_.x) + size_t(x)];
}

SurfaceSamples sample_surface(const TriangleMesh& mesh, double density, size_t max_points) {
  if (!std::isfinite(density) || density < 0.0) throw ParameterError("sample density must be finite and >= 0");
  SurfaceSamples out;
  const size_t t_count = mesh.num_triangles();
  const auto& pos = mesh.local_positions();
  const auto& idx = mesh.indices();
  std::vector<double> area(t_count);
  double total = 0.0;
  for (size_t t = 0; t < t_count; ++t) {
    const glm::dvec3 a(pos[idx[3 * t]]), b(pos[idx[3 * t + 1]]), c(pos[idx[3 * t + 2]]);
    area[t] = 0.5 * glm::length(glm::cross(b - a, c - a));
    total += area[t];
  }
  // The expected count within the cap (one more per triangle at most).
  if (total * density + double(t_count) > double(max_points)) {
    density = std::max(0.0, (double(max_points) - double(t_count)) / std::max(total, 1e-30));
    out.capped = true;
  }
  std::vector<uint32_t> counts(t_count);
  size_t n = 0;
  for (size_t t = 0; t < t_count; ++t) {
    const double u = unit_float(hash_u32(uint32_t(t) ^ kSampleSeed));
    counts[t] = uint32_t(std::floor(area[t] * density + u));
    n += counts[t];
  }
  out.positions.reserve(3 * n);
  out.colors.reserve(4 * n);
  out.normals.reserve(3 * n);
  out.ids.reserve(n);
  const glm::dvec3 origin = mesh.origin();
  // Without any colour source the points take the style's constant colour.
  const bool colored = mesh.has_colors() || mesh.has_texture() || mesh.has_base_color();
  for (size_t t = 0; t < t_count; ++t) {
    if (counts[t] == 0) continue;
    const size_t c0 = 3 * t;
    const glm::vec3 a = pos[idx[c0]], b = pos[idx[c0 + 1]], c = pos[idx[c0 + 2]];
    glm::vec3 normal = glm::cross(b - a, c - a);
    const float len = glm::length(normal);
    normal = len > 0.0f ? normal / len : glm::vec3(0.0f);
    for (uint32_t j = 0; j < counts[t]; ++j) {
      const uint32_t h = hash_u32(uint32_t(t) * 0x9e3779b9u ^ hash_u32(j ^ kSampleSeed));
      float r1 = unit_float(h), r2 = unit_float(hash_u32(h ^ 0x68e31da4u));
      if (r1 + r2 > 1.0f) {  // fold the square onto the triangle: uniform in area
        r1 = 1.0f - r1;
        r2 = 1.0f - r2;
      }
      const float w0 = 1.0f - r1 - r2;
      const glm::dvec3 q = origin + glm::dvec3(a) * double(w0) + glm::dvec3(b) * double(r1) + glm::dvec3(c) * double(r2);
      out.positions.insert(out.positions.end(), {q.x, q.y, q.z});
      glm::vec4 color = mesh.base_color();
      if (mesh.has_colors()) {
        color = unpack_rgba(mesh.corner_color(c0)) * w0 + unpack_rgba(mesh.corner_color(c0 + 1)) * r1 +
                unpack_rgba(mesh.corner_color(c0 + 2)) * r2;
      } else if (mesh.has_texture()) {
        color = unpack_rgba(mesh.texel(mesh.corner_uv(c0) * w0 + mesh.corner_uv(c0 + 1) * r1 +
                                       mesh.corner_uv(c0 + 2) * r2));
      }
      if (colored)
        for (int k = 0; k < 4; ++k) out.colors.push_back(uint8_t(std::lround(std::clamp(color[k], 0.0f, 1.0f) * 255.0f)));
      out.normals.insert(out.normals.end(), {normal.x, normal.y, normal.z});
      out.ids.push_back(uint32_t(out.ids.size()));
    }
  }
  return out;
}

std::shared_ptr<const PointCloud> TriangleMesh::vertex_cloud() const {
  std::lock_guard lock(clouds_mutex_);
  if (!vertex_cloud_) {
    std::vector<double> positions(3 * num_vertices());
    for (size_t i = 0; i < num_vertices(); ++i)
      for (int k = 0; k < 3; ++k) positions[3 * i + size_t(k)] = origin_[k] + double(local_positions_[i][k]);
    std::vector<float> normals;
    if (num_triangles() > 0)
      for (const glm::vec3& n : vertex_normals()) normals.insert(normals.end(), {n.x, n.y, n.z});
    std::vector<uint8_t> colors;
    if (has_colors() && color_domain_ == MeshDomain::Vertex)
      for (uint32_t c : colors_)
        for (int k = 0; k < 4; ++k) colors.push_back(uint8_t(c >> (8 * k)));
    if (has_colors() && color_domain_ == MeshDomain::Corner) {
      // A vertex gets the mean of its corners' colours (white where no
      // triangle uses it).
      std::vector<uint32_t> sums(4 * num_vertices(), 0), counts(num_vertices(), 0);
      for (size_t corner = 0; corner < indices_.size(); ++corner) {
        const size_t v = indices_[corner];
        ++counts[v];
        for (int k = 0; k < 4; ++k) sums[4 * v + size_t(k)] += (colors_[corner] >> (8 * k)) & 0xffu;
      }
      colors.resize(4 * num_vertices(), 255);
      for (size_t v = 0; v < num_vertices(); ++v)
        if (counts[v] > 0)
          for (int k = 0; k < 4; ++k)
            colors[4 * v + size_t(k)] = uint8_t((sums[4 * v + size_t(k)] + counts[v] / 2) / counts[v]);
    }
    PointCloudInput in;
    in.positions = positions;
    in.normals = normals;
    in.colors = colors;
    in.color_channels = 4;
    vertex_cloud_ = std::make_shared<PointCloud>(in);
  }
  return vertex_cloud_;
}

std::shared_ptr<const PointCloud> TriangleMesh::sampled_cloud(double density, bool* capped) const {
  std::lock_guard lock(clouds_mutex_);
  if (!sampled_cloud_ || sampled_density_ != density) {
    const SurfaceSamples s = sample_surface(*this, density);
    PointCloudInput in;
    in.positions = s.positions;
    in.colors = s.colors;
    in.color_channels = 4;
    in.normals = s.normals;
    in.point_index = s.ids;
    sampled_cloud_ = std::make_shared<PointCloud>(in);
    sampled_density_ = density;
    sampled_capped_ = s.capped;
  }
  if (capped) *capped = sampled_capped_;
  return sampled_cloud_;
}

}  // namespace pointnpr
