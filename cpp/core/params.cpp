#include "core/params.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace pointnpr {

const char* to_string(ParamType type) {
  switch (type) {
    case ParamType::Float: return "float";
    case ParamType::Int: return "int";
    case ParamType::Bool: return "bool";
    case ParamType::Color: return "color";
    case ParamType::Enum: return "enum";
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

const ParamSpec* Schema::find(const std::string& name) const {
  for (const auto& p : params)
    if (p.name == name) return &p;
  return nullptr;
}

namespace {
size_t arity(const ParamSpec& spec) { return spec.type == ParamType::Color ? 4 : 1; }

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
}  // namespace

ParamValues validate(const Schema& schema, const std::map<std::string, std::vector<double>>& given) {
  ParamValues out;
  out.schema_ = &schema;
  for (const auto& [name, values] : given) {
    const ParamSpec* spec = schema.find(name);
    if (!spec) {
      std::string known;
      for (const auto& p : schema.params) known += (known.empty() ? "" : ", ") + p.name;
      throw ParameterError("'" + schema.id + "' has no parameter '" + name + "' (parameters: " + known + ")");
    }
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

const std::vector<double>& ParamValues::at(const std::string& name, ParamType expected) const {
  auto it = values_.find(name);
  const ParamSpec* spec = schema_ ? schema_->find(name) : nullptr;
  if (it == values_.end() || !spec)
    throw ParameterError("parameter '" + name + "' is not declared in '" + (schema_ ? schema_->id : "?") + "'");
  if (spec->type != expected)
    throw ParameterError("parameter '" + name + "' is a " + to_string(spec->type) + ", read as " + to_string(expected));
  return it->second;
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

}  // namespace pointnpr
