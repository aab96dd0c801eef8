#include "render/filter.h"

#include <algorithm>
#include <map>

#include "core/error.h"

namespace pointnpr {

Rect Rect::grown(int by, glm::ivec2 limit) const {
  if (empty()) return *this;
  Rect r{glm::max(min - by, glm::ivec2(0)), glm::min(max + by, limit)};
  return r;
}

Rect Rect::united(const Rect& o) const {
  if (empty()) return o;
  if (o.empty()) return *this;
  return {glm::min(min, o.min), glm::max(max, o.max)};
}

namespace {
std::map<std::string, FilterInfo>& registry() {
  static std::map<std::string, FilterInfo> filters;
  return filters;
}
}  // namespace

FilterRegistration::FilterRegistration(FilterInfo info) {
  const std::string id = info.schema.id;
  registry().emplace(id, std::move(info));
}

const std::vector<const FilterInfo*>& registered_filters() {
  static const std::vector<const FilterInfo*> list = [] {
    std::vector<const FilterInfo*> out;
    for (const auto& [id, info] : registry()) out.push_back(&info);
    return out;
  }();
  return list;
}

const FilterInfo& find_filter(const std::string& id) {
  auto it = registry().find(id);
  if (it == registry().end()) {
    std::string known;
    for (const auto& [name, info] : registry()) known += (known.empty() ? "" : ", ") + name;
    throw ParameterError("unknown filter '" + id + "' (filters: " + known + ")");
  }
  return it->second;
}

void dispatch_rect(const gl::Program& program, const Rect& rect) {
  if (rect.empty()) return;
  program.use();
  glUniform2i(program.location("u_rect_min"), rect.min.x, rect.min.y);
  glUniform2i(program.location("u_rect_max"), rect.max.x, rect.max.y);
  const glm::ivec2 s = rect.size();
  glDispatchCompute(GLuint((s.x + 15) / 16), GLuint((s.y + 15) / 16), 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                  GL_SHADER_STORAGE_BARRIER_BIT);
}

}  // namespace pointnpr
