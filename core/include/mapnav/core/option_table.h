#pragma once
// A declarative table of an option struct's fields: each field is a name, the member it reads and
// writes, its rule (a range; integers; odd) and its documentation; rules between fields (`far_m >
// near_m`) are check()s of the table. The struct's member initialisers
// are the only defaults (as in Ceres' option structs): the table reads them from a default-constructed
// struct. A struct that holds a component's options nest()s the component's table. From the one
// table come
//   parse()    a JSON object of options onto a struct, `"preset": "NAME"` applied before the other
//              members; errors name who is configured, the option and its bad value,
//   read()     the same for a block of a file, every bad member an Issue at its JSON Pointer,
//   validate() the rules, as Ceres words them ("OWNER::FIELD = VALUE: must be RULE"),
//   list()     the documented options with their defaults as JSON text (`mapnav pipelines`),
//   json()     a struct's values as a JSON object (parse() reads it back),
//   describe() the table as data, from which optionSchemaJson() and optionMarkdown() write the JSON
//              Schema of its options object and its reference in docs (`mapnav options`).
// The JSON is read and written in core/src/option_table.cpp: this header needs no JSON library.
//
//   const OptionTable<FooOptions>& fooOptionTable() {
//     static const OptionTable<FooOptions> table = OptionTable<FooOptions>("FooOptions")
//         .field("iterations", &FooOptions::iterations, inRange(1, 100), "iterations at most")
//         .field("fast", &FooOptions::fast, "the lookup table instead of the reference path")
//         .field("low", &FooOptions::low, "the lower bound").field("high", &FooOptions::high, "the upper bound")
//         .check("high", [](const FooOptions& o) { return o.high > o.low; }, "> low")
//         .preset("quick", R"({"iterations": 5, "fast": true})", "for previews");
//     return table;
//   }
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/core/issue.h"
#include "mapnav/core/option_info.h"

namespace mapnav {

/// The values a number option allows: finite, within [min, max] (either end open; an infinite end
/// is no bound), and odd when `odd`.
struct OptionRule {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false, max_open = false;
  bool odd = false;

