#pragma once
// Needs <vector> and does not include it.
inline std::vector<int> none() { return {}; }
