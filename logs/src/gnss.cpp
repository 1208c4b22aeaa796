#include "mapnav/logs/gnss.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mapnav/core/error.h"

namespace mapnav {

const OptionTable<GnssReceiverOptions>& gnssReceiverOptionTable() {
  using O = GnssReceiverOptions;
  static const OptionTable<O> table =
      OptionTable<O>("GnssReceiverOptions")
          .field("seed", &O::seed, "the same seed gives the same errors")
          .field("sigma_m", &O::sigma_m, inRange(0, 1000), "white noise of each fix, 1-sigma per axis, m")
          .field("bias_sigma_m", &O::bias_sigma_m, inRange(0, 1000), "the drifting bias's steady 1-sigma per axis, m")
          .field("bias_time_s", &O::bias_time_s, aboveUpTo(0, 1e7), "the bias's correlation time, s");
  return table;
}

double GnssReceiverOptions::statedSigma() const { return std::hypot(sigma_m, bias_sigma_m); }

void GnssReceiverOptions::validate() const { gnssReceiverOptionTable().validate(*this); }

GnssReceiver::GnssReceiver(const GnssReceiverOptions& options) : options_(options), rng_(options.seed) {
  options_.validate();
}

GnssFix GnssReceiver::measure(const Vec2& truth, double t) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const double b = options_.bias_sigma_m;
  if (!last_t_) {
    bias_ = Vec2(b * unit(rng_), b * unit(rng_));
  } else {
    if (t < *last_t_)
      throw InvalidInput("GnssReceiver::measure: time went back from " + std::to_string(*last_t_) + " to " +
                         std::to_string(t) + " s");
    // Gauss-Markov over dt: keep exp(-dt/T) of the bias, add what keeps its variance at b².
    const double keep = std::exp(-(t - *last_t_) / options_.bias_time_s);
    const double fresh = b * std::sqrt(1.0 - keep * keep);
    bias_ = keep * bias_ + Vec2(fresh * unit(rng_), fresh * unit(rng_));
  }
  last_t_ = t;
  const Vec2 white(options_.sigma_m * unit(rng_), options_.sigma_m * unit(rng_));
  return GnssFix{truth + bias_ + white, std::max(0.05, options_.statedSigma())};
}

}  // namespace mapnav
