// The JSON side of option tables (option_table.h): reading an options object against the fields'
// specs, checking values against their rules, and writing values as JSON text.
#include "mapnav/core/option_table.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mapnav/core/json.h"

namespace mapnav {

namespace {

/// A number as people write it: the shortest of 6 significant digits ("1e-06", "0.15", "1e+09")
/// when that reads back exactly, else 17.
std::string readableNumber(double value) {
  std::ostringstream s;
  s << value;
  if (std::strtod(s.str().c_str(), nullptr) == value) return s.str();
  std::ostringstream exact;
  exact.precision(17);
  exact << value;
  return exact.str();
}

bool isOdd(double value) { return std::fmod(std::abs(value), 2.0) == 1.0; }

/// "\"a\", \"b\" or \"c\""
std::string choicesText(const std::vector<std::string>& choices) {
  std::string out;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) out += i + 1 == choices.size() ? " or " : ", ";
    out += nlohmann::json(choices[i]).dump();
  }
  return out;
}

std::string presetNames(const std::vector<OptionPreset>& presets) {
  if (presets.empty()) return "there are none";
  std::string out = "presets: ";
  for (std::size_t i = 0; i < presets.size(); ++i) out += (i > 0 ? ", " : "") + presets[i].name;
  return out;
}

/// One member's value checked against its field: the value, or what is wrong with it ("option KEY =
/// VALUE: must be RULE") and whether that is its type.
struct MemberValue {
  OptionValue value = false;
  std::string error = {};
  bool wrong_type = false;
};

MemberValue memberValue(const OptionFieldSpec& field, const Json& value) {
  const auto bad = [&](const std::string& rule, bool wrong_type) {
    return MemberValue{.error = "option " + field.name + " = " + value.dump() + ": must be " + rule, .wrong_type = wrong_type};
  };
  switch (field.kind) {
    case OptionKind::Bool:
      if (!value.is_boolean()) return bad("true or false", true);
      return {.value = value.get<bool>()};
    case OptionKind::String:
      if (!value.is_string()) return bad("a string", true);
      return {.value = value.get<std::string>()};
    case OptionKind::Choice:
      if (!value.is_string()) return bad(choicesText(field.choices), true);
      if (std::find(field.choices.begin(), field.choices.end(), value.get<std::string>()) == field.choices.end())
        return bad(choicesText(field.choices), false);
      return {.value = value.get<std::string>()};
    case OptionKind::Integer:
    case OptionKind::Number:
      break;
  }
  if (!value.is_number() || !std::isfinite(value.get<double>())) return bad("a number", true);
  const double v = value.get<double>();
  if (!field.rule.allows(v)) return bad(field.rule.rangeText(false), false);
  if (field.kind == OptionKind::Integer) {
    if (v != std::floor(v)) return bad("an integer", true);
    if (v < field.integer_min || v > field.integer_max)
      return bad("an integer in [" + readableNumber(field.integer_min) + ", " + readableNumber(field.integer_max) + "]", false);
  }
  if (field.rule.odd && !isOdd(v)) return bad("odd", false);
  return {.value = v};
}

const OptionFieldSpec* findField(const std::vector<OptionFieldSpec>& fields, const std::string& key) {
  const auto it = std::find_if(fields.begin(), fields.end(), [&](const OptionFieldSpec& f) { return f.name == key; });
  return it == fields.end() ? nullptr : &*it;
}

/// The members of `object` (but "preset") as (field index, value), appended to `out`; throws
/// InvalidInput "WHO: ..." at the first bad one.
void readMembers(const std::vector<OptionFieldSpec>& fields, const Json& object, std::string_view who,
                 std::vector<std::pair<std::size_t, OptionValue>>& out) {
  for (const auto& member : object.items()) {
    const std::string& key = member.key();  // not a structured binding: clang 14 (scripts/fuzz) cannot capture one
    if (key == "preset") continue;
    const OptionFieldSpec* field = findField(fields, key);
    if (!field) throw InvalidInput(std::string(who) + ": unknown option \"" + key + "\"");
    MemberValue read = memberValue(*field, member.value());
    if (!read.error.empty()) throw InvalidInput(std::string(who) + ": " + read.error);
    out.emplace_back(static_cast<std::size_t>(field - fields.data()), std::move(read.value));
  }
}

/// The members of `object` (but "preset") that are good, as (field index, value), appended to `out`;
/// every other member is an Issue at POINTER/KEY.
void collectMembers(const std::vector<OptionFieldSpec>& fields, const Json& object, const std::string& pointer,
                    Issues& issues, std::vector<std::pair<std::size_t, OptionValue>>& out) {
  for (const auto& member : object.items()) {
    const std::string& key = member.key();
    if (key == "preset" || key.rfind("x-", 0) == 0 || key == "$schema") continue;  // extensions, as in every file
    const std::string where = pointerJoin(pointer, key);
    const OptionFieldSpec* field = findField(fields, key);
    if (!field) {
      addIssue(issues, Severity::Error, "schema.unknown_field", where, "unknown option \"" + key + "\"");
      continue;
    }
    MemberValue read = memberValue(*field, member.value());
    if (!read.error.empty())
      addIssue(issues, Severity::Error, read.wrong_type ? "schema.type" : "schema.range", where, std::move(read.error));
    else
      out.emplace_back(static_cast<std::size_t>(field - fields.data()), std::move(read.value));
  }
}

}  // namespace

