#pragma once
// Parameters are declared once, here in C++, as a schema: name, type,
// default, range, unit and a one-line doc. Validation, the Python bindings,
// the Blender UI and docs/parameters.md are all generated from it.
#include <glm/vec4.hpp>
#include <map>
#include <string>
#include <vector>

namespace pointnpr {

// Path: a file (an image) given as a string; "" means none. Its value is
// kept apart from the numbers (ParamValues::get_path).
enum class ParamType { Float, Int, Bool, Color, Enum, Path };

// An enum value that older scripts and files used and that is spelt
// otherwise now, e.g. the gaussians' rasterizer "compute", now "gl" as on
// every mark; or one folded into two parameters: the points' rasterizer
// "gl_points", now rasterizer "gl" with gl_method "gl_points".
struct FormerItem {
  std::string name;        // the value as older scripts gave it
  std::string now;         // the item of this parameter it means now
  std::string also_param;  // "" or another enum parameter it sets too
  std::string also_value;  // that parameter's item
};

const char* to_string(ParamType type);

struct ParamSpec {
  std::string name;                  // snake_case identifier
  ParamType type = ParamType::Float;
  std::vector<double> default_value; // 1 value, 4 for Color (RGBA, display sRGB), none for Path
  double min = 0.0;                  // inclusive range (Float, Int; Color components)
  double max = 1.0;
  std::string unit;                  // "px", "m", "s", "Hz", "deg", "" ...
  std::string doc;                   // one line, shown as tooltip and in docs
  std::vector<std::string> items;    // Enum identifiers; the value is the index
  // Applies only while enum (or bool: "true"/"false"; or number: "zero"/
  // "nonzero", e.g. a strength whose 0 is off) parameter `when_param` has
  // one of `when_values`; the UI greys it out otherwise.
  std::string when_param;
  std::vector<std::string> when_values;
  // Further conditions, any of which also makes it apply (a line width
  // applies when any class of strokes is drawn as lines).
  struct Condition {
    std::string param;
    std::vector<std::string> values;
  };
  std::vector<Condition> or_when;
  // Conditions that must hold as well, whichever of the above does (the
  // stipples' specular_share acts only on the share rule's lit points).
  std::vector<Condition> and_when;
  // Names it had before, which scripts and saved files may still use:
  // validation takes them for this one, and the Blender add-on moves a
  // saved value (and its animation) to the current name when a file opens.
  std::vector<std::string> former_names;
  // For a parameter added after files were saved without it, or whose
  // default changed since: the value that renders those files as before
  // (empty: the default does). The Blender add-on gives it to nodes made
  // before the parameter existed, or before its default changed, that
  // store no value of their own.
  std::vector<double> older_files_value;
  bool default_changed = false;  // (older_files_value is the former default)
  // Values it took before (see FormerItem): scripts may still give them.
  std::vector<FormerItem> former_items;
  // The items, in their order, of files saved before they changed (empty:
  // unchanged). Blender stores an enum's index, so the add-on reads a
  // saved index through these (and former_items) when such a file opens.
  std::vector<std::string> older_files_items;
};

// `spec`, applying only while `param` is one of `values` (see ParamSpec).
ParamSpec only_when(ParamSpec spec, std::string param, std::vector<std::string> values);
// `spec`, applying only while any of `conditions` holds (the first is its
// `when`, the others its `or_when`).
ParamSpec only_when_any(ParamSpec spec, std::vector<ParamSpec::Condition> conditions);
// `spec`, applying only while `param` is one of `values` too (on top of
// its only_when; see ParamSpec::and_when).
ParamSpec also_when(ParamSpec spec, std::string param, std::vector<std::string> values);
// `spec`, once named `names` (see ParamSpec::former_names).
ParamSpec formerly(ParamSpec spec, std::vector<std::string> names);
// `spec`, added after files were saved without it; they keep `value` (an
// enum's index; see ParamSpec::older_files_value).
ParamSpec added_later(ParamSpec spec, std::vector<double> value);
// `spec`, whose default was `former` when files that keep it were saved
// (see ParamSpec::older_files_value).
ParamSpec default_changed(ParamSpec spec, std::vector<double> former);

// `spec`, whose items were `older_items` (their order: older files stored
// indices into it), with `renamed` the values that are spelt otherwise now
// (see FormerItem, ParamSpec::older_files_items). Same-named items keep
// their meaning.
ParamSpec items_changed(ParamSpec spec, std::vector<std::string> older_items, std::vector<FormerItem> renamed);

// Builders keep declarations short and uniform in each filter's file.
ParamSpec float_param(std::string name, double def, double min, double max, std::string unit, std::string doc);
ParamSpec int_param(std::string name, int def, int min, int max, std::string unit, std::string doc);
ParamSpec bool_param(std::string name, bool def, std::string doc);
ParamSpec color_param(std::string name, glm::dvec4 def, std::string doc);
ParamSpec enum_param(std::string name, std::vector<std::string> items, int def, std::string doc);
// An image file read through OpenImageIO; the default is none ("").
ParamSpec image_param(std::string name, std::string doc);

// A named, documented set of parameters: a pipeline stage or a filter.
struct Schema {
  std::string id;      // e.g. "cartoon"
  std::string label;   // e.g. "Cartoon"
  std::string doc;
  std::vector<ParamSpec> params;
  // Ids it had before (a filter renamed so that no mark shares its id):
  // styles and saved files that name it so still find it.
  std::vector<std::string> former_ids;
  // "mark", "filter" or "stage"; set by the registry a schema is added to,
  // so a mark and a filter may share an id.
  std::string kind = "stage";

