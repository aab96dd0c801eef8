#include <gtest/gtest.h>
#include <algorithm>

#include <cmath>
#include <limits>
#include <set>

#include "core/error.h"
#include "render/filter.h"
#include "render/mark.h"
#include "render/style.h"

using namespace pointnpr;

TEST(Params, DefaultsFillEveryParameter) {
  const ParamValues v = validate(find_mark("points").schema, {});
  EXPECT_DOUBLE_EQ(v.get_float("point_size"), 2.0);
  EXPECT_EQ(v.get_enum_name("color_source"), "auto");
  EXPECT_EQ(v.raw().size(), find_mark("points").schema.params.size());
}

TEST(Params, GivenValuesOverrideDefaults) {
  const ParamValues v = validate(inpaint_schema(), {{"radius", {7}}, {"threshold", {0.5}}});
  EXPECT_EQ(v.get_int("radius"), 7);
  EXPECT_DOUBLE_EQ(v.get_float("threshold"), 0.5);
}

TEST(Params, RejectsUnknownNameListingKnownOnes) {
  try {
    validate(inpaint_schema(), {{"radious", {3}}});
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("radious"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("radius"), std::string::npos);
  }
}

TEST(Params, AFormerNameIsReadAsTheCurrentOneAndNoNameIsTaken) {
  const Schema schema{"renamed", "Renamed", "", {formerly(int_param("count", 1, 0, 9, "", ""), {"number", "n"})}};
  EXPECT_EQ(validate(schema, {{"n", {4}}}).get_int("count"), 4);
  EXPECT_EQ(validate(schema, {{"number", {5}}}).raw().count("number"), 0u);
  EXPECT_THROW(validate(schema, {{"count", {4}}, {"number", {5}}}), ParameterError);  // given twice
  EXPECT_THROW(validate(schema, {{"number", {10}}}), ParameterError);                  // still checked
  // No two parameters of a schema share a name or former name.
  std::vector<const Schema*> all;
  for (const MarkInfo* m : registered_marks()) all.push_back(&m->schema);
  for (const FilterInfo* f : registered_filters()) all.push_back(&f->schema);
  ASSERT_GT(all.size(), 10u);
  for (const Schema* s : all) {
    std::set<std::string> names;
    for (const auto& p : s->params) {
      EXPECT_TRUE(names.insert(p.name).second) << s->id << "." << p.name;
      for (const auto& former : p.former_names) EXPECT_TRUE(names.insert(former).second) << s->id << "." << former;
    }
  }
}

TEST(Params, RejectsNaNInfinityAndOutOfRange) {
  EXPECT_THROW(validate(inpaint_schema(), {{"threshold", {std::nan("")}}}), ParameterError);
  EXPECT_THROW(validate(inpaint_schema(), {{"threshold", {std::numeric_limits<double>::infinity()}}}),
               ParameterError);
  EXPECT_THROW(validate(inpaint_schema(), {{"radius", {0}}}), ParameterError);
  EXPECT_THROW(validate(inpaint_schema(), {{"radius", {65}}}), ParameterError);
  EXPECT_THROW(validate(inpaint_schema(), {{"radius", {2.5}}}), ParameterError);  // ints are whole
  EXPECT_THROW(validate(find_mark("points").schema, {{"color_source", {5}}}), ParameterError);
  EXPECT_THROW(validate(find_mark("points").schema, {{"color", {1, 0, 0}}}), ParameterError);  // RGBA expected
}

TEST(Params, ReadingWithTheWrongTypeFails) {
  const ParamValues v = validate(inpaint_schema(), {});
  EXPECT_THROW(v.get_float("radius"), ParameterError);
  EXPECT_THROW(v.get_int("nope"), ParameterError);
}

TEST(Params, EveryFilterSchemaIsWellFormed) {
  ASSERT_GE(registered_filters().size(), 2u);
  for (const FilterInfo* f : registered_filters()) {
    EXPECT_FALSE(f->schema.doc.empty()) << f->schema.id;
    for (const ParamSpec& p : f->schema.params) {
      EXPECT_FALSE(p.doc.empty()) << f->schema.id << "." << p.name;
      EXPECT_LE(p.min, p.max) << f->schema.id << "." << p.name;
      // The default must itself validate (a path's default is none, "").
      if (p.type == ParamType::Path)
        EXPECT_NO_THROW(validate(f->schema, {}, {{p.name, ""}})) << f->schema.id << "." << p.name;
      else
        EXPECT_NO_THROW(validate(f->schema, {{p.name, p.default_value}})) << f->schema.id << "." << p.name;
    }
  }
  EXPECT_THROW(find_filter("no_such_filter"), ParameterError);
}

