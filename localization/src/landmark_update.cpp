// The pose filter's landmark update: range and bearing to a mapped landmark (pose_filter.h).
#include <cmath>

#include <Eigen/Cholesky>
#include <boost/math/distributions/chi_squared.hpp>

#include "mapnav/core/error.h"
#include "mapnav/localization/pose_filter.h"

namespace mapnav {

namespace {

void requireObservation(const LandmarkObservation& o) {
  const bool finite = o.map_world.allFinite() && o.origin_vehicle.allFinite() && std::isfinite(o.range_m) &&
                      std::isfinite(o.bearing_rad) && o.covariance.allFinite();
  const bool symmetric = std::abs(o.covariance(0, 1) - o.covariance(1, 0)) <= 1e-12 * (1 + o.covariance.norm());
  if (!finite || !symmetric || o.covariance.llt().info() != Eigen::Success) {
    throw InvalidInput("PoseFilter::updateLandmarks: landmark \"" + o.id +
                       "\": the measurement must be finite and its covariance symmetric positive definite");
  }
}

// The predicted (range, bearing) of the landmark from the pose (x, y, heading), and its Jacobian
// over (x, y, heading). d = R(h)^T (p - t) - o: the landmark from the origin, vehicle axes.
struct RangeBearing {
  Vec2 h;
  Eigen::Matrix<double, 2, 3> jacobian;
};

RangeBearing predictRangeBearing(const LandmarkObservation& o, const Pose2& pose) {
  const double c = std::cos(pose.heading()), s = std::sin(pose.heading());
  const Vec2 w = o.map_world - pose.translation();
  const Vec2 d = Vec2(c * w.x() + s * w.y(), -s * w.x() + c * w.y()) - o.origin_vehicle;
  const double r2 = d.squaredNorm(), r = std::sqrt(r2);
  Eigen::Matrix<double, 2, 3> dd;  // d(d) / d(x, y, heading)
  dd << -c, -s, -s * w.x() + c * w.y(),  //
      s, -c, -c * w.x() - s * w.y();
  Eigen::Matrix<double, 2, 2> dh;  // d(range, bearing) / d(d)
  dh << d.x() / r, d.y() / r, -d.y() / r2, d.x() / r2;
  return {Vec2(r, std::atan2(d.y(), d.x())), dh * dd};
}

}  // namespace

LandmarkUpdateResult PoseFilter::updateLandmarks(const std::vector<LandmarkObservation>& observations) {
  LandmarkUpdateResult result;
  step_.reset();
  const double limit = boost::math::quantile(boost::math::chi_squared_distribution<double>(2), options_.gate_probability);
  for (const LandmarkObservation& o : observations) {
    requireObservation(o);
    const RangeBearing predicted = predictRangeBearing(o, pose_);
    if (!(predicted.h.x() > 1e-6)) {  // the landmark at the origin itself: no bearing
      result.rejected.push_back(o.id);
      continue;
    }
    Eigen::Matrix<double, 2, kStateSize> h = Eigen::Matrix<double, 2, kStateSize>::Zero();
    h.leftCols<3>() = predicted.jacobian;
    const Vec2 innovation(o.range_m - predicted.h.x(), normalizeAngle(o.bearing_rad - predicted.h.y()));
    const Mat2 s = h * full_ * h.transpose() + o.covariance;
    const double d2 = innovation.dot(s.ldlt().solve(innovation));
    if (!(d2 <= limit)) {
      result.rejected.push_back(o.id);
      continue;
    }
    const Eigen::Matrix<double, kStateSize, 2> k = full_ * h.transpose() * s.inverse();
    const StateVector change = k * innovation;
    const StateMatrix i_kh = StateMatrix::Identity() - k * h;
    full_ = i_kh * full_ * i_kh.transpose() + k * o.covariance * k.transpose();  // Joseph form
    applyUpdate(change);
    result.information += predicted.jacobian.transpose() * o.covariance.inverse() * predicted.jacobian;
    result.used.push_back(o.id);
    along_since_fix_m_ = 0;
  }
  return result;
}

}  // namespace mapnav
