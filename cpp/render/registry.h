#pragma once
// One registry for every kind of plugin (marks, filters): each plugin's .cpp
// adds its Info (a Schema plus a factory) from a static initialiser, and the
// core looks it up by id within its kind.
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"

namespace pointnpr {

// Info must have `Schema schema` and `static constexpr const char* kKind`.
template <class Info>
class Registry {
 public:
  static Registry& instance() {
    static Registry registry;
    return registry;
  }

  void add(Info info) {
    info.schema.kind = Info::kKind;
    const std::string id = info.schema.id;
    entries_.emplace(id, std::move(info));
  }

  // Sorted by id. Built on first use (after every static registration ran).
  const std::vector<const Info*>& all() const {
    static const std::vector<const Info*> list = [this] {
      std::vector<const Info*> out;
      for (const auto& [id, info] : entries_) out.push_back(&info);
      return out;
    }();
    return list;
  }

  // By id, or by a former id (Schema::former_ids).
  const Info& find(const std::string& id) const {
    auto it = entries_.find(id);
    if (it == entries_.end())
      it = std::find_if(entries_.begin(), entries_.end(), [&](const auto& entry) {
        const auto& former = entry.second.schema.former_ids;
        return std::find(former.begin(), former.end(), id) != former.end();
      });
    if (it == entries_.end()) {
      std::string known;
      for (const auto& [name, info] : entries_) known += (known.empty() ? "" : ", ") + name;
      throw ParameterError("unknown " + std::string(Info::kKind) + " '" + id + "' (" + Info::kKind + "s: " + known +
                           ")");
    }
    return it->second;
  }

 private:
  std::map<std::string, Info> entries_;
};

// Used by each plugin's .cpp: `const Registration<FilterInfo> reg{{schema, factory}};`
template <class Info>
struct Registration {
  explicit Registration(Info info) { Registry<Info>::instance().add(std::move(info)); }
};

}  // namespace pointnpr
