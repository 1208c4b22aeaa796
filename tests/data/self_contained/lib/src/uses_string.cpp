// Needs <string> and does not include it: compiles only after first.cpp in a unity batch.
std::string secondName() { return "second"; }
