// The option table (core/option_table.h) on a small struct of every kind of field: the listing is
// the struct's defaults, parsing errors name the option and its value, validate() words its rules
// "OWNER::FIELD = VALUE: must be RULE", presets apply before the other members, and every field round-trips.
#include "mapnav/core/option_table.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "mapnav/core/error.h"

namespace mapnav {
namespace {

enum class Shape { Line, Arc };

struct BaseToy {
  double sigma = 0.5;  // > 0
};

struct Toy : BaseToy {
  bool fast = true;
  int count = 5;               // [1, 30]
  std::uint64_t seed = 1;      // [0, 1e15]
  double rate = 0.3;           // (0, 4]
  double tolerance = 1e-6;
  double third = 1.0 / 3.0;    // needs 17 digits
  std::string label = "road";
  Shape shape = Shape::Line;
  int window = 7;              // odd, [3, 63]
  int steps = 10;              // any int
};

const OptionTable<BaseToy>& baseTable() {
  static const OptionTable<BaseToy> table =
      OptionTable<BaseToy>("BaseToy").field("sigma", &BaseToy::sigma, above(0), "a sigma");
  return table;
}

const OptionTable<Toy>& toyTable() {
  static const OptionTable<Toy> table =
      OptionTable<Toy>("Toy")
          .field("fast", &Toy::fast, "the fast path")
          .field("count", &Toy::count, inRange(1, 30), "how many")
          .field("seed", &Toy::seed, inRange(0, 1e15), "the seed")
          .field("rate", &Toy::rate, aboveUpTo(0, 4), "a rate")
          .field("tolerance", &Toy::tolerance, atLeast(0), "a tolerance")
          .field("third", &Toy::third, "a third")
          .field("label", &Toy::label, "a name")
          .choice("shape", &Toy::shape, {{Shape::Line, "line"}, {Shape::Arc, "arc"}}, "the model")
          .computed(
              "curved", [](const Toy& t) { return t.shape == Shape::Arc; },
              [](Toy& t, bool curved) { t.shape = curved ? Shape::Arc : Shape::Line; }, "the arc model")
          .field("window", &Toy::window, oddIn(inRange(3, 63)), "a window side")
          .field("steps", &Toy::steps, "steps")
          .include(baseTable())
          .preset("wide", R"({"count": 8, "curved": true, "label": "park"})", "more and curved");
  return table;
}

/// The InvalidInput message of parsing `json`, or "" when it parses.
std::string parseError(const std::string& json) {
  try {
    toyTable().parse(json, Toy{}, "toy");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

std::string validateError(const Toy& toy) {
  try {
    toyTable().validate(toy);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(OptionTable, ListingShowsTheDefaultConstructedStruct) {
  const std::vector<OptionInfo> list = toyTable().list();
  ASSERT_EQ(list.size(), 12u);
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"fast", "true"},   {"count", "5"},    {"seed", "1"},        {"rate", "0.3"},
      {"tolerance", "1e-06"}, {"third", "0.33333333333333331"}, {"label", "\"road\""}, {"shape", "\"line\""},
      {"curved", "false"}, {"window", "7"},  {"steps", "10"},      {"sigma", "0.5"}};
  for (std::size_t i = 0; i < list.size(); ++i) {
    EXPECT_EQ(list[i].name, expected[i].first);
    EXPECT_EQ(list[i].default_json, expected[i].second) << list[i].name;
    EXPECT_FALSE(list[i].description.empty()) << list[i].name;
  }
}

TEST(OptionTable, DefaultsValidate) { EXPECT_NO_THROW(toyTable().validate(Toy{})); }

TEST(OptionTable, ParseSetsTheMembersGivenAndKeepsTheRest) {
  Toy base;
  base.steps = 3;
  const Toy t = toyTable().parse(
      R"({"fast": false, "count": 30, "seed": 1e15, "rate": 4, "label": "x", "shape": "arc", "window": 63, "sigma": 2})",
      base, "toy");
  EXPECT_FALSE(t.fast);
  EXPECT_EQ(t.count, 30);
  EXPECT_EQ(t.seed, 1000000000000000u);
  EXPECT_EQ(t.rate, 4.0);
  EXPECT_EQ(t.label, "x");
  EXPECT_EQ(t.shape, Shape::Arc);
  EXPECT_EQ(t.window, 63);
  EXPECT_EQ(t.sigma, 2.0);
  EXPECT_EQ(t.steps, 3);  // from the base
  EXPECT_EQ(toyTable().parse("", base, "toy").steps, 3);
  EXPECT_EQ(toyTable().parse(R"({"count": 7.0})", base, "toy").count, 7);  // an integer written as a float
}

TEST(OptionTable, ParseErrorsNameTheOptionAndItsValue) {
  EXPECT_EQ(parseError(R"({"nope": 1})"), "toy: unknown option \"nope\"");
  EXPECT_EQ(parseError(R"({"fast": 1})"), "toy: option fast = 1: must be true or false");
  EXPECT_EQ(parseError(R"({"count": "5"})"), "toy: option count = \"5\": must be a number");
  EXPECT_EQ(parseError(R"({"count": 31})"), "toy: option count = 31: must be in [1, 30]");
  EXPECT_EQ(parseError(R"({"count": 2.5})"), "toy: option count = 2.5: must be an integer");
  EXPECT_EQ(parseError(R"({"steps": 1e10})"), "toy: option steps = 10000000000.0: must be an integer in [-2147483648, 2147483647]");
  EXPECT_EQ(parseError(R"({"seed": 1e16})"), "toy: option seed = 1e+16: must be in [0, 1e+15]");
  EXPECT_EQ(parseError(R"({"rate": 0})"), "toy: option rate = 0: must be in (0, 4]");
  EXPECT_EQ(parseError(R"({"tolerance": -1})"), "toy: option tolerance = -1: must be >= 0");
  EXPECT_EQ(parseError(R"({"sigma": 0})"), "toy: option sigma = 0: must be > 0");
  EXPECT_EQ(parseError(R"({"window": 8})"), "toy: option window = 8: must be odd");
  EXPECT_EQ(parseError(R"({"label": 3})"), "toy: option label = 3: must be a string");
  EXPECT_EQ(parseError(R"({"shape": "circle"})"), "toy: option shape = \"circle\": must be \"line\" or \"arc\"");
  EXPECT_EQ(parseError("[1]"), "toy: options must be a JSON object");
  EXPECT_EQ(parseError("{").rfind("toy: options are not JSON: ", 0), 0u);
}

TEST(OptionTable, AFailedParseLeavesTheBaseAsItWas) {
  Toy base;
  base.count = 9;
  EXPECT_THROW(toyTable().parse(R"({"count": 3, "window": 8})", base, "toy"), InvalidInput);
  EXPECT_EQ(base.count, 9);
}

TEST(OptionTable, ValidateNamesTheOwnerTheFieldTheValueAndTheRule) {
  Toy t;
  t.count = 0;
  EXPECT_EQ(validateError(t), "Toy::count = 0: must be in [1, 30]");
  t = Toy{};
  t.sigma = std::numeric_limits<double>::infinity();
  EXPECT_EQ(validateError(t), "Toy::sigma = inf: must be finite and > 0");
  t = Toy{};
  t.third = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(validateError(t), "Toy::third = nan: must be finite");
  t = Toy{};
  t.window = 4;
  EXPECT_EQ(validateError(t), "Toy::window = 4: must be odd");
  t = Toy{};
  t.rate = 5;
  EXPECT_EQ(validateError(t), "Toy::rate = 5: must be in (0, 4]");
}

TEST(OptionTable, APresetAppliesBeforeTheOtherMembers) {
  const Toy wide = toyTable().parse(R"({"preset": "wide"})", Toy{}, "toy");
  EXPECT_EQ(wide.count, 8);
  EXPECT_EQ(wide.shape, Shape::Arc);
  EXPECT_EQ(wide.label, "park");
  const Toy overridden = toyTable().parse(R"({"count": 12, "preset": "wide", "curved": false})", Toy{}, "toy");
  EXPECT_EQ(overridden.count, 12);
  EXPECT_EQ(overridden.shape, Shape::Line);
  EXPECT_EQ(overridden.label, "park");
  ASSERT_EQ(toyTable().presets().size(), 1u);
  EXPECT_EQ(toyTable().presets()[0].name, "wide");
  EXPECT_EQ(toyTable().presets()[0].description, "more and curved");
}

TEST(OptionTable, AnUnknownPresetListsThePresets) {
  EXPECT_EQ(parseError(R"({"preset": "narrow"})"), "toy: unknown preset \"narrow\" (presets: wide)");
  EXPECT_EQ(parseError(R"({"preset": 1})"), "toy: option preset = 1: must be a string (presets: wide)");
  try {
    baseTable().parse(R"({"preset": "wide"})", BaseToy{}, "base");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "base: unknown preset \"wide\" (there are none)");
  }
}

/// Two bounds with a rule between them, and a struct that holds them through a base's table.
struct Band {
  double low = 1;   // >= 0
  double high = 2;  // > low
  bool open = false;
};

const OptionTable<Band>& bandTable() {
  static const OptionTable<Band> table = OptionTable<Band>("Band")
                                             .field("low", &Band::low, atLeast(0), "the lower bound")
                                             .field("high", &Band::high, "the upper bound")
                                             .field("open", &Band::open, "whether the ends are open")
                                             .check("high", [](const Band& b) { return b.high > b.low; }, "> low");
  return table;
}

struct WideBand : Band {
  int count = 3;  // [1, 9]
};

const OptionTable<WideBand>& wideBandTable() {
  static const OptionTable<WideBand> table =
      OptionTable<WideBand>("WideBand").field("count", &WideBand::count, inRange(1, 9), "how many").include(bandTable());
  return table;
}

TEST(OptionTable, ARuleBetweenFieldsIsJudgedAfterTheFieldsOwnRules) {
  EXPECT_NO_THROW(bandTable().validate(Band{}));
  Band b;
  b.high = 0.5;
  try {
    bandTable().validate(b);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "Band::high = 0.5: must be > low");
  }
  b.low = -1;  // breaks its own rule too: that one is named first
  ASSERT_TRUE(bandTable().brokenRule(b));
  EXPECT_EQ(bandTable().brokenRule(b)->second, "Band::low = -1: must be finite and >= 0");
  EXPECT_EQ(bandTable().brokenRule(b)->first, 0u);
}

TEST(OptionTable, AnIncludedTableBringsItsRulesBetweenFields) {
  WideBand w;
  w.low = 4;
  ASSERT_TRUE(wideBandTable().brokenRule(w));
  EXPECT_EQ(wideBandTable().brokenRule(w)->second, "WideBand::high = 2: must be > low");
  EXPECT_EQ(wideBandTable().fields()[wideBandTable().brokenRule(w)->first].name, "high");
}


/// A pipeline's options that hold a component's (Band) instead of copying its fields.
struct Holder {
  int count = 3;
  Band band;
};

const OptionTable<Holder>& holderTable() {
  static const OptionTable<Holder> table = OptionTable<Holder>("Holder")
                                               .field("count", &Holder::count, inRange(1, 9), "how many")
                                               .nest(&Holder::band, bandTable(), {{"high", "band_high"}}, {"open"});
  return table;
}

TEST(OptionTable, ANestedTableReachesTheComponentUnderFlatNames) {
  std::vector<std::string> names;
  for (const auto& f : holderTable().fields()) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"count", "low", "band_high"}));  // "open" omitted, "high" renamed
  const Holder h = holderTable().parse(R"({"low": 0.5, "band_high": 7})", Holder{}, "holder");
  EXPECT_EQ(h.band.low, 0.5);
  EXPECT_EQ(h.band.high, 7);
  EXPECT_FALSE(h.band.open);
  EXPECT_EQ(holderTable().list()[2].default_json, "2");  // the component's default, read from it
  EXPECT_EQ(holderTable().json(Holder{}), R"({"count": 3, "low": 1, "band_high": 2})");
  Holder bad;
  bad.band.low = 5;  // the component's rule between fields, under the name it has here
  ASSERT_TRUE(holderTable().brokenRule(bad));
  EXPECT_EQ(holderTable().brokenRule(bad)->second, "Holder::band_high = 2: must be > low");
}

