#pragma once
// Ctrl-C (SIGINT) and SIGTERM without half-written outputs. The handler only records the signal
// (async-signal-safe); long loops (the mission runners, the simulator) call throwIfInterrupted()
// once a frame, and writeFileAtomic() checks before it renames, so an interrupted command unwinds
// like any failure: the temporary files and folders are removed by the code that made them and the
// previous outputs stay as they were. A second signal kills at once (the default action).
// Without installInterruptHandlers() (a library user), nothing here ever throws.
#include "mapnav/core/error.h"

namespace mapnav {

/// The command was interrupted by a signal. The CLI exits with 128 + the signal number.
class Interrupted : public Error {
 public:
  explicit Interrupted(int signal_number);
  int signalNumber() const { return signal_; }

 private:
  int signal_;
};

/// Installs the SIGINT and SIGTERM handlers (once a process; the CLI's main does it).
void installInterruptHandlers();

/// The signal received since the handlers were installed, 0 when none.
int interruptSignal();

/// Throws Interrupted when a signal was received.
void throwIfInterrupted();

}  // namespace mapnav
