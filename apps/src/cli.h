#pragma once
#include <iosfwd>

namespace mapnav::cli {

/// Exit codes of every command, by the kind of mistake (docs/architecture.md, Conventions): 0
/// success; 1 what was given is wrong (out of range, malformed, an invalid map, an unknown id); 2 the
/// command line itself is wrong (an unknown flag, a missing argument, not a number) or a file cannot
/// be read or written.
enum ExitCode : int { kOk = 0, kInvalid = 1, kUsage = 2 };

/// Parses the command line and runs the command. Never throws.
int run(int argc, char** argv, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