TEST(OptionTable, ARuleOnAFieldTheTableDoesNotHaveOrTwoFieldsOfOneNameAreProgrammingErrors) {
  EXPECT_THROW(OptionTable<Band>("Band").check("width", [](const Band&) { return true; }, "> 0"), std::logic_error);
  EXPECT_THROW(OptionTable<Holder>("Holder").field("low", &Holder::count, "how many").nest(&Holder::band, bandTable()),
               std::logic_error);
}

TEST(OptionTable, ReadReportsEveryBadMemberAtItsPointerAndAppliesTheRest) {
  Issues issues;
  const WideBand w =
      wideBandTable().read(R"({"low": "x", "high": 5, "count": 12, "widht": 1, "open": true})", WideBand{}, "/band", issues);
  ASSERT_EQ(issues.size(), 3u);  // in the file's order
  EXPECT_EQ(issues[0], (Issue{Severity::Error, "schema.type", "/band/low", "option low = \"x\": must be a number"}));
  EXPECT_EQ(issues[1], (Issue{Severity::Error, "schema.range", "/band/count", "option count = 12: must be in [1, 9]"}));
  EXPECT_EQ(issues[2], (Issue{Severity::Error, "schema.unknown_field", "/band/widht", "unknown option \"widht\""}));
  EXPECT_EQ(w.high, 5);  // the good members are applied
  EXPECT_TRUE(w.open);
  EXPECT_EQ(w.low, 1);
  EXPECT_EQ(w.count, 3);
}

