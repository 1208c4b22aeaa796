// The Map module's integrity monitor: innovations and the departure from odometry (integrity.h).
#include "mapnav/localization/integrity.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <boost/math/distributions/chi_squared.hpp>

#include "mapnav/core/strprintf.h"

namespace mapnav {

const OptionTable<IntegrityOptions>& integrityOptionTable() {
  using O = IntegrityOptions;
  static const OptionTable<O> table =
      OptionTable<O>("IntegrityOptions")
          .field("window_frames", &O::window_frames, atLeast(0),
                 "frames with lines whose rejections by the gate are counted (0: no innovation test)")
          .field("probability", &O::probability, OptionRule{.min = 0, .max = 1, .min_open = true, .max_open = true},
                 "uncertain when so many rejections would happen to a consistent filter with less than 1 - this")
          .field("max_unobserved_m", &O::max_unobserved_m, above(0),
                 "the distance over which observed frames are counted, m")
          .field("min_observed_fraction", &O::min_observed_fraction, OptionRule{.min = 0, .max = 1},
                 "uncertain when fewer of those frames observed the position (0: no such test)")
          .field("departure_probability", &O::departure_probability,
                 OptionRule{.min = 0, .max = 1, .min_open = true},
                 "the departure-from-odometry test's chi-square(3) quantile (1: no departure test)")
          .field("anchor_every_m", &O::anchor_every_m, above(0),
                 "while consistent, the dead reckoning restarts from the estimate after this distance, m");
  return table;
}

void IntegrityOptions::validate() const { integrityOptionTable().validate(*this); }

std::string_view toString(IntegrityVerdict::State state) {
  switch (state) {
    case IntegrityVerdict::State::Ok: return "ok";
    case IntegrityVerdict::State::Uncertain: return "uncertain";
    case IntegrityVerdict::State::Departed: return "departed";
  }
  return "ok";
}

namespace {

double chi2Quantile(int dof, double probability) {
  return boost::math::quantile(boost::math::chi_squared_distribution<double>(dof), probability);
}

// P(X >= k) for X ~ Binomial(n, p).
double binomialTail(int n, int k, double p) {
  double tail = 0;
  for (int i = k; i <= n; ++i) {
    tail += std::exp(std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) + i * std::log(p) +
                     (n - i) * std::log1p(-p));
  }
  return tail;
}

// The dead reckoning: the filter's state, odometry alone from here (no map error to follow).
PoseFilter deadReckoningFrom(const PoseFilter& filter) {
  PoseFilter copy = filter;
  copy.setMapSigma(0);
  return copy;
}

}  // namespace

IntegrityMonitor::IntegrityMonitor(const PoseFilter& filter, const IntegrityOptions& options)
    : options_(options), dead_reckoning_(deadReckoningFrom(filter)) {
  options_.validate();
}

void IntegrityMonitor::predict(const MotionIncrement& motion, double dt_s) {
  dead_reckoning_.predict(motion, dt_s);
  since_anchor_m_ += std::abs(motion.distance_m);
  last_distance_m_ = motion.distance_m;
}

void IntegrityMonitor::anchor(const PoseFilter& filter) {
  dead_reckoning_ = deadReckoningFrom(filter);
  since_anchor_m_ = 0;
}

IntegrityVerdict IntegrityMonitor::observe(const CurrentPosition& position, const PoseFilter& filter) {
  IntegrityVerdict v;
  v.dead_reckoned = dead_reckoning_.pose();
  v.dead_reckoned_covariance = dead_reckoning_.covariance();

  // Departure: the estimate against the dead reckoning, both covariances and the map's error.
  if (options_.departure_probability < 1) {
    const Pose2& e = filter.pose();
    const Vec3 d(e.x() - v.dead_reckoned.x(), e.y() - v.dead_reckoned.y(),
                 normalizeAngle(e.heading() - v.dead_reckoned.heading()));
    const Mat3 s = filter.covariance() + filter.mapCovariance() + v.dead_reckoned_covariance;
    const Eigen::LDLT<Mat3> ldlt(s);
    v.departure_d2 = d.dot(ldlt.solve(d));
    v.departure_bound = chi2Quantile(3, options_.departure_probability);
    if (!(v.departure_d2 <= v.departure_bound)) {
      v.state = IntegrityVerdict::State::Departed;
      v.reason = strprintf("the estimate departed from odometry by %.2f m and %.1f deg (Mahalanobis d^2 = %.1f > %.1f)",
                           d.head<2>().norm(), radToDeg(std::abs(d(2))), v.departure_d2, v.departure_bound);
      window_.clear();
      for (Recent& r : recent_) r.observed = false;
      return v;
    }
  }

  // Innovations: the gate's rejections among the last window_frames frames with lines.
  if (options_.window_frames > 0 && position.gate_dof > 0) {
    window_.push_back(position.status == PositionStatus::Rejected);
    while (window_.size() > static_cast<std::size_t>(options_.window_frames)) window_.pop_front();
  }
  v.rejections = static_cast<int>(std::count(window_.begin(), window_.end(), true));
  const double p_reject = 1 - filter.options().gate_probability;
  if (v.rejections > 0 && binomialTail(static_cast<int>(window_.size()), v.rejections, p_reject) < 1 - options_.probability) {
    v.state = IntegrityVerdict::State::Uncertain;
    v.reason = strprintf("position uncertain: the gate rejected the lines of %d of the last %zu frames with lines",
                         v.rejections, window_.size());
  }
  // Rarely observed: the frames of the last max_unobserved_m driven, and how many fixed the position
  // across or along the road (a heading alone does not). After a departure, none did.
  const bool observed = position.observed_lateral || position.observed_along || position.landmarks_used > 0;
  recent_.push_back({std::abs(last_distance_m_), observed});
  double driven = 0;
  for (const Recent& r : recent_) driven += r.distance_m;
  while (recent_.size() > 1 && driven - recent_.front().distance_m >= options_.max_unobserved_m) {
    driven -= recent_.front().distance_m;
    recent_.pop_front();
  }
  const auto seen = std::count_if(recent_.begin(), recent_.end(), [](const Recent& r) { return r.observed; });
  v.observed_fraction = static_cast<double>(seen) / static_cast<double>(recent_.size());
  if (v.state == IntegrityVerdict::State::Ok && driven >= options_.max_unobserved_m &&
      v.observed_fraction < options_.min_observed_fraction) {
    v.state = IntegrityVerdict::State::Uncertain;
    v.reason = strprintf("position uncertain: observed in %lld of the %zu frames of the last %.0f m",
                         static_cast<long long>(seen), recent_.size(), driven);
  }
  if (v.state == IntegrityVerdict::State::Ok && since_anchor_m_ >= options_.anchor_every_m) anchor(filter);
  return v;
}

}  // namespace mapnav
