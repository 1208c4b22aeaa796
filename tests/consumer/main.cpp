// Loads a map through the installed mapnav and prints its road count.
#include <iostream>

#include "mapnav/map/map_io.h"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const mapnav::Map map = mapnav::loadMap(argv[1]);
  std::cout << map.roads().size() << " roads\n";
  return 0;
}