TEST(Params, AFormerEnumValueIsReadAsItsCurrentItemAndMaySetAnother) {
  const Schema& points = find_mark("points").schema;
  const ParamSpec& rasterizer = *points.find("rasterizer");
  std::map<std::string, std::vector<double>> given;
  set_enum_item(points, rasterizer, "gl_points", given);
  ParamValues v = validate(points, given);
  EXPECT_EQ(v.get_enum_name("rasterizer"), "gl");
  EXPECT_EQ(v.get_enum_name("gl_method"), "gl_points");
  // A method given too is kept.
  given = {{"gl_method", {0}}};
  set_enum_item(points, rasterizer, "gl_points", given);
  EXPECT_EQ(validate(points, given).get_enum_name("gl_method"), "compute");
  given.clear();
  set_enum_item(points, rasterizer, "native", given);
  EXPECT_EQ(validate(points, given).get_enum_name("rasterizer"), "native");
  EXPECT_THROW(set_enum_item(points, rasterizer, "opengl", given), ParameterError);
  // Every mark with two backends takes the same values, and every former
  // value and the items older files stored name items that exist.
  std::vector<const Schema*> all;
  for (const MarkInfo* m : registered_marks()) all.push_back(&m->schema);
  for (const FilterInfo* f : registered_filters()) all.push_back(&f->schema);
  for (const Schema* s : all) {
    if (const ParamSpec* r = s->find("rasterizer"); r && s->kind == "mark") {
      EXPECT_EQ(r->items, (std::vector<std::string>{"gl", "native", "auto"})) << s->id;
    }
    for (const ParamSpec& p : s->params) {
      auto has = [](const std::vector<std::string>& items, const std::string& item) {
        return std::find(items.begin(), items.end(), item) != items.end();
      };
      for (const FormerItem& f : p.former_items) {
        EXPECT_TRUE(has(p.items, f.now)) << s->id << "." << p.name << " " << f.name;
        EXPECT_FALSE(has(p.items, f.name)) << s->id << "." << p.name << " " << f.name;
        if (f.also_param.empty()) continue;
        const ParamSpec* other = s->find(f.also_param);
        ASSERT_NE(other, nullptr) << s->id << "." << f.also_param;
        EXPECT_TRUE(has(other->items, f.also_value)) << s->id << "." << f.also_param;
      }
      for (const std::string& older : p.older_files_items)
        EXPECT_TRUE(has(p.items, older) || std::any_of(p.former_items.begin(), p.former_items.end(),
                                                       [&](const FormerItem& f) { return f.name == older; }))
            << s->id << "." << p.name << " " << older;
    }
  }
}

TEST(Params, MarksAndFiltersAreLookedUpByKindAndByAFormerId) {
  EXPECT_EQ(find_mark("hatching").schema.kind, "mark");
  // The pencil hatching filter was "hatching" too: that id still finds it.
  EXPECT_EQ(find_filter("pencil_hatching").schema.kind, "filter");
  EXPECT_EQ(&find_filter("hatching"), &find_filter("pencil_hatching"));
  EXPECT_TRUE(answers_to(find_filter("pencil_hatching").schema, "hatching"));
  EXPECT_FALSE(answers_to(find_mark("hatching").schema, "pencil_hatching"));
  // No current id is another's former id within a kind.
  std::set<std::string> filter_ids;
  for (const FilterInfo* f : registered_filters()) filter_ids.insert(f->schema.id);
  for (const FilterInfo* f : registered_filters())
    for (const auto& former : f->schema.former_ids) EXPECT_EQ(filter_ids.count(former), 0u) << former;
  EXPECT_EQ(find_mark("points").schema.kind, "mark");
  EXPECT_EQ(inpaint_schema().kind, "stage");
  try {
    find_mark("cartoon");  // a filter, not a mark
    FAIL() << "no mark named cartoon";
  } catch (const ParameterError& e) {
    // Names the marks there are (others may be registered too).
    const std::string what = e.what();
    EXPECT_NE(what.find("unknown mark 'cartoon' (marks: "), std::string::npos) << what;
    EXPECT_NE(what.find("hatching"), std::string::npos) << what;
    EXPECT_NE(what.find("points"), std::string::npos) << what;
  }
}

