#include "mapnav/mission/blackboard.h"

#include <array>
#include <cmath>
#include <cstdio>

#include "mapnav/core/error.h"

namespace mapnav {

namespace {

constexpr std::array<std::pair<Module, std::string_view>, 8> kModules{{
    {Module::User, "User"},
    {Module::Sensors, "Sensors"},
    {Module::Map, "Map"},
    {Module::Vision, "Vision"},
    {Module::Navigator, "Navigator"},
    {Module::MotionControl, "MotionControl"},
    {Module::Blackboard, "Blackboard"},
    {Module::Mission, "Mission"},
}};

constexpr std::array<std::pair<TokenType, std::string_view>, 7> kTypes{{
    {TokenType::PredictedObject, "PredictedObject"},
    {TokenType::DetectedObject, "DetectedObject"},
    {TokenType::CurrentPosition, "CurrentPosition"},
    {TokenType::MotionCommand, "MotionCommand"},
    {TokenType::VisionFailure, "VisionFailure"},
    {TokenType::Halt, "Halt"},
    {TokenType::Resume, "Resume"},
}};

template <typename E, std::size_t N>
std::string_view nameOf(const std::array<std::pair<E, std::string_view>, N>& table, E value) {
  for (const auto& [e, name] : table) {
    if (e == value) return name;
  }
  return "?";
}

template <typename E, std::size_t N>
std::optional<E> valueOf(const std::array<std::pair<E, std::string_view>, N>& table, std::string_view text) {
  for (const auto& [e, name] : table) {
    if (name == text) return e;
  }
  return std::nullopt;
}

std::string seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", s);
  return text;
}

double timeOf(const PredictionToken& t) { return t.view.timestamp; }
template <typename T>
double timeOf(const T& t) {
  return t.timestamp;
}

}  // namespace

std::string_view toString(Module module) { return nameOf(kModules, module); }
std::optional<Module> moduleFromString(std::string_view text) { return valueOf(kModules, text); }
std::string_view toString(TokenType type) { return nameOf(kTypes, type); }
std::optional<TokenType> tokenTypeFromString(std::string_view text) { return valueOf(kTypes, text); }

std::string_view toString(CommandKind kind) { return kind == CommandKind::Drive ? "drive" : "stop"; }
std::optional<CommandKind> commandKindFromString(std::string_view text) {
  if (text == "drive") return CommandKind::Drive;
  if (text == "stop") return CommandKind::Stop;
  return std::nullopt;
}

TokenType tokenType(const Token& token) { return static_cast<TokenType>(token.index()); }

double tokenTime(const Token& token) {
  return std::visit([](const auto& t) { return timeOf(t); }, token);
}

const OptionTable<BlackboardOptions>& blackboardOptionTable() {
  using O = BlackboardOptions;
  static const OptionTable<O> table =
      OptionTable<O>("BlackboardOptions")
          .field("prediction_validity_s", &O::prediction_validity_s, above(0),
                 "a PredictedObject may be used this long after its timestamp, s")
          .field("detection_validity_s", &O::detection_validity_s, above(0), "... a DetectedObject, s")
          .field("position_validity_s", &O::position_validity_s, above(0), "... a CurrentPosition, s")
          .field("command_validity_s", &O::command_validity_s, above(0), "... a MotionCommand, s");
  return table;
}

void BlackboardOptions::validate() const { blackboardOptionTable().validate(*this); }

Blackboard::Blackboard(const BlackboardOptions& options) : options_(options) { options_.validate(); }

bool Blackboard::mayPost(Module from, TokenType type) {
  switch (type) {
    case TokenType::PredictedObject:
    case TokenType::CurrentPosition: return from == Module::Map;
    case TokenType::DetectedObject:
    case TokenType::VisionFailure:
    case TokenType::Halt: return from == Module::Vision;
    case TokenType::MotionCommand: return from == Module::Navigator;
    case TokenType::Resume: return from == Module::User;
  }
  return false;
}

