#pragma once
// The blackboard (Wallace 1985, 2.1 and 4): the four modules — Map, Vision, Navigator, Motion
// Control — talk only through typed, timestamped tokens posted here. "Timestamps on data carried
// through the entire system enable the vehicle to be controlled in real time, with old steering
// plans aborted as the Navigator creates new ones."
//
// Information hiding is enforced, not just documented: every token type has the modules that may
// post it and the modules that may read it, and anything else throws. Vision may read only the
// PredictedObject (never the CurrentPosition, the route or a command); the PredictedObject it gets
// carries no world coordinates.
//
// Lifetime: the blackboard keeps the newest token of each type. A token posted with an older
// timestamp than the one it would replace is dropped as stale; a newer MotionCommand aborts the older
// one; a token older than its type's validity is dropped when read. Every post and every drop is
// reported to the listener (the trace).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/navigator/route.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/tokens/current_position.h"
#include "mapnav/tokens/detected_object.h"
#include "mapnav/tokens/predicted_object.h"
#include "mapnav/tokens/vision_failure.h"

namespace mapnav {

/// Who speaks. The four modules of the paper, the person (user / operator), and the blackboard
/// itself (drops). Sensors and Mission appear only in the trace (frames, the header and summary).
enum class Module { User, Sensors, Map, Vision, Navigator, MotionControl, Blackboard, Mission };
std::string_view toString(Module module);
std::optional<Module> moduleFromString(std::string_view text);

enum class TokenType { PredictedObject, DetectedObject, CurrentPosition, MotionCommand, VisionFailure, Halt, Resume };
std::string_view toString(TokenType type);
std::optional<TokenType> tokenTypeFromString(std::string_view text);

/// Map → Vision. Vision reads `view` only; `made_for` is the Map's own record of the pose the view
/// was predicted from (for the trace), never handed to Vision.
struct PredictionToken {
  PredictedObject view;
  Pose2 made_for;
};

enum class CommandKind {
  Drive,  ///< follow `path`
  Stop,   ///< stand still (halted, or nowhere to go)
};
std::string_view toString(CommandKind kind);
std::optional<CommandKind> commandKindFromString(std::string_view text);

/// Navigator → Motion Control: "Drive on it 2.5 meters and turn to right 90 degrees", with the
/// steering plan that carries it out. A newer command aborts every older one.
struct MotionCommand {
  std::uint64_t sequence = 0;  ///< 1, 2, ... per run; set by the Navigator
  double timestamp = 0;        ///< of the CurrentPosition it was planned from, s
  CommandKind kind = CommandKind::Drive;
  std::string reason;          ///< Stop: why ("vision failed: halted", "goal reached")
  // The dialogue.
  std::string road;               ///< the road being driven
  double drive_m = 0;             ///< to drive on it before the next turn (or the goal), m
  std::optional<Leg> next_turn;   ///< the turn after that; nothing: the goal comes next
  bool same_road = false;         ///< `road` is the road of the previous command ("Drive on it")
  // The steering plan.
  std::vector<Vec2> path;         ///< world frame: the route's centre line from just behind the vehicle ahead
  bool path_ends_at_goal = false; ///< the path's last point is the goal: stop there
  /// The path's last point is where the route turns around (an out-and-back via point): stop there;
  /// the next plan starts there, back the way it came, and the vehicle turns around in place.
  bool path_ends_at_turn = false;
  double speed_mps = 0;           ///< cruise speed
  VehicleCommand setpoint;        ///< pure pursuit at the estimated pose it was planned from
  Vec2 lookahead_point = Vec2::Zero();  ///< that pursuit's goal point, world frame
};

/// User (the operator) → all: control handed back to the modules after a halt.
struct Resume {
  double timestamp = 0;
  std::size_t frames_halted = 0;
};

using Token = std::variant<PredictionToken, DetectedObject, CurrentPosition, MotionCommand, VisionFailure, Halt, Resume>;
TokenType tokenType(const Token& token);
double tokenTime(const Token& token);

/// One post, as the listener sees it.
struct Posting {
  Module from = Module::Blackboard;
  Token token;
  /// MotionCommand: the sequence number of the command it aborted (0: none).
  std::uint64_t aborts = 0;
};

/// A token the blackboard dropped.
struct Drop {
  double time = 0;        ///< when it was dropped (the reader's "now", or the stale post's time), s
  TokenType type = TokenType::PredictedObject;
  double token_time = 0;  ///< the token's own timestamp, s
  std::string why;        ///< "expired: 3.0 s old, valid 1.5 s", "stale: older than the current one"
};

struct BlackboardOptions {
  /// How long a token of each type may be used after its timestamp, s (> 0). Defaults for a 2 Hz
  /// loop; the runners set them from the frame period (runner.h).
  double prediction_validity_s = 1.0;
  double detection_validity_s = 1.0;
  double position_validity_s = 1.0;
  double command_validity_s = 1.5;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<BlackboardOptions>& blackboardOptionTable();

class Blackboard {
 public:
  using PostListener = std::function<void(const Posting&)>;
  using DropListener = std::function<void(const Drop&)>;

  explicit Blackboard(const BlackboardOptions& options = {});

  void onPost(PostListener listener) { on_post_ = std::move(listener); }
  void onDrop(DropListener listener) { on_drop_ = std::move(listener); }

  /// Posts a token. Throws Error when `from` may not post this type (only Map posts predictions and
  /// positions, only Vision detections, failures and halts, only the Navigator commands, only the
  /// User resumes). A token older than the one it would replace is dropped (reported) and false is
  /// returned. A Halt stays until a Resume clears it.
  bool post(Module from, Token token);

  /// The newest token of the type, if still valid at `now`; one older than its validity is dropped
  /// (reported) and nothing is returned. Throws Error when `reader` may not read the type:
  ///   PredictedObject: Vision, Map       DetectedObject: Map
  ///   CurrentPosition: Navigator, Map, MotionControl      MotionCommand: MotionControl, Navigator
  ///   Halt: every module               (VisionFailure and Resume are events: only listeners see them)
  const PredictedObject* prediction(Module reader, double now);
  const DetectedObject* detection(Module reader, double now);
  const CurrentPosition* position(Module reader, double now);
  const MotionCommand* command(Module reader, double now);
  /// The halt in force, if any (a halt does not expire).
  const Halt* halt(Module reader) const;

  /// Whether `reader` may read tokens of `type` (the table above).
  static bool mayRead(Module reader, TokenType type);
  static bool mayPost(Module from, TokenType type);

  const BlackboardOptions& options() const { return options_; }

 private:
  template <typename T>
  const T* read(std::optional<T>& slot, TokenType type, Module reader, double now, double validity);
  void drop(double time, TokenType type, double token_time, std::string why);

  BlackboardOptions options_;
  PostListener on_post_;
  DropListener on_drop_;
  std::optional<PredictionToken> prediction_;
  std::optional<DetectedObject> detection_;
  std::optional<CurrentPosition> position_;
  std::optional<MotionCommand> command_;
  std::optional<Halt> halt_;
};

}  // namespace mapnav