  /// Finite and within the range (oddness aside).
  bool allows(double value) const;
  /// "in [0, 255]", "in (0, 4]", ">= 4", "> 0", "<= 1" or "finite"; `finite` writes "finite and "
  /// before a one-sided range (for floating-point fields, where infinity would pass it).
  std::string rangeText(bool finite) const;
};

/// [min, max]
inline OptionRule inRange(double min, double max) { return {.min = min, .max = max}; }
/// (min, max]
inline OptionRule aboveUpTo(double min, double max) { return {.min = min, .max = max, .min_open = true}; }
/// >= min
inline OptionRule atLeast(double min) { return {.min = min}; }
/// > min
inline OptionRule above(double min) { return {.min = min, .min_open = true}; }
/// `rule`, and odd.
inline OptionRule oddIn(OptionRule rule) {
  rule.odd = true;
  return rule;
}

enum class OptionKind { Bool, Integer, Number, String, Choice };

/// One option's value as the table moves it: Bool -> bool; Integer and Number -> double (integers
/// exact up to 2^53); String and Choice (an enum's name) -> std::string.
using OptionValue = std::variant<bool, double, std::string>;

/// One field of a table, as the JSON code sees it (without its member).
struct OptionFieldSpec {
  std::string name = {};
  OptionKind kind = OptionKind::Number;
  OptionRule rule = {};                     ///< Integer, Number
  double integer_min = 0, integer_max = 0;  ///< Integer: what the member's type holds
  std::vector<std::string> choices = {};    ///< Choice: the names of the enum's values
  std::string doc = {};
};

/// What a table says of itself: the data the generated schemas and docs are written from.
struct OptionTableDescription {
  std::string owner = {};
  std::vector<OptionFieldSpec> fields = {};
  std::vector<std::string> defaults = {};  ///< parallel to fields: a default-constructed struct's value, JSON text
  std::vector<OptionPreset> presets = {};
  /// The rules between fields as (field, rule): ("far_m", "> near_m").
  std::vector<std::pair<std::string, std::string>> rules = {};
};

/// The JSON Schema (draft 2020-12) of the options object the table reads, as one line of JSON: an
/// object of the fields (each with its type, its range as minimum / exclusiveMinimum / maximum /
/// exclusiveMaximum, an integer's type bounds, "odd" as not a multiple of 2, a choice's names as an
/// enum, its default unless that is not finite, its doc as the description, a rule between fields
/// appended to it as "; must be RULE"), no other members but "x-..." ones, and "preset" when the table has
/// presets. Rules a schema cannot state (a number must be finite; the rules between fields) are
/// still the table's.
std::string optionSchemaJson(const OptionTableDescription& table);
/// The table as a Markdown section of docs/options.md: "### OWNER", one row per field (option,
/// default, allowed values, meaning), then the rules between fields and the presets.
std::string optionMarkdown(const OptionTableDescription& table);

namespace detail {

/// The members of the JSON object `text` ("" = {}) as (field index, value), checked against
/// `fields` and in the order to apply them: a preset's members first (`"preset": "NAME"`), then the
/// others. Throws InvalidInput "WHO: ..." naming the option and its bad value (not JSON, not an
/// object, unknown option or preset, wrong type, out of range, not an integer, not odd).
std::vector<std::pair<std::size_t, OptionValue>> parseOptionMembers(const std::vector<OptionFieldSpec>& fields,
                                                                    const std::vector<OptionPreset>& presets,
                                                                    std::string_view who, std::string_view text);
/// As parseOptionMembers, for a block of a file at JSON Pointer `pointer`: every member that is
/// unknown, of the wrong type or out of its range becomes an Issue at POINTER/NAME
/// ("schema.unknown_field", "schema.type", "schema.range"), and only the good members are returned.
/// Members named "x-..." (extensions) and "$schema" are skipped, as in every object of mapnav's
/// files; a syntax error is a "json.syntax" Issue with its line and column, text that is not a JSON
/// object one Issue at `pointer`.
std::vector<std::pair<std::size_t, OptionValue>> readOptionMembers(const std::vector<OptionFieldSpec>& fields,
                                                                   const std::vector<OptionPreset>& presets,
                                                                   const std::string& pointer, std::string_view text,
                                                                   Issues& issues);
/// "OWNER::FIELD = VALUE: must be RULE" unless `value` keeps the field's own rule; "" when it does.
std::string brokenOptionValue(const OptionFieldSpec& field, std::string_view owner, const OptionValue& value);
/// "OWNER::FIELD = VALUE: must be RULE", a number VALUE with 17 digits (it reads back exactly).
std::string optionRuleText(const OptionFieldSpec& field, std::string_view owner, const OptionValue& value,
                           std::string_view rule);
/// The value as JSON text: true, 12, 0.5, 1e-06, "luminance".
std::string optionValueJson(const OptionFieldSpec& field, const OptionValue& value);
/// {"NAME": VALUE, ...} on one line, in the fields' order.
std::string optionObjectJson(const std::vector<OptionFieldSpec>& fields, const std::vector<OptionValue>& values);

template <class M>
constexpr OptionKind optionKindOf() {
  if constexpr (std::is_same_v<M, bool>) return OptionKind::Bool;
  else if constexpr (std::is_integral_v<M>) return OptionKind::Integer;
  else if constexpr (std::is_floating_point_v<M>) return OptionKind::Number;
  else {
    static_assert(std::is_same_v<M, std::string>, "an option is a bool, an integer, a double, a string or an enum");
    return OptionKind::String;
  }
}

template <class M>
OptionValue toOptionValue(const M& value) {
  if constexpr (std::is_same_v<M, bool> || std::is_same_v<M, std::string>) return value;
  else return static_cast<double>(value);
}

template <class M>
M fromOptionValue(const OptionValue& value) {
  if constexpr (std::is_same_v<M, bool> || std::is_same_v<M, std::string>) return std::get<M>(value);
  else return static_cast<M>(std::get<double>(value));
}

}  // namespace detail

/// The table of option struct T's fields. Build it once (a function-local static) with the chained
/// field(), choice(), computed(), include() and preset() calls; then it only reads.
template <class T>
class OptionTable {
 public:
  using Getter = std::function<OptionValue(const T&)>;
  using Setter = std::function<void(T&, const OptionValue&)>;

