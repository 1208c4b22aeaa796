#pragma once
// Fixture of the Architecture.AClassInFourFiles* tests (scripts/class_files.py). Never compiled.

namespace fixture {

/// Its members are defined in four files (src/part*.cpp): one too many.
class Spread {
 public:
  int part1() const;
  int part2() const;
  int part3() const;
  int part4() const;
};

/// Its members are defined in one file (src/other.cpp).
class Whole {
 public:
  Whole();
  int size() const;
};

namespace detail {
int helper();  // a free function: detail:: is a namespace, not a class
}  // namespace detail

}  // namespace fixture
