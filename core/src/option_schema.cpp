// What an option table writes of itself (option_table.h): the JSON Schema of its options object and
// its section of docs/options.md. Both come from OptionTableDescription, so the committed schemas and
// docs can be compared with the tables (`mapnav options --check`).
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "mapnav/core/option_table.h"

namespace mapnav {

namespace {

using OrderedJson = nlohmann::ordered_json;

/// A bound as JSON: an integer when it is one (type bounds, counts), else the double.
OrderedJson bound(double value) {
  if (value == std::floor(value) && std::abs(value) <= 9007199254740992.0) return static_cast<long long>(value);
  return value;
}

void addRange(OrderedJson& schema, const OptionFieldSpec& field) {
  const OptionRule& rule = field.rule;
  const bool integer = field.kind == OptionKind::Integer;
  if (std::isfinite(rule.min)) schema[rule.min_open ? "exclusiveMinimum" : "minimum"] = bound(rule.min);
  else if (integer) schema["minimum"] = bound(field.integer_min);
  if (std::isfinite(rule.max)) schema[rule.max_open ? "exclusiveMaximum" : "maximum"] = bound(rule.max);
  else if (integer) schema["maximum"] = bound(field.integer_max);
  if (rule.odd) schema["not"] = {{"multipleOf", 2}};
}

/// The rules between fields about `field`, as "; must be RULE" clauses.
std::string rulesAbout(const OptionTableDescription& table, const std::string& field) {
  std::string out;
  for (const auto& [name, rule] : table.rules)
    if (name == field) out += "; must be " + rule;
  return out;
}

std::string presetList(const std::vector<OptionPreset>& presets) {
  std::string out;
  for (std::size_t i = 0; i < presets.size(); ++i) out += (i > 0 ? "; " : "") + presets[i].name + ": " + presets[i].description;
  return out;
}

OrderedJson fieldSchema(const OptionTableDescription& table, std::size_t i) {
  const OptionFieldSpec& field = table.fields[i];
  OrderedJson schema = OrderedJson::object();
  switch (field.kind) {
    case OptionKind::Bool:
      schema["type"] = "boolean";
      break;
    case OptionKind::String:
      schema["type"] = "string";
      break;
    case OptionKind::Choice:
      schema["enum"] = field.choices;
      break;
    case OptionKind::Integer:
      schema["type"] = "integer";
      addRange(schema, field);
      break;
    case OptionKind::Number:
      schema["type"] = "number";
      addRange(schema, field);
      break;
  }
  const OrderedJson value = OrderedJson::parse(table.defaults.at(i));
  if (!value.is_null()) schema["default"] = value;
  schema["description"] = field.doc + rulesAbout(table, field.name);
  return schema;
}

/// "\"a\", \"b\" or \"c\"" for Markdown: each name in backticks.
std::string choicesMarkdown(const std::vector<std::string>& choices) {
  std::string out;
  for (std::size_t i = 0; i < choices.size(); ++i) {
    if (i > 0) out += i + 1 == choices.size() ? " or " : ", ";
    out += "`\"" + choices[i] + "\"`";
  }
  return out;
}

std::string allowedMarkdown(const OptionFieldSpec& field) {
  switch (field.kind) {
    case OptionKind::Bool:
      return "true or false";
    case OptionKind::String:
      return "a string";
    case OptionKind::Choice:
      return choicesMarkdown(field.choices);
    case OptionKind::Integer:
    case OptionKind::Number:
      break;
  }
  const bool bounded = std::isfinite(field.rule.min) || std::isfinite(field.rule.max);
  std::string out = field.kind == OptionKind::Integer ? (bounded ? "an integer " + field.rule.rangeText(false) : "an integer")
                                                      : field.rule.rangeText(true);
  if (field.rule.odd) out += ", odd";
  return out;
}

/// A table cell: a '|' would end it, a line break would end the row.
std::string cell(std::string text) {
  std::string out;
  for (const char c : text) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

}  // namespace

std::string optionSchemaJson(const OptionTableDescription& table) {
  OrderedJson schema = {{"type", "object"},
                        {"title", table.owner},
                        {"additionalProperties", false},
                        {"patternProperties", {{"^x-", OrderedJson::object()}}},
                        {"properties", OrderedJson::object()}};
  OrderedJson& properties = schema["properties"];
  if (!table.presets.empty()) {
    OrderedJson names = OrderedJson::array();
    for (const OptionPreset& preset : table.presets) names.push_back(preset.name);
    properties["preset"] = {{"enum", names},
                            {"description", "A named set of values, applied before the other members: " + presetList(table.presets)}};
  }
  for (std::size_t i = 0; i < table.fields.size(); ++i) properties[table.fields[i].name] = fieldSchema(table, i);
  return schema.dump();
}

std::string optionMarkdown(const OptionTableDescription& table) {
  std::string out = "### " + table.owner + "\n\n| option | default | allowed | meaning |\n|---|---|---|---|\n";
  for (std::size_t i = 0; i < table.fields.size(); ++i) {
    const OptionFieldSpec& field = table.fields[i];
    out += "| `" + field.name + "` | `" + cell(table.defaults.at(i)) + "` | " + cell(allowedMarkdown(field)) + " | " +
           cell(field.doc) + " |\n";
  }
  if (!table.rules.empty()) {
    out += "\nRules between fields:\n";
    for (const auto& [field, rule] : table.rules) out += "- `" + field + "` must be " + rule + "\n";
  }
  if (!table.presets.empty()) {
    out += "\nPresets (`\"preset\": \"NAME\"`, applied before the other members):\n";
    for (const OptionPreset& preset : table.presets) out += "- `" + preset.name + "`: " + preset.description + ": `" + preset.json + "`\n";
  }
  return out;
}

}  // namespace mapnav