bool Blackboard::mayRead(Module reader, TokenType type) {
  switch (type) {
    case TokenType::PredictedObject: return reader == Module::Vision || reader == Module::Map;
    case TokenType::DetectedObject: return reader == Module::Map;
    case TokenType::CurrentPosition:
      return reader == Module::Navigator || reader == Module::Map || reader == Module::MotionControl;
    case TokenType::MotionCommand: return reader == Module::MotionControl || reader == Module::Navigator;
    case TokenType::Halt:
      return reader == Module::Map || reader == Module::Vision || reader == Module::Navigator ||
             reader == Module::MotionControl || reader == Module::User;
    case TokenType::VisionFailure:
    case TokenType::Resume: return false;
  }
  return false;
}

void Blackboard::drop(double time, TokenType type, double token_time, std::string why) {
  if (on_drop_) on_drop_(Drop{time, type, token_time, std::move(why)});
}

bool Blackboard::post(Module from, Token token) {
  const TokenType type = tokenType(token);
  if (!mayPost(from, type)) {
    throw Error("blackboard: " + std::string(toString(from)) + " may not post a " + std::string(toString(type)));
  }
  const double t = tokenTime(token);
  auto stale = [&](const auto& slot) {
    if (!slot) return false;
    const double current = timeOf(*slot);
    if (t >= current) return false;
    drop(t, type, t, "stale: older than the current one (" + seconds(current) + " s)");
    return true;
  };
  Posting posting{from, token, 0};
  switch (type) {
    case TokenType::PredictedObject:
      if (stale(prediction_)) return false;
      prediction_ = std::get<PredictionToken>(std::move(token));
      break;
    case TokenType::DetectedObject:
      if (stale(detection_)) return false;
      detection_ = std::get<DetectedObject>(std::move(token));
      break;
    case TokenType::CurrentPosition:
      if (stale(position_)) return false;
      position_ = std::get<CurrentPosition>(std::move(token));
      break;
    case TokenType::MotionCommand: {
      if (stale(command_)) return false;
      MotionCommand c = std::get<MotionCommand>(std::move(token));
      if (command_) {
        if (c.sequence <= command_->sequence) {
          drop(t, type, t, "stale: sequence " + std::to_string(c.sequence) + " is not newer than " +
                               std::to_string(command_->sequence));
          return false;
        }
        posting.aborts = command_->sequence;  // "old steering plans aborted as the Navigator creates new ones"
      }
      command_ = std::move(c);
      break;
    }
    case TokenType::Halt: halt_ = std::get<Halt>(token); break;
    case TokenType::Resume: halt_.reset(); break;
    case TokenType::VisionFailure: break;
  }
  if (on_post_) on_post_(posting);
  return true;
}

template <typename T>
const T* Blackboard::read(std::optional<T>& slot, TokenType type, Module reader, double now, double validity) {
  if (!mayRead(reader, type)) {
    throw Error("blackboard: " + std::string(toString(reader)) + " may not read the " + std::string(toString(type)) +
                " (information hiding)");
  }
  if (!slot) return nullptr;
  const double t = timeOf(*slot);
  if (now - t > validity + 1e-9) {
    drop(now, type, t, "expired: " + seconds(now - t) + " s old, valid " + seconds(validity) + " s");
    slot.reset();
    return nullptr;
  }
  return &*slot;
}

const PredictedObject* Blackboard::prediction(Module reader, double now) {
  const PredictionToken* p = read(prediction_, TokenType::PredictedObject, reader, now, options_.prediction_validity_s);
  return p != nullptr ? &p->view : nullptr;
}

const DetectedObject* Blackboard::detection(Module reader, double now) {
  return read(detection_, TokenType::DetectedObject, reader, now, options_.detection_validity_s);
}

const CurrentPosition* Blackboard::position(Module reader, double now) {
  return read(position_, TokenType::CurrentPosition, reader, now, options_.position_validity_s);
}

const MotionCommand* Blackboard::command(Module reader, double now) {
  return read(command_, TokenType::MotionCommand, reader, now, options_.command_validity_s);
}

const Halt* Blackboard::halt(Module reader) const {
  if (!mayRead(reader, TokenType::Halt)) {
    throw Error("blackboard: " + std::string(toString(reader)) + " may not read the Halt");
  }
  return halt_ ? &*halt_ : nullptr;
}

}  // namespace mapnav
