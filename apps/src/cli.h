#pragma once
#include <iosfwd>

namespace mapnav::cli {

/// Exit codes of every command (ARCHITECTURE.md): 0 success, 1 the input was understood and is
/// wrong, 2 usage or I/O error.
enum ExitCode : int { kOk = 0, kInvalid = 1, kUsage = 2 };

/// Parses the command line and runs the command. Never throws.
int run(int argc, char** argv, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
