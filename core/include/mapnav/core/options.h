#pragma once
// Validation of option structs (as Ceres' Solver::Options::IsValid): every `validate()` names the
// struct, the field and its value in the same words.
#include <string_view>

namespace mapnav {

/// Throws InvalidInput "OWNER::FIELD = VALUE: must be RULE" unless `ok`.
void requireOption(bool ok, std::string_view owner, std::string_view field, double value, std::string_view rule);

}  // namespace mapnav
