#include <iostream>

#include "cli.h"

#include "mapnav/core/interrupt.h"

int main(int argc, char** argv) {
  mapnav::installInterruptHandlers();  // Ctrl-C leaves the previous outputs as they were
  return mapnav::cli::run(argc, argv, std::cout, std::cerr);
}
