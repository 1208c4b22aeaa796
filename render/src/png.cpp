#include "mapnav/render/canvas.h"