TEST(Params, EveryConditionNamesAnEnumBoolOrNumberOfItsSchemaAndOneOfItsValues) {
  std::vector<const Schema*> all = {&inpaint_schema(), &composite_schema()};
  for (const MarkInfo* m : registered_marks()) all.push_back(&m->schema);
  for (const FilterInfo* f : registered_filters()) all.push_back(&f->schema);
  int conditions = 0;
  for (const Schema* schema : all) {
    for (const ParamSpec& p : schema->params) {
      if (p.when_param.empty()) {
        EXPECT_TRUE(p.or_when.empty()) << schema->id << "." << p.name << ": alternatives without a condition";
        EXPECT_TRUE(p.and_when.empty()) << schema->id << "." << p.name << ": requirements without a condition";
        continue;
      }
      std::vector<ParamSpec::Condition> each = {{p.when_param, p.when_values}};
      each.insert(each.end(), p.or_when.begin(), p.or_when.end());
      each.insert(each.end(), p.and_when.begin(), p.and_when.end());
      for (const ParamSpec::Condition& c : each) {
        ++conditions;
        const ParamSpec* other = schema->find(c.param);
        ASSERT_NE(other, nullptr) << schema->id << "." << p.name << " depends on unknown " << c.param;
        const bool number = other->type == ParamType::Float || other->type == ParamType::Int;
        ASSERT_TRUE(other->type == ParamType::Enum || other->type == ParamType::Bool || number)
            << schema->id << "." << p.name;
        ASSERT_FALSE(c.values.empty());
        for (const std::string& v : c.values) {
          const std::vector<std::string> allowed = other->type == ParamType::Bool ? std::vector<std::string>{"true", "false"}
                                                   : number ? std::vector<std::string>{"zero", "nonzero"}
                                                            : other->items;
          EXPECT_NE(std::find(allowed.begin(), allowed.end(), v), allowed.end())
              << schema->id << "." << p.name << ": " << v << " is not a value of " << other->name;
        }
      }
    }
  }
  EXPECT_GE(conditions, 6);
}

TEST(Params, ConditionsFollowTheCurrentValues) {
  const Schema& points = find_mark("points").schema;
  const ParamValues pixels = validate(points, {});
  const ParamValues world = validate(points, {{"size_mode", {1}}});
  EXPECT_TRUE(applies(*points.find("point_size"), pixels));
  EXPECT_FALSE(applies(*points.find("world_size"), pixels));
  EXPECT_FALSE(applies(*points.find("point_size"), world));
  EXPECT_TRUE(applies(*points.find("world_size"), world));
  EXPECT_TRUE(applies(*points.find("color_source"), world));  // unconditional
  // A condition on a number: the watercolor's paper shows only through a dry brush.
  const Schema& watercolor = find_filter("watercolor").schema;
  EXPECT_FALSE(applies(*watercolor.find("paper_color"), validate(watercolor, {{"dry_brush", {0.0}}})));
  EXPECT_TRUE(applies(*watercolor.find("paper_color"), validate(watercolor, {{"dry_brush", {0.2}}})));
  // A condition that must hold as well: the stipples' specular share scales
  // the share rule's lit points, so it acts with a specular light and only
  // under that rule.
  const Schema& stipples = find_mark("stipples").schema;
  const ParamSpec& share = *stipples.find("specular_share");
  EXPECT_FALSE(applies(share, validate(stipples, {})));  // no specular light
  EXPECT_TRUE(applies(share, validate(stipples, {{"specular", {1.0}}})));
  EXPECT_FALSE(applies(share, validate(stipples, {{"specular", {1.0}}, {"lit_rule", {1.0}}})));  // nearest
  // Any of several conditions: the brush's second layer is painted with two
  // layers or on small clusters.
  const Schema& brush = find_mark("brush_splats").schema;
  const ParamSpec& tint = *brush.find("layer_tint");
  EXPECT_FALSE(applies(tint, validate(brush, {})));
  EXPECT_TRUE(applies(tint, validate(brush, {{"layers", {1.0}}})));
  EXPECT_TRUE(applies(tint, validate(brush, {{"clusters", {1.0}}})));
}