  // The parameter of that name or former name, or null.
  const ParamSpec* find(const std::string& name) const;
};

// Whether `id` is the schema's id or one of its former ids.
bool answers_to(const Schema& schema, const std::string& id);

// Sets `numbers[spec.name]` to the index of enum item `item`, current or
// former; a former item folded into two parameters sets the other one too
// unless `numbers` has it. An unknown item raises ParameterError naming the
// items.
void set_enum_item(const Schema& schema, const ParamSpec& spec, const std::string& item,
                   std::map<std::string, std::vector<double>>& numbers);

// Whether `spec` applies to `values`: any of its conditions holds (not
// chained through the parameters they name; the add-on's param_applies is).
class ParamValues;
bool applies(const ParamSpec& spec, const ParamValues& values);

// Validated values for one schema. Built only through validate(), so every
// value present is known, finite and in range.
class ParamValues {
 public:
  ParamValues() = default;
  double get_float(const std::string& name) const;
  int get_int(const std::string& name) const;
  bool get_bool(const std::string& name) const;
  glm::vec4 get_color(const std::string& name) const;
  int get_enum(const std::string& name) const;
  const std::string& get_enum_name(const std::string& name) const;
  const std::string& get_path(const std::string& name) const;  // "" = none
  // Numbers of every parameter but the paths, and the paths.
  const std::map<std::string, std::vector<double>>& raw() const { return values_; }
  const std::map<std::string, std::string>& raw_paths() const { return paths_; }
  const Schema& schema() const;

 private:
  friend ParamValues validate(const Schema& schema, const std::map<std::string, std::vector<double>>& given,
                              const std::map<std::string, std::string>& paths);
  const ParamSpec& spec_of(const std::string& name, ParamType expected) const;
  const std::vector<double>& at(const std::string& name, ParamType expected) const;
  const Schema* schema_ = nullptr;
  std::map<std::string, std::vector<double>> values_;
  std::map<std::string, std::string> paths_;
};

// Fills in defaults and checks every given value: unknown names, wrong
// arity, NaN/inf and values outside [min, max] raise ParameterError naming
// the schema, the parameter and the allowed range. Paths must name an
// existing regular file (or be "" for none); a number given for a path, or a
// path for a number, is an error too.
ParamValues validate(const Schema& schema, const std::map<std::string, std::vector<double>>& given,
                     const std::map<std::string, std::string>& paths = {});

}  // namespace pointnpr
