// Fixture of the Architecture.AClassInFourFiles* tests: a class in one file, a function in a
// namespace (not a class), neither reported. Never compiled.
#include "../include/spread.h"

namespace fixture {

Whole::Whole() = default;
int Whole::size() const { return 1; }
int detail::helper() { return 2; }

}  // namespace fixture
