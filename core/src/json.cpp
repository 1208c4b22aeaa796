#include "mapnav/core/json.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mapnav {

namespace {

// nlohmann reports a byte offset; people want line and column.
void lineColumn(std::string_view text, std::size_t byte, int& line, int& column) {
  line = 1;
  column = 1;
  const std::size_t end = std::min(byte, text.size());
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
}

// The part of nlohmann's message after "syntax error while parsing value - ".
std::string syntaxReason(const std::string& what) {
  std::string reason = what;
  const auto dash = reason.find(" - ");
  if (dash != std::string::npos) reason = reason.substr(dash + 3);
  return reason;
}

// Iterative, so that a hostile document nested 100 000 deep cannot overflow the stack. The JSON
// Pointer is joined only for a number it reports: a pointer string built for every value would copy
// depth² bytes (40 GB for 200 000 brackets).
void findNonFinite(const Json& root, Issues& issues) {
  struct Pending {
    const Json* value;
    std::size_t depth;  // 0 for the root
    std::string step;   // "/key" or "/3" from its parent
  };
  std::vector<Pending> stack{{&root, 0, ""}};
  std::vector<std::string> path;  // the steps from the root to the value being looked at
  while (!stack.empty()) {
    Pending next = std::move(stack.back());
    stack.pop_back();
    path.resize(next.depth == 0 ? 0 : next.depth - 1);
    if (next.depth > 0) path.push_back(std::move(next.step));
    const Json& value = *next.value;
    if (value.is_number_float()) {
      if (!std::isfinite(value.get<double>())) {
        std::string pointer;
        for (const std::string& step : path) pointer += step;
        addIssue(issues, Severity::Error, "json.not_finite", pointer,
                 "number is out of the range of a double (overflows to infinity)");
      }
    } else if (value.is_object()) {
      for (auto it = value.begin(); it != value.end(); ++it) stack.push_back({&*it, next.depth + 1, pointerJoin("", it.key())});
    } else if (value.is_array()) {
      for (std::size_t i = value.size(); i-- > 0;) stack.push_back({&value[i], next.depth + 1, pointerJoin("", i)});
    }
  }
}

// How deep arrays and objects may nest (json.h says so).
constexpr std::size_t kMaxJsonDepth = 512;

// Where the first array or object nested deeper than kMaxJsonDepth opens; npos when none does.
// Parsing is iterative, but writing (dump) and copying a value recurse once per level, so a hostile
// document nested 100 000 deep would overflow the stack later, far from here.
std::size_t tooDeep(std::string_view text) {
  std::size_t depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

}  // namespace

std::optional<Json> parseJson(std::string_view text, Issues& issues) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    issues.push_back(Issue{Severity::Error, "json.syntax", "", "the file is empty", 1, 1});
    return std::nullopt;
  }
  if (const std::size_t at = tooDeep(text); at != std::string_view::npos) {
    Issue issue{Severity::Error, "json.too_deep", "",
                "arrays and objects nested more than " + std::to_string(kMaxJsonDepth) + " deep"};
    lineColumn(text, at, issue.line, issue.column);
    issues.push_back(std::move(issue));
    return std::nullopt;
  }
  try {
    Json value = Json::parse(text.begin(), text.end());
    const std::size_t before = issues.size();
    findNonFinite(value, issues);
    if (issues.size() != before) return std::nullopt;
    return value;
  } catch (const Json::parse_error& e) {
    Issue issue{Severity::Error, "json.syntax", "", syntaxReason(e.what())};
    // nlohmann's byte is 1-based and points just past the offending character.
    lineColumn(text, e.byte > 0 ? e.byte - 1 : 0, issue.line, issue.column);
    issues.push_back(std::move(issue));
    return std::nullopt;
  } catch (const Json::out_of_range& e) {
    // "number overflow parsing '1e999'": nlohmann gives no position, so find the token.
    std::string token;
    const std::string what = e.what();
    const auto open = what.find('\''), close = what.rfind('\'');
    if (open != std::string::npos && close > open) token = what.substr(open + 1, close - open - 1);
    Issue issue{Severity::Error, "json.not_finite", "",
                token.empty() ? "a number overflows a double" : "number " + token + " overflows a double"};
    const auto at = token.empty() ? std::string_view::npos : text.find(token);
    lineColumn(text, at == std::string_view::npos ? 0 : at, issue.line, issue.column);
    issues.push_back(std::move(issue));
    return std::nullopt;
  }
}

