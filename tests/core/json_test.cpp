#include "mapnav/core/json.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"

namespace mapnav {
namespace {

TEST(ParseJson, SyntaxErrorCarriesLineAndColumnOfTheOffendingCharacter) {
  Issues issues;
  // Line 3 is `  "b": ]`: the ']' at column 8 is where a value was expected.
  EXPECT_FALSE(parseJson("{\n  \"a\": 1,\n  \"b\": ]\n}", issues));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "json.syntax");
  EXPECT_EQ(issues[0].line, 3);
  EXPECT_EQ(issues[0].column, 8);
}

TEST(ParseJson, EmptyTextIsASyntaxErrorAtLineOne) {
  Issues issues;
  EXPECT_FALSE(parseJson(" \n ", issues));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].message, "the file is empty");
  EXPECT_EQ(issues[0].line, 1);
}

TEST(ParseJson, OverflowingNumberIsNotFiniteWithItsPosition) {
  Issues issues;
  EXPECT_FALSE(parseJson("{\"a\": [1,\n 2e999]}", issues));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "json.not_finite");
  EXPECT_EQ(issues[0].line, 2);
  EXPECT_EQ(issues[0].column, 2);
}

// Found with fuzz_mission: a mission's `vision.options` nested 200 000 deep parsed, then overflowed
// the stack in Json::dump(). Refused here, for every format, with where it goes too deep.
TEST(ParseJson, NestingDeeperThanTheLimitIsRefusedWithItsPosition) {
  Issues issues;
  const std::string deep = "{\"a\": \"[[{\",\n \"b\": " + std::string(200000, '[') + std::string(200000, ']') + "}";
  EXPECT_FALSE(parseJson(deep, issues));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "json.too_deep");
  EXPECT_EQ(issues[0].message, "arrays and objects nested more than 512 deep");
  EXPECT_EQ(issues[0].line, 2);
  EXPECT_EQ(issues[0].column, 7 + 511);  // " \"b\": " is 6 columns; the 512th '[' is the object's 513th level
}

TEST(ParseJson, NestingUpToTheLimitParses) {
  Issues issues;
  const auto json = parseJson(std::string(512, '[') + std::string(512, ']'), issues);
  ASSERT_TRUE(json);
  EXPECT_TRUE(json->is_array());
  EXPECT_TRUE(issues.empty());
}

TEST(PointerJoin, EscapesTildeAndSlashAsRfc6901Says) {
  EXPECT_EQ(pointerJoin("/surfaces", "a/b~c"), "/surfaces/a~1b~0c");
  EXPECT_EQ(pointerJoin("", std::size_t{3}), "/3");
}

TEST(JsonObject, ReportsWrongTypesMissingAndUnknownMembersWithPointers) {
  Issues issues;
  const Json j = Json::parse(R"({"width": "2", "misspelt": 1, "x-note": "ok", "ok": true})");
  JsonObject object(j, "/roads/4", issues);
  EXPECT_FALSE(object.number("width"));
  EXPECT_FALSE(object.string("id"));
  EXPECT_EQ(object.boolean("ok"), true);
  object.rejectUnknownMembers();
  ASSERT_EQ(issues.size(), 3u);
  EXPECT_EQ(issues[0].check, "schema.type");
  EXPECT_EQ(issues[0].where, "/roads/4/width");
  EXPECT_EQ(issues[1].check, "schema.required");
  EXPECT_EQ(issues[1].where, "/roads/4");
  EXPECT_EQ(issues[2].check, "schema.unknown_field");
  EXPECT_EQ(issues[2].where, "/roads/4/misspelt");
}

TEST(JsonObject, RangeIsCheckedInclusively) {
  Issues issues;
  const Json j = Json::parse(R"({"a": 255, "b": 255.5, "c": -0.1})");
  JsonObject object(j, "", issues);
  EXPECT_EQ(object.number("a", true, 0, 255), 255.0);
  EXPECT_FALSE(object.number("b", true, 0, 255));
  EXPECT_FALSE(object.number("c", true, 0, 255));
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_EQ(issues[0].where, "/b");
  EXPECT_EQ(issues[1].check, "schema.range");
}

TEST(DumpJson, PutsPointsOnOneLineAndRoundTripsDoublesExactly) {
  Json j = Json::object();
  j["p"] = Json::array({0.1, 1.0 / 3.0});
  const std::string text = dumpJson(j);
  EXPECT_EQ(text, "{\n  \"p\": [0.1, 0.3333333333333333]\n}\n");
  EXPECT_EQ(Json::parse(text)["p"][1].get<double>(), 1.0 / 3.0);
  // Short flat objects inside a document go on one line too; the document itself does not.
  Json legs = Json::object();
  legs["legs"] = Json::array({Json{{"action", "drive"}, {"meters", 2.5}}});
  EXPECT_EQ(dumpJson(legs), "{\n  \"legs\": [\n    {\"action\": \"drive\", \"meters\": 2.5}\n  ]\n}\n");
}

TEST(FormatIssue, PrintsFilePointerSeverityCheckAndMessage) {
  const Issue pointed{Severity::Error, "roads.invalid_width", "/roads/2/width", "width 0 m must be > 0"};
  EXPECT_EQ(formatIssue(pointed, "m.json"), "m.json:/roads/2/width: error: roads.invalid_width: width 0 m must be > 0");
  const Issue syntax{Severity::Error, "json.syntax", "", "unexpected ']'", 3, 8};
  EXPECT_EQ(formatIssue(syntax, "m.json"), "m.json:3:8: error: json.syntax: unexpected ']'");
  const Issue whole{Severity::Warning, "topology.disconnected", "", "falls apart"};
  EXPECT_EQ(formatIssue(whole, "m.json"), "m.json: warning: topology.disconnected: falls apart");
}

TEST(ValidationError, WhatNamesTheFirstErrorAndCountsTheRest) {
  const ValidationError e("m.json", {Issue{Severity::Warning, "w", "/a", "warn"}, Issue{Severity::Error, "e1", "/b", "first"},
                                     Issue{Severity::Error, "e2", "/c", "second"}});
  EXPECT_STREQ(e.what(), "m.json:/b: error: e1: first (and 1 more errors)");
  EXPECT_EQ(e.issues().size(), 3u);
}

}  // namespace
}  // namespace mapnav
