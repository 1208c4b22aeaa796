#pragma once
// Log colour: an 8-bit channel level c as 255 ln(c + 1) / ln 256, in 0..255 like the level itself.
// A shadow scales a colour's channels by one factor k (Wallace 1985, 3.4.3: C1 = k C2); in log colour
// that is a shift by 255 ln k / ln 256 along the grey axis, the same for every colour, so a class
// spread along that axis covers a surface in sun and shade without covering every grey. Used by the
// colour classifier (ColorSpace::LogRGB) and the cluster-perceptron (log_color).
#include <array>
#include <cmath>

namespace mapnav::log_colour {

/// 255 / ln 256: the factor from ln(c + 1) to log-colour levels.
inline constexpr double kScale = 255.0 / 5.545177444479562;

/// The log colour of every level 0..255, in double (exact to double rounding).
inline const std::array<double, 256>& table() {
  static const std::array<double, 256> t = [] {
    std::array<double, 256> a{};
    for (int c = 0; c < 256; ++c) a[c] = kScale * std::log(c + 1.0);
    return a;
  }();
  return t;
}

/// The same values in single precision, for the vectorised fast paths.
inline const std::array<float, 256>& tableF() {
  static const std::array<float, 256> t = [] {
    std::array<float, 256> a{};
    for (int c = 0; c < 256; ++c) a[c] = static_cast<float>(table()[c]);
    return a;
  }();
  return t;
}

/// The log colour of a level c >= 0 that need not be an integer (the table's value where it is).
inline double of(double c) {
  const int i = static_cast<int>(c);
  return i == c && i >= 0 && i < 256 ? table()[i] : kScale * std::log(c + 1.0);
}

/// The level whose log colour is x (the inverse of of()).
inline double level(double x) { return std::exp(x / kScale) - 1.0; }

}  // namespace mapnav::log_colour
