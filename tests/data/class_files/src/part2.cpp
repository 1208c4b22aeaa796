// Fixture of the Architecture.AClassInFourFiles* tests (scripts/class_files.py): one of four
// files that each define a member of Spread, which the check reports. Never compiled.
#include "../include/spread.h"

namespace fixture {

int Spread::part2() const { return 2; }

}  // namespace fixture