std::string pointerJoin(std::string_view base, std::string_view key) {
  std::string out(base);
  out += '/';
  for (char c : key) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

std::string pointerJoin(std::string_view base, std::size_t index) {
  return std::string(base) + "/" + std::to_string(index);
}

std::string_view jsonTypeName(const Json& value) {
  switch (value.type()) {
    case Json::value_t::object: return "object";
    case Json::value_t::array: return "array";
    case Json::value_t::string: return "string";
    case Json::value_t::boolean: return "boolean";
    case Json::value_t::null: return "null";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "number";
    default: return "binary";
  }
}

namespace {

bool isScalar(const Json& v) { return !v.is_object() && !v.is_array(); }

// Arrays of scalars, arrays of those ([[x, y], ...]) and objects of scalars or scalar arrays go on
// one line when short, so a point, a colour or a leg {"action": "drive", ...} reads as one thing.
bool inlineable(const Json& v, std::size_t depth) {
  if (isScalar(v)) return true;
  if (v.empty()) return true;
  if (depth > 1) return false;
  if (v.is_object()) {
    return depth == 0 && std::all_of(v.begin(), v.end(), [&](const Json& e) {
             return isScalar(e) || (e.is_array() && std::all_of(e.begin(), e.end(), isScalar));
           });
  }
  return std::all_of(v.begin(), v.end(), [&](const Json& e) { return isScalar(e) || (e.is_array() && inlineable(e, depth + 1)); });
}

void write(const Json& v, int indent, std::string& out) {
  const std::string pad(static_cast<std::size_t>(indent) * 2, ' ');
  if (inlineable(v, 0) && !(v.is_object() && indent == 0 && !v.empty())) {  // a document opens on its own line
    std::string flat = v.dump();
    // nlohmann writes [1,2]; people read [1, 2].
    std::string spaced;
    bool in_string = false;
    for (std::size_t i = 0; i < flat.size(); ++i) {
      const char c = flat[i];
      if (c == '"' && (i == 0 || flat[i - 1] != '\\')) in_string = !in_string;
      spaced += c;
      if (!in_string && (c == ',' || c == ':')) spaced += ' ';
    }
    const bool scalars_only = v.is_array() && std::all_of(v.begin(), v.end(), [](const Json& e) { return isScalar(e); });
    if (!v.is_structured() || spaced.size() <= 100 || scalars_only) {
      out += spaced;
      return;
    }
  }
  const bool object = v.is_object();
  out += object ? "{\n" : "[\n";
  std::size_t i = 0;
  for (auto it = v.begin(); it != v.end(); ++it, ++i) {
    out += pad + "  ";
    if (object) out += Json(it.key()).dump() + ": ";
    write(*it, indent + 1, out);
    if (i + 1 < v.size()) out += ',';
    out += '\n';
  }
  out += pad + (object ? "}" : "]");
}

}  // namespace

std::string dumpJson(const Json& value) {
  std::string out;
  write(value, 0, out);
  out += '\n';
  return out;
}

JsonObject::JsonObject(const Json& value, std::string pointer, Issues& issues)
    : pointer_(std::move(pointer)), issues_(issues) {
  if (value.is_object()) {
    object_ = &value;
  } else {
    addIssue(issues_, Severity::Error, "schema.type", pointer_,
             "expected an object, got " + std::string(jsonTypeName(value)));
  }
}

bool JsonObject::has(std::string_view key) const {
  return object_ != nullptr && object_->contains(key);
}

const Json* JsonObject::member(std::string_view key, bool required) {
  if (object_ == nullptr) return nullptr;
  known_.emplace_back(key);
  auto it = object_->find(key);
  if (it == object_->end()) {
    if (required) addIssue(issues_, Severity::Error, "schema.required", pointer_, "missing required member \"" + std::string(key) + "\"");
    return nullptr;
  }
  return &*it;
}

std::optional<std::string> JsonObject::string(std::string_view key, bool required) {
  const Json* value = member(key, required);
  if (value == nullptr) return std::nullopt;
  if (!value->is_string()) {
    addIssue(issues_, Severity::Error, "schema.type", pointer(key),
             "expected a string, got " + std::string(jsonTypeName(*value)));
    return std::nullopt;
  }
  return value->get<std::string>();
}

std::optional<double> readNumber(const Json& value, const std::string& pointer, Issues& issues, double min, double max) {
  if (!value.is_number()) {
    addIssue(issues, Severity::Error, "schema.type", pointer, "expected a number, got " + std::string(jsonTypeName(value)));
    return std::nullopt;
  }
  const double x = value.get<double>();
  if (!std::isfinite(x) || x < min || x > max) {
    std::ostringstream text;
    text.precision(17);
    text << "number " << x << " is outside [" << min << ", " << max << "]";
    addIssue(issues, Severity::Error, "schema.range", pointer, text.str());
    return std::nullopt;
  }
  return x;
}

std::optional<double> JsonObject::number(std::string_view key, bool required, double min, double max) {
  const Json* value = member(key, required);
  if (value == nullptr) return std::nullopt;
  return readNumber(*value, pointer(key), issues_, min, max);
}

std::optional<bool> JsonObject::boolean(std::string_view key, bool required) {
  const Json* value = member(key, required);
  if (value == nullptr) return std::nullopt;
  if (!value->is_boolean()) {
    addIssue(issues_, Severity::Error, "schema.type", pointer(key),
             "expected true or false, got " + std::string(jsonTypeName(*value)));
    return std::nullopt;
  }
  return value->get<bool>();
}

void JsonObject::rejectUnknownMembers() {
  if (object_ == nullptr) return;
  for (auto it = object_->begin(); it != object_->end(); ++it) {
    const std::string& key = it.key();
    if (key.rfind("x-", 0) == 0 || key == "$schema") continue;
    if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
      addIssue(issues_, Severity::Error, "schema.unknown_field", pointer(key),
               "unknown member \"" + key + "\" (misspelt? extensions must start with \"x-\")");
    }
  }
}

}  // namespace mapnav
