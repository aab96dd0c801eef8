#include "core/params.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "core/error.h"

namespace pointnpr {

const char* to_string(ParamType type) {
  switch (type) {
    case ParamType::Float: return "float";
    case ParamType::Int: return "int";
    case ParamType::Bool: return "bool";
    case ParamType::Color: return "color";
    case ParamType::Enum: return "enum";
    case ParamType::Path: return "path";
  }
  return "?";
}

ParamSpec float_param(std::string name, double def, double min, double max, std::string unit, std::string doc) {
  return {std::move(name), ParamType::Float, {def}, min, max, std::move(unit), std::move(doc), {}};
}
ParamSpec int_param(std::string name, int def, int min, int max, std::string unit, std::string doc) {
  return {std::move(name), ParamType::Int, {double(def)}, double(min), double(max), std::move(unit), std::move(doc), {}};
}
ParamSpec bool_param(std::string name, bool def, std::string doc) {
  return {std::move(name), ParamType::Bool, {def ? 1.0 : 0.0}, 0.0, 1.0, "", std::move(doc), {}};
}
ParamSpec color_param(std::string name, glm::dvec4 def, std::string doc) {
  return {std::move(name), ParamType::Color, {def.x, def.y, def.z, def.w}, 0.0, 1.0, "", std::move(doc), {}};
}
ParamSpec enum_param(std::string name, std::vector<std::string> items, int def, std::string doc) {
  const double max = double(items.size()) - 1.0;
  return {std::move(name), ParamType::Enum, {double(def)}, 0.0, max, "", std::move(doc), std::move(items)};
}

ParamSpec image_param(std::string name, std::string doc) {
  return {std::move(name), ParamType::Path, {}, 0.0, 0.0, "image", std::move(doc), {}};
}

ParamSpec only_when(ParamSpec spec, std::string param, std::vector<std::string> values) {
  spec.when_param = std::move(param);
  spec.when_values = std::move(values);
  return spec;
}

ParamSpec only_when_any(ParamSpec spec, std::vector<ParamSpec::Condition> conditions) {
  if (conditions.empty()) throw std::invalid_argument("only_when_any: " + spec.name + " has no condition");
  spec = only_when(std::move(spec), conditions.at(0).param, conditions.at(0).values);
  spec.or_when.assign(std::make_move_iterator(conditions.begin() + 1), std::make_move_iterator(conditions.end()));
  return spec;
}

ParamSpec also_when(ParamSpec spec, std::string param, std::vector<std::string> values) {
  if (spec.when_param.empty()) throw std::invalid_argument("also_when: " + spec.name + " has no only_when");
  spec.and_when.push_back({std::move(param), std::move(values)});
  return spec;
}

ParamSpec formerly(ParamSpec spec, std::vector<std::string> names) {
  spec.former_names = std::move(names);
  return spec;
}

ParamSpec added_later(ParamSpec spec, std::vector<double> value) {
  spec.older_files_value = std::move(value);
  return spec;
}

ParamSpec default_changed(ParamSpec spec, std::vector<double> former) {
  spec.older_files_value = std::move(former);
  spec.default_changed = true;
  return spec;
}

ParamSpec items_changed(ParamSpec spec, std::vector<std::string> older_items, std::vector<FormerItem> renamed) {
  spec.older_files_items = std::move(older_items);
  spec.former_items = std::move(renamed);
  return spec;
}

bool answers_to(const Schema& schema, const std::string& id) {
  return schema.id == id || std::find(schema.former_ids.begin(), schema.former_ids.end(), id) != schema.former_ids.end();
}

const ParamSpec* Schema::find(const std::string& name) const {
  for (const auto& p : params)
    if (p.name == name) return &p;
  for (const auto& p : params)
    if (std::find(p.former_names.begin(), p.former_names.end(), name) != p.former_names.end()) return &p;
  return nullptr;
}

namespace {
size_t arity(const ParamSpec& spec) {
  return spec.type == ParamType::Color ? 4 : spec.type == ParamType::Path ? 0 : 1;
}

std::string known_names(const Schema& schema) {
  std::string known;
  for (const auto& p : schema.params) known += (known.empty() ? "" : ", ") + p.name;
  return known;
}

const ParamSpec& declared(const Schema& schema, const std::string& name) {
  const ParamSpec* spec = schema.find(name);
  if (!spec)
    throw ParameterError("'" + schema.id + "' has no parameter '" + name + "' (parameters: " + known_names(schema) +
                         ")");
  return *spec;
}

// `given` keyed by the parameters' current names: a former name is taken
// for its parameter, once (the same value under two names is an error).
template <class Value>
std::map<std::string, Value> by_current_name(const Schema& schema, const std::map<std::string, Value>& given) {
  std::map<std::string, Value> out;
  std::map<std::string, std::string> given_as;
  for (const auto& [name, value] : given) {
    const ParamSpec& spec = declared(schema, name);
    if (given_as.count(spec.name))
      throw ParameterError(schema.id + "." + spec.name + " is given twice (as '" + given_as[spec.name] + "' and '" +
                           name + "')");
    given_as[spec.name] = name;
    out[spec.name] = value;
  }
  return out;
}

std::string range_text(const ParamSpec& spec) {
  std::ostringstream os;
  if (spec.type == ParamType::Enum) {
    os << "one of";
    for (const auto& item : spec.items) os << " '" << item << "'";
  } else if (spec.type == ParamType::Bool) {
    os << "true or false";
  } else {
    os << "[" << spec.min << ", " << spec.max << "]" << (spec.unit.empty() ? "" : " " + spec.unit);
  }
  return os.str();
}
size_t item_index(const ParamSpec& spec, const std::string& item) {
  return size_t(std::find(spec.items.begin(), spec.items.end(), item) - spec.items.begin());
}
}  // namespace

void set_enum_item(const Schema& schema, const ParamSpec& spec, const std::string& item,
                   std::map<std::string, std::vector<double>>& numbers) {
  size_t index = item_index(spec, item);
  if (index == spec.items.size()) {
    for (const FormerItem& former : spec.former_items) {
      if (former.name != item) continue;
      index = item_index(spec, former.now);
      if (!former.also_param.empty()) {
        const ParamSpec* other = schema.find(former.also_param);
        if (other && !numbers.count(other->name))
          numbers[other->name] = {double(item_index(*other, former.also_value))};
      }
      break;
    }
  }
  if (index == spec.items.size())
    throw ParameterError(schema.id + "." + spec.name + " = '" + item + "' is not " + range_text(spec));
  numbers[spec.name] = {double(index)};
}

ParamValues validate(const Schema& schema, const std::map<std::string, std::vector<double>>& given_by_any_name,
                     const std::map<std::string, std::string>& paths_by_any_name) {
  ParamValues out;
  out.schema_ = &schema;
  const auto paths = by_current_name(schema, paths_by_any_name);
  const auto given = by_current_name(schema, given_by_any_name);
  for (const auto& [name, path] : paths) {
    const ParamSpec& spec = declared(schema, name);
    if (spec.type != ParamType::Path)
      throw ParameterError(schema.id + "." + name + " is a " + to_string(spec.type) + ", got a file path");
    std::error_code ec;
    if (!path.empty() && !std::filesystem::is_regular_file(std::filesystem::path(path), ec))
      throw ParameterError(schema.id + "." + name + ": no such file '" + path + "'");
    out.paths_[name] = path;
  }
  for (const auto& [name, values] : given) {
    const ParamSpec* spec = &declared(schema, name);
    if (spec->type == ParamType::Path)
      throw ParameterError(schema.id + "." + name + " expects a file path, got a number");
    if (values.size() != arity(*spec))
      throw ParameterError(schema.id + "." + name + " expects " + std::to_string(arity(*spec)) +
                           " value(s), got " + std::to_string(values.size()));
    for (double v : values) {
      if (!std::isfinite(v))
        throw ParameterError(schema.id + "." + name + " must be finite, got " + std::to_string(v));
      if (v < spec->min || v > spec->max) {
        std::ostringstream os;
        os << schema.id << "." << name << " = " << v << " is outside " << range_text(*spec);
        throw ParameterError(os.str());
      }
      if ((spec->type == ParamType::Int || spec->type == ParamType::Enum || spec->type == ParamType::Bool) &&
          v != std::floor(v))
        throw ParameterError(schema.id + "." + name + " must be a whole number, got " + std::to_string(v));
    }
  }
  for (const auto& spec : schema.params) {
    if (spec.type == ParamType::Path) {
      out.paths_.emplace(spec.name, std::string());  // keeps a given path
      continue;
    }
    if (!out.values_.count(spec.name)) {
      auto it = given.find(spec.name);
      out.values_[spec.name] = it != given.end() ? it->second : spec.default_value;
    }
  }
  return out;
}

const Schema& ParamValues::schema() const {
  if (!schema_) throw ParameterError("parameter values used before validation");
  return *schema_;
}

const ParamSpec& ParamValues::spec_of(const std::string& name, ParamType expected) const {
  const ParamSpec* spec = schema_ ? schema_->find(name) : nullptr;
  if (!spec)
    throw ParameterError("parameter '" + name + "' is not declared in '" + (schema_ ? schema_->id : "?") + "'");
  if (spec->type != expected)
    throw ParameterError("parameter '" + name + "' is a " + to_string(spec->type) + ", read as " + to_string(expected));
  return *spec;
}

const std::vector<double>& ParamValues::at(const std::string& name, ParamType expected) const {
  spec_of(name, expected);
  return values_.at(name);
}

const std::string& ParamValues::get_path(const std::string& name) const {
  spec_of(name, ParamType::Path);
  return paths_.at(name);
}

double ParamValues::get_float(const std::string& name) const { return at(name, ParamType::Float)[0]; }
int ParamValues::get_int(const std::string& name) const { return int(at(name, ParamType::Int)[0]); }
bool ParamValues::get_bool(const std::string& name) const { return at(name, ParamType::Bool)[0] != 0.0; }
int ParamValues::get_enum(const std::string& name) const { return int(at(name, ParamType::Enum)[0]); }
const std::string& ParamValues::get_enum_name(const std::string& name) const {
  return schema_->find(name)->items.at(size_t(get_enum(name)));
}
glm::vec4 ParamValues::get_color(const std::string& name) const {
  const auto& v = at(name, ParamType::Color);
  return {float(v[0]), float(v[1]), float(v[2]), float(v[3])};
}

namespace {

bool holds(const std::string& param, const std::vector<std::string>& wanted, const ParamValues& values) {
  const ParamSpec* other = values.schema().find(param);
  if (!other) return true;
  std::string current;
  switch (other->type) {
    case ParamType::Bool: current = values.get_bool(other->name) ? "true" : "false"; break;
    case ParamType::Float:
    case ParamType::Int: current = values.raw().at(other->name).at(0) != 0.0 ? "nonzero" : "zero"; break;
    default: current = values.get_enum_name(other->name);
  }
  return std::find(wanted.begin(), wanted.end(), current) != wanted.end();
}

}  // namespace

bool applies(const ParamSpec& spec, const ParamValues& values) {
  if (spec.when_param.empty()) return true;
  for (const ParamSpec::Condition& c : spec.and_when)
    if (!holds(c.param, c.values, values)) return false;
  if (holds(spec.when_param, spec.when_values, values)) return true;
  for (const ParamSpec::Condition& c : spec.or_when)
    if (holds(c.param, c.values, values)) return true;
  return false;
}

}  // namespace pointnpr