bool OptionRule::allows(double value) const {
  if (!std::isfinite(value)) return false;
  if (min_open ? !(value > min) : !(value >= min)) return false;
  return max_open ? value < max : value <= max;
}

std::string OptionRule::rangeText(bool finite) const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max)
    return std::string("in ") + (min_open ? "(" : "[") + readableNumber(min) + ", " + readableNumber(max) + (max_open ? ")" : "]");
  const std::string prefix = finite ? "finite and " : "";
  if (has_min) return prefix + (min_open ? "> " : ">= ") + readableNumber(min);
  if (has_max) return prefix + (max_open ? "< " : "<= ") + readableNumber(max);
  return "finite";
}

namespace detail {

std::vector<std::pair<std::size_t, OptionValue>> parseOptionMembers(const std::vector<OptionFieldSpec>& fields,
                                                                    const std::vector<OptionPreset>& presets,
                                                                    std::string_view who, std::string_view text) {
  Json j;
  try {
    j = Json::parse(text.empty() ? std::string_view("{}") : text);
  } catch (const nlohmann::json::exception& e) {
    throw InvalidInput(std::string(who) + ": options are not JSON: " + e.what());
  }
  if (!j.is_object()) throw InvalidInput(std::string(who) + ": options must be a JSON object");
  std::vector<std::pair<std::size_t, OptionValue>> out;
  if (const auto p = j.find("preset"); p != j.end()) {
    if (!p->is_string()) throw InvalidInput(std::string(who) + ": option preset = " + p->dump() + ": must be a string (" + presetNames(presets) + ")");
    const std::string name = p->get<std::string>();
    const auto preset = std::find_if(presets.begin(), presets.end(), [&](const OptionPreset& s) { return s.name == name; });
    if (preset == presets.end())
      throw InvalidInput(std::string(who) + ": unknown preset \"" + name + "\" (" + presetNames(presets) + ")");
    const std::string in_preset = std::string(who) + ", preset \"" + name + "\"";
    const Json values = Json::parse(preset->json, nullptr, false);
    if (!values.is_object() || values.contains("preset"))
      throw InvalidInput(in_preset + ": must be a JSON object of options (without \"preset\")");
    readMembers(fields, values, in_preset, out);
  }
  readMembers(fields, j, who, out);
  return out;
}

std::vector<std::pair<std::size_t, OptionValue>> readOptionMembers(const std::vector<OptionFieldSpec>& fields,
                                                                   const std::vector<OptionPreset>& presets,
                                                                   const std::string& pointer, std::string_view text,
                                                                   Issues& issues) {
  std::vector<std::pair<std::size_t, OptionValue>> out;
  const std::optional<Json> parsed = parseJson(text.empty() ? std::string_view("{}") : text, issues);
  if (!parsed) return out;  // the syntax error is an Issue with its line and column
  const Json& j = *parsed;
  if (!j.is_object()) {
    addIssue(issues, Severity::Error, "schema.type", pointer, "options must be a JSON object");
    return out;
  }
  if (const auto p = j.find("preset"); p != j.end()) {
    const auto preset = std::find_if(presets.begin(), presets.end(),
                                     [&](const OptionPreset& s) { return p->is_string() && s.name == p->get<std::string>(); });
    if (preset == presets.end()) {
      addIssue(issues, Severity::Error, p->is_string() ? "schema.range" : "schema.type", pointer + "/preset",
               "unknown preset " + p->dump() + " (" + presetNames(presets) + ")");
    } else {
      collectMembers(fields, Json::parse(preset->json), pointer + "/preset", issues, out);
    }
  }
  collectMembers(fields, j, pointer, issues, out);
  return out;
}

std::string optionRuleText(const OptionFieldSpec& field, std::string_view owner, const OptionValue& value,
                           std::string_view rule) {
  std::ostringstream text;
  text << owner << "::" << field.name << " = ";
  if (const double* number = std::get_if<double>(&value)) {
    text.precision(17);
    text << *number;
  } else {
    text << optionValueJson(field, value);
  }
  text << ": must be " << rule;
  return text.str();
}

std::string brokenOptionValue(const OptionFieldSpec& field, std::string_view owner, const OptionValue& value) {
  if (field.kind != OptionKind::Integer && field.kind != OptionKind::Number) return "";
  const double v = std::get<double>(value);
  if (!field.rule.allows(v)) return optionRuleText(field, owner, value, field.rule.rangeText(field.kind == OptionKind::Number));
  if (field.rule.odd && !isOdd(v)) return optionRuleText(field, owner, value, "odd");
  return "";
}

std::string optionValueJson(const OptionFieldSpec& field, const OptionValue& value) {
  switch (field.kind) {
    case OptionKind::Bool:
      return std::get<bool>(value) ? "true" : "false";
    case OptionKind::String:
    case OptionKind::Choice:
      return nlohmann::json(std::get<std::string>(value)).dump();
    case OptionKind::Integer:
      return std::to_string(static_cast<long long>(std::get<double>(value)));
    case OptionKind::Number:
      break;
  }
  const double v = std::get<double>(value);
  return std::isfinite(v) ? readableNumber(v) : "null";
}

std::string optionObjectJson(const std::vector<OptionFieldSpec>& fields, const std::vector<OptionValue>& values) {
  std::string out = "{";
  for (std::size_t i = 0; i < fields.size() && i < values.size(); ++i)
    out += (i > 0 ? ", " : "") + nlohmann::json(fields[i].name).dump() + ": " + optionValueJson(fields[i], values[i]);
  return out + "}";
}

}  // namespace detail

}  // namespace mapnav
