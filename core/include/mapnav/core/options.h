#pragma once
// Checks of values that are not options: a function's arguments. Option structs state their rules in
// their tables (option_table.h); these are for the arguments of a call (`PathTracker(path, window_m)`).
#include <string_view>

namespace mapnav {

/// Throws InvalidInput "FUNCTION: ARGUMENT = VALUE: must be RULE" unless `ok` (VALUE with 17 digits).
void requireArgument(bool ok, std::string_view function, std::string_view argument, double value, std::string_view rule);

}  // namespace mapnav