  /// `owner`: the struct's name in validate()'s messages ("EdgeTrackerOptions").
  explicit OptionTable(std::string owner) : owner_(std::move(owner)) {}

  /// A bool, integer (int, std::uint64_t, ...), double or std::string member of T (or of a base of T).
  template <class M, class C>
  OptionTable& field(std::string name, M C::*member, OptionRule rule, std::string doc) {
    static_assert(std::is_base_of_v<C, T>, "a member of the struct or of its base");
    return computed(
        std::move(name), [member](const T& o) -> M { return o.*member; }, [member](T& o, M v) { o.*member = std::move(v); },
        rule, std::move(doc));
  }
  template <class M, class C>
  OptionTable& field(std::string name, M C::*member, std::string doc) {
    return field(std::move(name), member, OptionRule{}, std::move(doc));
  }

  /// An enum member, written as one of `names` (each value's name).
  template <class E, class C>
  OptionTable& choice(std::string name, E C::*member, std::vector<std::pair<E, std::string>> names, std::string doc) {
    static_assert(std::is_enum_v<E> && std::is_base_of_v<C, T>);
    OptionFieldSpec spec{.name = std::move(name), .kind = OptionKind::Choice, .doc = std::move(doc)};
    for (const auto& entry : names) spec.choices.push_back(entry.second);
    Getter get = [member, names](const T& o) -> OptionValue {
      for (const auto& [value, text] : names)
        if (value == o.*member) return text;
      return std::string("?");
    };
    Setter set = [member, names](T& o, const OptionValue& v) {
      for (const auto& [value, text] : names)
        if (text == std::get<std::string>(v)) o.*member = value;
    };
    return add(std::move(spec), std::move(get), std::move(set));
  }

  /// An option that is not one member as it is: read with get(const T&) -> M, written with
  /// set(T&, M) (a bool that picks an enum's value, a member of a member).
  template <class Get, class Set>
  OptionTable& computed(std::string name, Get get, Set set, OptionRule rule, std::string doc) {
    using M = std::remove_cvref_t<std::invoke_result_t<Get, const T&>>;
    OptionFieldSpec spec{.name = std::move(name), .kind = detail::optionKindOf<M>(), .rule = rule, .doc = std::move(doc)};
    if constexpr (std::is_integral_v<M> && !std::is_same_v<M, bool>) {
      constexpr double kExact = 9007199254740992.0;  // 2^53: the doubles that are integers beyond are not all
      spec.integer_min = std::max(-kExact, static_cast<double>(std::numeric_limits<M>::min()));
      spec.integer_max = std::min(kExact, static_cast<double>(std::numeric_limits<M>::max()));
    }
    return add(
        std::move(spec), [get](const T& o) { return detail::toOptionValue<M>(get(o)); },
        [set](T& o, const OptionValue& v) { set(o, detail::fromOptionValue<M>(v)); });
  }
  template <class Get, class Set>
  OptionTable& computed(std::string name, Get get, Set set, std::string doc) {
    return computed(std::move(name), std::move(get), std::move(set), OptionRule{}, std::move(doc));
  }

  /// Every field of a base struct's table, in its order.
  template <class Base>
  OptionTable& include(const OptionTable<Base>& base) {
    static_assert(std::is_base_of_v<Base, T>);
    for (std::size_t i = 0; i < base.specs_.size(); ++i) {
      add(base.specs_[i], [get = base.getters_[i]](const T& o) { return get(o); },
          [set = base.setters_[i]](T& o, const OptionValue& v) { set(o, v); });
    }
    for (const auto& c : base.checks_)
      checks_.push_back({fieldIndex(base.specs_[c.field].name), [ok = c.ok](const T& o) { return ok(o); }, c.rule});
    return *this;
  }

