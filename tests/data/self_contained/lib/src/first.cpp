#include <string>

std::string firstName() { return "first"; }