TEST(OptionTable, ReadReportsABrokenRuleBetweenFieldsAtTheFieldItIsAbout) {
  Issues issues;
  wideBandTable().read(R"({"low": 3})", WideBand{}, "/band", issues);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0], (Issue{Severity::Error, "schema.range", "/band/high", "WideBand::high = 2: must be > low"}));
  issues.clear();
  wideBandTable().read(R"([1, 2])", WideBand{}, "/band", issues);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].where, "/band");
  EXPECT_EQ(issues[0].message, "options must be a JSON object");
  issues.clear();
  EXPECT_EQ(wideBandTable().read("", WideBand{}, "/band", issues).count, 3);
  EXPECT_TRUE(issues.empty());
}

TEST(OptionTable, EveryFieldRoundTripsThroughJson) {
  Toy t;
  t.fast = false;
  t.count = 17;
  t.seed = 123456789012345u;
  t.rate = 0.1 + 0.2;
  t.tolerance = 2.5e-7;
  t.third = 2.0 / 3.0;
  t.label = "a \"quoted\" name";
  t.shape = Shape::Arc;
  t.window = 9;
  t.steps = -4;
  t.sigma = 1e-300;
  const std::string json = toyTable().json(t);
  const Toy back = toyTable().parse(json, Toy{}, "toy");
  EXPECT_EQ(toyTable().json(back), json);
  for (std::size_t i = 0; i < toyTable().fields().size(); ++i)
    EXPECT_EQ(toyTable().get(back, i), toyTable().get(t, i)) << toyTable().fields()[i].name;
  EXPECT_EQ(back.third, t.third);
  EXPECT_EQ(back.rate, t.rate);
}

}  // namespace
}  // namespace mapnav