  /// The fields of a component's table, reached through `member` (a struct of T, or of a base of T,
  /// with a table of its own), under the component's names — so a pipeline's options hold its
  /// components' options instead of copying them, and their JSON stays flat. `renamed`: {component
  /// name, name here} where the JSON has always used another name; `omitted`: the component's
  /// fields that are no option here (set by the code, or stated by this table itself). The
  /// component's rules between fields come along, but for those about an omitted field.
  template <class M, class C>
  OptionTable& nest(M C::*member, const OptionTable<M>& table, const std::vector<std::pair<std::string, std::string>>& renamed = {},
                    const std::vector<std::string>& omitted = {}) {
    static_assert(std::is_base_of_v<C, T>, "a member of the struct or of its base");
    const auto nameHere = [&](const std::string& name) {
      for (const auto& [from, to] : renamed)
        if (from == name) return to;
      return name;
    };
    const auto isOmitted = [&](const std::string& name) { return std::find(omitted.begin(), omitted.end(), name) != omitted.end(); };
    for (std::size_t i = 0; i < table.specs_.size(); ++i) {
      if (isOmitted(table.specs_[i].name)) continue;
      OptionFieldSpec spec = table.specs_[i];
      spec.name = nameHere(spec.name);
      add(std::move(spec), [member, get = table.getters_[i]](const T& o) { return get(o.*member); },
          [member, set = table.setters_[i]](T& o, const OptionValue& v) { set(o.*member, v); });
    }
    for (const auto& c : table.checks_) {
      if (isOmitted(table.specs_[c.field].name)) continue;
      checks_.push_back({fieldIndex(nameHere(table.specs_[c.field].name)), [member, ok = c.ok](const T& o) { return ok(o.*member); }, c.rule});
    }
    return *this;
  }

  /// A named set of values (a JSON object of this table's options), chosen with `"preset": "NAME"`.
  OptionTable& preset(std::string name, std::string json, std::string doc) {
    presets_.push_back({std::move(name), std::move(doc), std::move(json)});
    return *this;
  }

  /// A rule between fields, judged after every field's own rule: `ok(options)` must hold, else
  /// validate() throws "OWNER::FIELD = VALUE: must be RULE" (`field`: a field of this table, the one
  /// the rule is about; `rule`: "> near_m", "in (0, turn_in_place_deg)").
  OptionTable& check(std::string_view field, std::function<bool(const T&)> ok, std::string rule) {
    checks_.push_back({fieldIndex(field), std::move(ok), std::move(rule)});
    return *this;
  }

  const std::string& owner() const { return owner_; }
  const std::vector<OptionFieldSpec>& fields() const { return specs_; }
  const std::vector<OptionPreset>& presets() const { return presets_; }
  OptionValue get(const T& options, std::size_t field) const { return getters_.at(field)(options); }
  void set(T& options, std::size_t field, const OptionValue& value) const { setters_.at(field)(options, value); }

  /// The first broken rule as (field, "OWNER::FIELD = VALUE: must be RULE"): the fields' own rules
  /// in the table's order, then the rules between fields in theirs; nothing when all hold.
  std::optional<std::pair<std::size_t, std::string>> brokenRule(const T& options) const {
    for (std::size_t i = 0; i < specs_.size(); ++i)
      if (std::string text = detail::brokenOptionValue(specs_[i], owner_, getters_[i](options)); !text.empty())
        return std::pair{i, std::move(text)};
    for (const Check& c : checks_)
      if (!c.ok(options)) return std::pair{c.field, detail::optionRuleText(specs_[c.field], owner_, getters_[c.field](options), c.rule)};
    return std::nullopt;
  }

  /// Throws InvalidInput "OWNER::FIELD = VALUE: must be RULE" for the first broken rule (brokenRule).
  void validate(const T& options) const {
    if (auto broken = brokenRule(options)) throw InvalidInput(broken->second);
  }

