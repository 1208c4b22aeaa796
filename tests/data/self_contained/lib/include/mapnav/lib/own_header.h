#pragma once
#include <string>

std::string ownName();
