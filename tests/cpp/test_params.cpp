#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "render/filter.h"
#include "render/style.h"

using namespace pointnpr;

TEST(Params, DefaultsFillEveryParameter) {
  const ParamValues v = validate(rasterize_schema(), {});
  EXPECT_DOUBLE_EQ(v.get_float("point_size"), 2.0);
  EXPECT_EQ(v.get_enum_name("color_source"), "rgb");
  EXPECT_EQ(v.raw().size(), rasterize_schema().params.size());
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

TEST(Params, RejectsNaNInfinityAndOutOfRange) {
  EXPECT_THROW(validate(inpaint_schema(), {{"threshold", {std::nan("")}}}), ParameterError);
  EXPECT_THROW(validate(inpaint_schema(), {{"threshold", {std::numeric_limits<double>::infinity()}}}),
               ParameterError);
  EXPECT_THROW(validate(inpaint_schema(), {{"radius", {0}}}), ParameterError);
  EXPECT_THROW(validate(inpaint_schema(), {{"radius", {65}}}), ParameterError);
  EXPECT_THROW(validate(inpaint_schema(), {{"radius", {2.5}}}), ParameterError);  // ints are whole
  EXPECT_THROW(validate(rasterize_schema(), {{"color_source", {4}}}), ParameterError);
  EXPECT_THROW(validate(rasterize_schema(), {{"color", {1, 0, 0}}}), ParameterError);  // RGBA expected
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
