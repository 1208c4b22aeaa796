// What a table writes of itself (core/option_table.h: describe(), optionSchemaJson(), optionMarkdown())
// on a small struct of every kind of field, against a schema and a section written out by hand.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "mapnav/core/option_table.h"

namespace mapnav {
namespace {

enum class Lens { Pinhole, Fisheye };

struct SchemaToy {
  bool fast = true;
  std::uint8_t level = 3;  // no rule: its type's bounds
  int window = 7;          // odd, [3, 63]
  double rate = 0.25;      // (0, 4]
  double near_m = 1, far_m = 5;
  double limit = std::numeric_limits<double>::infinity();  // no finite default
  std::string label = "a|b";
  Lens lens = Lens::Pinhole;
};

const OptionTable<SchemaToy>& schemaToyTable() {
  using O = SchemaToy;
  static const OptionTable<O> table =
      OptionTable<O>("SchemaToy")
          .field("fast", &O::fast, "the fast path")
          .field("level", &O::level, "a level")
          .field("window", &O::window, oddIn(inRange(3, 63)), "a window side, pixels")
          .field("rate", &O::rate, aboveUpTo(0, 4), "a rate")
          .field("near_m", &O::near_m, atLeast(0), "near, m")
          .field("far_m", &O::far_m, above(0), "far, m")
          .field("limit", &O::limit, "a limit")
          .field("label", &O::label, "a name")
          .choice("lens", &O::lens, {{Lens::Pinhole, "pinhole"}, {Lens::Fisheye, "fisheye"}}, "the model")
          .check("far_m", [](const O& o) { return o.far_m > o.near_m; }, "> near_m")
          .preset("wide", R"({"lens": "fisheye"})", "a wide lens");
  return table;
}

TEST(OptionSchema, DescribeHoldsTheDefaultsAsJsonAndTheRulesBetweenFields) {
  const OptionTableDescription d = schemaToyTable().describe();
  EXPECT_EQ(d.owner, "SchemaToy");
  ASSERT_EQ(d.fields.size(), 9u);
  EXPECT_EQ(d.defaults, (std::vector<std::string>{"true", "3", "7", "0.25", "1", "5", "null", "\"a|b\"", "\"pinhole\""}));
  ASSERT_EQ(d.rules.size(), 1u);
  EXPECT_EQ(d.rules[0], (std::pair<std::string, std::string>{"far_m", "> near_m"}));
  ASSERT_EQ(d.presets.size(), 1u);
}

TEST(OptionSchema, TheSchemaStatesEachFieldsTypeRangeDefaultAndDoc) {
  const auto expected = nlohmann::ordered_json::parse(R"({
    "type": "object", "title": "SchemaToy", "additionalProperties": false, "patternProperties": {"^x-": {}},
    "properties": {
      "preset": {"enum": ["wide"], "description": "A named set of values, applied before the other members: wide: a wide lens"},
      "fast": {"type": "boolean", "default": true, "description": "the fast path"},
      "level": {"type": "integer", "minimum": 0, "maximum": 255, "default": 3, "description": "a level"},
      "window": {"type": "integer", "minimum": 3, "maximum": 63, "not": {"multipleOf": 2}, "default": 7,
                 "description": "a window side, pixels"},
      "rate": {"type": "number", "exclusiveMinimum": 0, "maximum": 4, "default": 0.25, "description": "a rate"},
      "near_m": {"type": "number", "minimum": 0, "default": 1, "description": "near, m"},
      "far_m": {"type": "number", "exclusiveMinimum": 0, "default": 5, "description": "far, m; must be > near_m"},
      "limit": {"type": "number", "description": "a limit"},
      "label": {"type": "string", "default": "a|b", "description": "a name"},
      "lens": {"enum": ["pinhole", "fisheye"], "default": "pinhole", "description": "the model"}
    }})");
  EXPECT_EQ(nlohmann::ordered_json::parse(optionSchemaJson(schemaToyTable().describe())), expected);
}

TEST(OptionSchema, TheMarkdownSectionIsOneRowPerFieldThenTheRulesAndPresets) {
  EXPECT_EQ(optionMarkdown(schemaToyTable().describe()),
            "### SchemaToy\n"
            "\n"
            "| option | default | allowed | meaning |\n"
            "|---|---|---|---|\n"
            "| `fast` | `true` | true or false | the fast path |\n"
            "| `level` | `3` | an integer | a level |\n"
            "| `window` | `7` | an integer in [3, 63], odd | a window side, pixels |\n"
            "| `rate` | `0.25` | in (0, 4] | a rate |\n"
            "| `near_m` | `1` | finite and >= 0 | near, m |\n"
            "| `far_m` | `5` | finite and > 0 | far, m |\n"
            "| `limit` | `null` | finite | a limit |\n"
            "| `label` | `\"a\\|b\"` | a string | a name |\n"
            "| `lens` | `\"pinhole\"` | `\"pinhole\"` or `\"fisheye\"` | the model |\n"
            "\n"
            "Rules between fields:\n"
            "- `far_m` must be > near_m\n"
            "\n"
            "Presets (`\"preset\": \"NAME\"`, applied before the other members):\n"
            "- `wide`: a wide lens: `{\"lens\": \"fisheye\"}`\n");
}

}  // namespace
}  // namespace mapnav
