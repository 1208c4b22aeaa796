#pragma once
// VisionFailure and Halt: Vision → all (Wallace 1985, 4): "the Vision system halts and signals the
// blackboard so that another module (or person) [can] take control".
#include <cstddef>
#include <optional>
#include <string>

namespace mapnav {

/// Vision → all: the frame could not be used.
struct VisionFailure {
  double timestamp = 0;
  std::string reason;  ///< the pipeline's ("frame too dark", "no road-coloured region", ...)
};

/// Vision → all: motion stops until another module or a person takes control.
struct Halt {
  double timestamp = 0;
  std::string reason;
  std::string control_to = "operator";   ///< who must take over
  std::optional<std::size_t> resume_after_frames;  ///< the mission's policy (nothing: never)
};

}  // namespace mapnav
