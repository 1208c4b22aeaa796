#include "mapnav/core/error.h"
#include "mapnav/map/map.h"