  /// `base` with the members of the JSON object `text` ("" = {}), a preset's first; then T::validate()
  /// when T has one (its cross-field rules), else validate(). Throws InvalidInput beginning "WHO: "
  /// (`pipeline "sidewalk"`) naming the option and its bad value; `base` is never changed.
  T parse(std::string_view text, const T& base, std::string_view who) const {
    T out = base;
    for (const auto& [field, value] : detail::parseOptionMembers(specs_, presets_, who, text)) setters_[field](out, value);
    try {
      if constexpr (requires { out.validate(); }) out.validate();
      else validate(out);
    } catch (const InvalidInput& e) {
      throw InvalidInput(std::string(who) + ": " + e.what());
    }
    return out;
  }

  /// As parse(), for the block of a file at JSON Pointer `pointer` (mold's way: every error of the
  /// pass): each bad member is an Issue at POINTER/NAME (readOptionMembers), the good ones apply to
  /// `base`; then the first broken rule is a "schema.range" Issue at POINTER/FIELD, and T::validate()'s
  /// complaint, when T has one, an Issue at `pointer`.
  T read(std::string_view text, const T& base, const std::string& pointer, Issues& issues) const {
    T out = base;
    const std::size_t before = issues.size();
    for (const auto& [field, value] : detail::readOptionMembers(specs_, presets_, pointer, text, issues))
      setters_[field](out, value);
    if (issues.size() != before) return out;
    if (auto broken = brokenRule(out)) {
      addIssue(issues, Severity::Error, "schema.range", pointer + "/" + specs_[broken->first].name, broken->second);
    } else if constexpr (requires { out.validate(); }) {
      try {
        out.validate();
      } catch (const InvalidInput& e) {
        addIssue(issues, Severity::Error, "schema.range", pointer, e.what());
      }
    }
    return out;
  }

  /// The documented options, each with a default-constructed T's value.
  std::vector<OptionInfo> list() const {
    const T defaults{};
    std::vector<OptionInfo> out;
    for (std::size_t i = 0; i < specs_.size(); ++i)
      out.push_back({specs_[i].name, detail::optionValueJson(specs_[i], getters_[i](defaults)), specs_[i].doc});
    return out;
  }

  /// The table as data (optionSchemaJson(), optionMarkdown()), with a default-constructed T's values.
  OptionTableDescription describe() const {
    const T defaults{};
    OptionTableDescription out{.owner = owner_, .fields = specs_, .presets = presets_};
    for (std::size_t i = 0; i < specs_.size(); ++i) out.defaults.push_back(detail::optionValueJson(specs_[i], getters_[i](defaults)));
    for (const Check& c : checks_) out.rules.emplace_back(specs_[c.field].name, c.rule);
    return out;
  }

  /// Every option's value in `options` as one JSON object.
  std::string json(const T& options) const {
    std::vector<OptionValue> values;
    for (const Getter& get : getters_) values.push_back(get(options));
    return detail::optionObjectJson(specs_, values);
  }

 private:
  template <class>
  friend class OptionTable;

  struct Check {
    std::size_t field;
    std::function<bool(const T&)> ok;
    std::string rule;
  };

  std::size_t fieldIndex(std::string_view name) const {
    for (std::size_t i = 0; i < specs_.size(); ++i)
      if (specs_[i].name == name) return i;
    throw std::logic_error(owner_ + ": a rule names \"" + std::string(name) + "\", which is not a field of the table");
  }

  OptionTable& add(OptionFieldSpec spec, Getter get, Setter set) {
    for (const OptionFieldSpec& other : specs_)
      if (other.name == spec.name) throw std::logic_error(owner_ + ": two fields are named \"" + spec.name + "\"");
    specs_.push_back(std::move(spec));
    getters_.push_back(std::move(get));
    setters_.push_back(std::move(set));
    return *this;
  }

  std::string owner_;
  std::vector<OptionFieldSpec> specs_;
  std::vector<Getter> getters_;  ///< parallel to specs_
  std::vector<Setter> setters_;
  std::vector<OptionPreset> presets_;
  std::vector<Check> checks_;
};

}  // namespace mapnav
