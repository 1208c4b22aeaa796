#include "mapnav/geometry/types.h"
