#include "mapnav/core/options.h"

#include <sstream>
#include <string>

#include "mapnav/core/error.h"

namespace mapnav {

void requireArgument(bool ok, std::string_view function, std::string_view argument, double value, std::string_view rule) {
  if (ok) return;
  std::ostringstream text;
  text.precision(17);
  text << function << ": " << argument << " = " << value << ": must be " << rule;
  throw InvalidInput(text.str());
}

}  // namespace mapnav
