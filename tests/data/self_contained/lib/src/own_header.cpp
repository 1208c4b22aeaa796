#include "mapnav/lib/own_header.h"

std::string ownName() { return "own"; }
