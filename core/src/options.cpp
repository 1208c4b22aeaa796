#include "mapnav/core/options.h"

#include <sstream>
#include <string>

#include "mapnav/core/error.h"

namespace mapnav {

namespace {

std::string broken(std::string_view who, std::string_view separator, std::string_view what, double value,
                   std::string_view rule) {
  std::ostringstream text;
  text.precision(17);
  text << who << separator << what << " = " << value << ": must be " << rule;
  return text.str();
}

}  // namespace

void requireArgument(bool ok, std::string_view function, std::string_view argument, double value, std::string_view rule) {
  if (!ok) throw InvalidInput(broken(function, ": ", argument, value, rule));
}

void requireOption(bool ok, std::string_view owner, std::string_view field, double value, std::string_view rule) {
  if (!ok) throw InvalidInput(broken(owner, "::", field, value, rule));
}

}  // namespace mapnav
