#include "mapnav/core/options.h"

#include <sstream>

#include "mapnav/core/error.h"

namespace mapnav {

void requireOption(bool ok, std::string_view owner, std::string_view field, double value, std::string_view rule) {
  if (ok) return;
  std::ostringstream text;
  text.precision(17);
  text << owner << "::" << field << " = " << value << ": must be " << rule;
  throw InvalidInput(text.str());
}

}  // namespace mapnav
