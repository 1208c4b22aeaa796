// The pose filter: odometry prediction, the gate and the iterated EKF update (pose_filter.h).
#include "mapnav/localization/pose_filter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/Eigenvalues>
#include <boost/math/distributions/chi_squared.hpp>

#include "line_problem.h"
#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"

namespace mapnav {

using namespace localization::detail;

const OptionTable<MotionNoiseOptions>& motionNoiseOptionTable() {
  using O = MotionNoiseOptions;
  static const OptionTable<O> table =
      OptionTable<O>("MotionNoiseOptions")
          .field("scale_sigma", &O::scale_sigma, atLeast(0),
                 "a priori 1-sigma of the encoders' relative scale error, the state e (0: not estimated)")
          .field("gyro_bias_sigma_deg_s", &O::gyro_bias_sigma_deg_s, atLeast(0),
                 "a priori 1-sigma of the gyro's bias, the state b, deg/s (0: not estimated)")
          .field("gyro_noise_deg_per_sqrt_s", &O::gyro_noise_deg_per_sqrt_s, atLeast(0),
                 "angle random walk: the heading variance grows by this^2 per second, deg per sqrt(s)")
          .field("distance_sigma_per_m", &O::distance_sigma_per_m, atLeast(0),
                 "random distance error per metre driven, m/m")
          .field("heading_sigma_per_rad", &O::heading_sigma_per_rad, atLeast(0),
                 "heading sigma per radian turned, rad/rad")
          .field("heading_sigma_per_m", &O::heading_sigma_per_m, atLeast(0), "heading sigma per metre driven, rad/m")
          .field("base_sigma_m", &O::base_sigma_m, atLeast(0), "added to x and y every step, m")
          .field("base_heading_sigma_rad", &O::base_heading_sigma_rad, atLeast(0),
                 "added to the heading every step, rad");
  return table;
}

void MotionNoiseOptions::validate() const { motionNoiseOptionTable().validate(*this); }

const OptionTable<FilterOptions>& filterOptionTable() {
  using O = FilterOptions;
  static const OptionTable<O> table =
      OptionTable<O>("FilterOptions")
          .field("gate_probability", &O::gate_probability,
                 OptionRule{.min = 0, .max = 1, .min_open = true, .max_open = true},
                 "measurements beyond the chi-square quantile of this probability are rejected")
          .field("frame_sigma_m", &O::frame_sigma_m, atLeast(0),
                 "the error all lines of a frame share, position 1-sigma, m (0: lines independent)")
          .field("frame_heading_sigma_deg", &O::frame_heading_sigma_deg, atLeast(0), "... heading 1-sigma, degrees")
          .field("update_iterations", &O::update_iterations, atLeast(1),
                 "iterated EKF: relinearisations of the update at most (1: a plain EKF update)")
          .field("map_correlation_m", &O::map_correlation_m, above(0),
                 "how far along a road the map's error stays alike, m (its correlation length)")
          .field("gnss_bias_sigma_m", &O::gnss_bias_sigma_m, atLeast(0),
                 "the GNSS receiver's slowly drifting error, steady 1-sigma per axis, m (0: fixes independent)")
          .field("gnss_bias_time_s", &O::gnss_bias_time_s, above(0), "... its correlation time, s");
  return table;
}

void FilterOptions::validate() const {
  match.validate();
  motion.validate();
  filterOptionTable().validate(*this);
}

namespace {

// The frame's shared error R: with r = J dx + J c + noise, c ~ N(0, R), the lines' information A and
// gradient g become M A and M g with M = (I + A R)^-1 (Woodbury: (A^-1 + R)^-1 = M A). Returns M.
Mat3 sharedErrorFactor(const Mat3& a, const Mat3& frame_error) { return (Mat3::Identity() + a * frame_error).inverse(); }

// M A, symmetrised, as the information on the full state.
StateMatrix fullInformation(const Mat3& m, const Mat3& a) {
  StateMatrix full = StateMatrix::Zero();
  full.topLeftCorner<3, 3>() = m * a;
  return 0.5 * (full + full.transpose());
}

void requireCovariance(const Mat3& covariance) {
  const bool symmetric = (covariance - covariance.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * (1 + covariance.norm());
  if (!covariance.allFinite() || !symmetric || covariance.llt().info() != Eigen::Success) {
    throw InvalidInput("PoseFilter: the covariance must be finite, symmetric and positive definite");
  }
}

}  // namespace

PoseFilter::PoseFilter(const Pose2& pose, const Mat3& covariance, const FilterOptions& options)
    : pose_(pose), covariance_(covariance), options_(options) {
  options_.validate();
  requireCovariance(covariance);
  full_ = StateMatrix::Zero();
  full_.topLeftCorner<3, 3>() = covariance;
  full_(3, 3) = std::pow(options_.motion.scale_sigma, 2);
  full_(4, 4) = std::pow(degToRad(options_.motion.gyro_bias_sigma_deg_s), 2);
  full_(5, 5) = full_(6, 6) = std::pow(options_.gnss_bias_sigma_m, 2);
}

void PoseFilter::resetPoseCovariance(const Mat3& covariance) {
  requireCovariance(covariance);
  full_.topRightCorner<3, kStateSize - 3>().setZero();
  full_.bottomLeftCorner<kStateSize - 3, 3>().setZero();
  full_.topLeftCorner<3, 3>() = covariance;
  covariance_ = covariance;
  step_.reset();
}

MotionIncrement PoseFilter::corrected(const MotionIncrement& motion, double dt_s) const {
  return MotionIncrement{(1 + scale_error_) * motion.distance_m, motion.dheading_rad - gyro_bias_ * dt_s};
}

void PoseFilter::predict(const MotionIncrement& motion, double dt_s) {
  if (!(std::isfinite(dt_s) && dt_s >= 0)) throw InvalidInput(strprintf("PoseFilter::predict: dt_s = %g must be finite and >= 0", dt_s));
  // The reading corrected by the estimated systematic errors.
  const MotionIncrement c_motion = corrected(motion, dt_s);
  const double d = c_motion.distance_m, dh = c_motion.dheading_rad;
  const double hm = pose_.heading() + 0.5 * dh;  // the mid-step heading
  const double c = std::cos(hm), s = std::sin(hm);
  StateMatrix f = StateMatrix::Identity();  // d(new state) / d(state)
  f(0, 2) = -d * s;
  f(1, 2) = d * c;
  f(0, 3) = motion.distance_m * c;  // d / de
  f(1, 3) = motion.distance_m * s;
  f(0, 4) = 0.5 * d * s * dt_s;     // d / db, through the mid-step heading
  f(1, 4) = -0.5 * d * c * dt_s;
  f(2, 4) = -dt_s;
  // The receiver's bias forgets itself (first-order Gauss-Markov), its steady variance kept.
  const double phi = std::exp(-dt_s / options_.gnss_bias_time_s);
  f(5, 5) = f(6, 6) = phi;
  Eigen::Matrix<double, kStateSize, 2> g = Eigen::Matrix<double, kStateSize, 2>::Zero();  // d(new state) / d(distance, heading change)
  g.topRows<3>() << c, -0.5 * d * s, s, 0.5 * d * c, 0, 1;
  const MotionNoiseOptions& m = options_.motion;
  const double var_d = std::pow(m.distance_sigma_per_m * d, 2);
  const double var_h = std::pow(m.heading_sigma_per_rad * dh, 2) + std::pow(m.heading_sigma_per_m * d, 2) +
                       std::pow(degToRad(m.gyro_noise_deg_per_sqrt_s), 2) * dt_s;
  // The map's direction error changes as the vehicle drives (setMapSigma).
  const double l = options_.map_correlation_m, slope = map_sigma_m_ / l;
  const double var_map = 2 * slope * slope * (1 - std::exp(-std::abs(d) / l));
  const Mat2 q = Eigen::Vector2d(var_d, var_h + var_map).asDiagonal();
  StateMatrix base = StateMatrix::Zero();
  base.diagonal().head<3>() << m.base_sigma_m * m.base_sigma_m, m.base_sigma_m * m.base_sigma_m,
      m.base_heading_sigma_rad * m.base_heading_sigma_rad;
  base(5, 5) = base(6, 6) = std::pow(options_.gnss_bias_sigma_m, 2) * (1 - phi * phi);
  full_ = f * full_ * f.transpose() + g * q * g.transpose() + base;
  if (map_sigma_m_ > 0) {
    const double l2 = 2 * options_.map_correlation_m * options_.map_correlation_m;
    const double d0 = along_since_fix_m_, d1 = d0 + std::abs(d);
    const double grow = 2 * map_sigma_m_ * map_sigma_m_ * (std::exp(-d0 * d0 / l2) - std::exp(-d1 * d1 / l2));
    const Vec3 a(c, s, 0);
    full_.topLeftCorner<3, 3>() += grow * a * a.transpose();
    along_since_fix_m_ = d1;
  }
  full_ = 0.5 * (full_ + full_.transpose());
  covariance_ = full_.topLeftCorner<3, 3>();
  pose_ = Pose2(pose_.x() + d * c, pose_.y() + d * s, pose_.heading() + dh);
  gnss_bias_ *= phi;
  step_ = Step{motion.distance_m, var_d, g.col(0)};
}

bool PoseFilter::updateStep(double measured_m, double variance) {
  if (!std::isfinite(measured_m) || !(std::isfinite(variance) && variance > 0)) {
    throw InvalidInput(strprintf("PoseFilter::updateStep: measured %g m with variance %g: both must be finite, the variance > 0",
                                 measured_m, variance));
  }
  if (!step_) return false;
  const Step step = *step_;
  step_.reset();
  // z = (1 + e) reading + w: w, the step's random distance error, moved the state by effect * w.
  StateVector h = StateVector::Zero();
  h(3) = step.reading_m;
  const StateVector cross = full_ * h + step.effect * step.variance;  // Cov(state, z)
  const double s = h.dot(full_ * h) + 2 * h.dot(step.effect) * step.variance + step.variance + variance;
  const double innovation = measured_m - (1 + scale_error_) * step.reading_m;
  const double limit = boost::math::quantile(boost::math::chi_squared_distribution<double>(1), options_.gate_probability);
  if (!(innovation * innovation / s <= limit)) return false;
  const StateVector k = cross / s;
  full_ -= k * cross.transpose();
  applyUpdate(k * innovation);
  return true;
}

bool PoseFilter::updatePosition(const Vec2& fix, double sigma_m) {
  if (!fix.allFinite() || !(std::isfinite(sigma_m) && sigma_m > 0)) {
    throw InvalidInput(strprintf("PoseFilter::updatePosition: fix (%g, %g) m with sigma %g m: all must be finite, the sigma > 0",
                                 fix.x(), fix.y(), sigma_m));
  }
  step_.reset();
  // z = (x, y) + (gx, gy) + v, v ~ N(0, white² I): H = [I 0 0 0 I].
  const double bias2 = std::pow(options_.gnss_bias_sigma_m, 2), stated2 = sigma_m * sigma_m;
  const double white2 = std::max(stated2 - bias2, 0.25 * stated2);
  const Eigen::Matrix<double, kStateSize, 2> cross = full_.leftCols<2>() + full_.rightCols<2>();  // P H^T
  // The state is the pose relative to the map, the fix the pose in the world: the map's error adds.
  const Eigen::Matrix2d s = cross.topRows<2>() + cross.bottomRows<2>() + mapCovariance().topLeftCorner<2, 2>() +
                            white2 * Eigen::Matrix2d::Identity();
  const Eigen::Vector2d innovation = fix - pose_.translation() - gnss_bias_;
  const double limit = boost::math::quantile(boost::math::chi_squared_distribution<double>(2), options_.gate_probability);
  if (!(innovation.dot(s.ldlt().solve(innovation)) <= limit)) return false;
  const Eigen::Matrix<double, kStateSize, 2> k = cross * s.inverse();
  full_ -= k * cross.transpose();
  applyUpdate(k * innovation);
  return true;
}

void PoseFilter::applyUpdate(const StateVector& change) {
  full_ = 0.5 * (full_ + full_.transpose());
  covariance_ = full_.topLeftCorner<3, 3>();
  pose_ = Pose2(pose_.x() + change(0), pose_.y() + change(1), pose_.heading() + change(2));
  scale_error_ += change(3);
  gyro_bias_ += change(4);
  gnss_bias_ += change.tail<2>();
}

void PoseFilter::setMapSigma(double sigma_m) {
  if (!(std::isfinite(sigma_m) && sigma_m >= 0)) {
    throw InvalidInput(strprintf("PoseFilter::setMapSigma: sigma %g m must be finite and >= 0", sigma_m));
  }
  map_sigma_m_ = sigma_m;
}

Mat3 PoseFilter::mapCovariance() const {
  const double s = map_sigma_m_, h = map_sigma_m_ / options_.map_correlation_m;
  return Vec3(s * s, s * s, h * h).asDiagonal();
}

CurrentPosition PoseFilter::current(double timestamp, std::string reason) const {
  CurrentPosition out;
  out.timestamp = timestamp;
  out.pose = pose_;
  out.covariance = covariance_;
  out.map_covariance = mapCovariance();
  out.status = PositionStatus::OdometryOnly;
  out.reason = std::move(reason);
  return out;
}

namespace {

std::string joined(const std::vector<std::string>& ids) {
  std::string out;
  for (const std::string& id : ids) out += (out.empty() ? "" : ", ") + id;
  return out;
}

// The directions a line fit observes: U, the eigenvectors of its information whose eigenvalue is at
// least min_information (and > 0), one column each, and the fit's variance 1 / eigenvalue along
// each. No column when the lines constrain no direction.
struct ObservedDirections {
  Eigen::MatrixXd u;
  Eigen::VectorXd fit_variance;
};

ObservedDirections observedDirections(const Mat3& information, double min_information) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(information);
  std::vector<int> kept;
  for (int i = 0; i < 3; ++i) {
    if (eig.eigenvalues()(i) >= min_information && eig.eigenvalues()(i) > 0) kept.push_back(i);
  }
  const int dof = static_cast<int>(kept.size());
  ObservedDirections out{Eigen::MatrixXd(3, dof), Eigen::VectorXd(dof)};
  for (int i = 0; i < dof; ++i) {
    out.u.col(i) = eig.eigenvectors().col(kept[static_cast<std::size_t>(i)]);
    out.fit_variance(i) = 1.0 / eig.eigenvalues()(kept[static_cast<std::size_t>(i)]);
  }
  return out;
}

// The frame's shared error R over (x, y, heading): m², m², rad², shared by the frame's lines.
Mat3 frameError(const FilterOptions& options) {
  const double fs = options.frame_sigma_m, fh = degToRad(options.frame_heading_sigma_deg);
  return Vec3(fs * fs, fs * fs, fh * fh).asDiagonal();
}

// The gate's Mahalanobis distance d^2 = e^T (U^T (P + R) U + Lambda^-1)^-1 e of the fit's change
// from the prior, `change` (fit - prior), with e = U^T change, P the prior's pose covariance and R
// the frame's shared error.
double gateDistance2(const ObservedDirections& observed, const Vec3& change, const Mat3& covariance,
                     const Mat3& frame_error) {
  const Eigen::MatrixXd& u = observed.u;
  const Eigen::VectorXd e = u.transpose() * change;
  const Eigen::MatrixXd s =
      u.transpose() * (covariance + frame_error) * u + Eigen::MatrixXd(observed.fit_variance.asDiagonal());
  return e.dot(s.ldlt().solve(e));
}

// The fit's inliers, each matched against the map line the fit associated it with.
std::vector<LineCorrespondence> inliersOf(const std::vector<LineCorrespondence>& lines, const LineFit& fit) {
  std::vector<LineCorrespondence> inliers;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const auto& out = fit.outlier_indices;
    if (std::find(out.begin(), out.end(), i) != out.end()) continue;
    inliers.push_back(lines[i]);
    inliers.back().map_world = fit.map_lines[i];
  }
  return inliers;
}

// a - b over the full state, the heading difference wrapped.
StateVector stateDifference(const StateVector& a, const StateVector& b) {
  StateVector d = a - b;
  d(2) = normalizeAngle(d(2));
  return d;
}

// The Gauss-Newton iterates of the update from `prior5` (PoseFilter::update, step 3): at each,
// `problem`'s points re-associated (not at the first, the prior: the fit's association is kept),
// their projected information and gradient through the frame's shared error, and the step solving
// (I + P A) step = -(x - prior) - P g with P = `p_used`. Stops after options.update_iterations
// iterates or at a pose step below match.step_tolerance. Returns the last iterate.
StateVector iterateUpdate(Problem& problem, const Mat3& project, const Mat3& frame_error, const StateVector& prior,
                          const StateMatrix& p_used, const StateMatrix& updated, const FilterOptions& options) {
  const std::vector<PointObs>& pts = problem.pts;
  StateVector x = prior;
  for (int it = 0; it < options.update_iterations; ++it) {
    const Vec3 pose_x = x.head<3>();
    if (it > 0) problem.reassociate(pose_x);  // the first iterate is the prior: keep the fit's association
    Mat3 a = Mat3::Zero();
    Vec3 g = Vec3::Zero();
    for (const PointObs& p : pts) {
      const Vec3 j = jacobian(p, pose_x);
      a += j * j.transpose() / (p.sigma * p.sigma);
      g += j * residual(p, pose_x) / (p.sigma * p.sigma);
    }
    const Mat3 a3 = project * a * project;
    const Mat3 m = sharedErrorFactor(a3, frame_error);
    const StateMatrix a_full = updated * fullInformation(m, a3) * updated;
    StateVector g_full = StateVector::Zero();
    g_full.head<3>() = m * project * g;
    g_full = updated * g_full;
    const StateVector step =
        (StateMatrix::Identity() + p_used * a_full).partialPivLu().solve(-stateDifference(x, prior) - p_used * g_full);
    x += step;
    x(2) = normalizeAngle(x(2));
    if (step.head<3>().norm() < options.match.step_tolerance) break;
  }
  return x;
}

// The directions of the full state a frame's lines update and those they only consider (Schmidt):
// Q, an orthonormal basis whose first `updated` columns span the updated directions.
struct UpdateBasis {
  StateMatrix q = StateMatrix::Identity();
  int updated = kStateSize;
  /// The projector onto the updated directions.
  StateMatrix updatedProjector() const {
    return q.leftCols(updated) * q.leftCols(updated).transpose();
  }
  /// P without its correlation between the updated and the considered directions.
  StateMatrix decoupled(const StateMatrix& p) const {
    const StateMatrix u = updatedProjector(), c = StateMatrix::Identity() - u;
    return u * p * u + c * p * c;
  }
};

// Lines that observe the position along the road update the whole state; the others update the
// pose only, the scale and the biases considered (their variances kept, their correlation with what
// is updated shrinking with it) — and on a map whose shape is not exact (`map_exact` false) the
// position along the road too: there the road's bends, which turn an along-road error into a
// lateral one, are no better known than the map.
UpdateBasis updateBasis(bool along_observed, bool map_exact, double heading) {
  UpdateBasis basis;
  if (along_observed) return basis;
  basis.updated = 3;
  if (map_exact) return basis;  // x, y, heading updated: Q = I
  const double c = std::cos(heading), s = std::sin(heading);
  basis.q.topLeftCorner<3, 3>() << -s, 0, c,  //
      c, 0, s,                                //
      0, 1, 0;  // across the road, the heading, along the road
  basis.updated = 2;
  return basis;
}

// The posterior covariance from the prior `full` and the measurement's information `a` over the
// full state (zero in the considered directions), symmetrised: in the basis Q, (I + P_uu A_uu)^-1
// applied to the updated rows, P_cc kept; with every direction updated, (P^-1 + A)^-1.
StateMatrix posteriorCovariance(const StateMatrix& full, const StateMatrix& a, const UpdateBasis& basis) {
  const int k = basis.updated;
  StateMatrix p = basis.q.transpose() * full * basis.q;
  const StateMatrix aq = basis.q.transpose() * a * basis.q;
  const Eigen::MatrixXd shrink =
      (Eigen::MatrixXd::Identity(k, k) + p.topLeftCorner(k, k) * aq.topLeftCorner(k, k)).partialPivLu().inverse();
  p.topRows(k) = (shrink * p.topRows(k)).eval();
  p.bottomLeftCorner(kStateSize - k, k) = p.topRightCorner(k, kStateSize - k).transpose();
  StateMatrix posterior = basis.q * p * basis.q.transpose();
  return 0.5 * (posterior + posterior.transpose());
}

}  // namespace

CurrentPosition PoseFilter::update(const std::vector<LineCorrespondence>& lines, double timestamp) {
  step_.reset();
  const LineMatchOptions& mo = options_.match;
  if (lines.empty()) return current(timestamp, "no usable lines: odometry only");

  // 1. The robust fit from the prior: which correspondences are inliers, and the pose they give.
  const std::optional<LineFit> fit = fitPoseToLines(pose_, lines, mo);
  if (!fit) return current(timestamp, "no line is an inlier: odometry only");

  // 2. The gate: the fitted pose against the prior in the observed directions U, where the fit's
  //    covariance is diag(1 / eigenvalue): d^2 = e^T (U^T P U + Lambda^-1)^-1 e, e = U^T (fit - prior).
  const Vec3 prior = toVec(pose_);
  const ObservedDirections observed = observedDirections(fit->information, mo.min_information);
  const Eigen::MatrixXd& u = observed.u;
  const int dof = static_cast<int>(u.cols());
  if (dof == 0) return current(timestamp, "the lines constrain no direction: odometry only");
  const Mat3 frame_error = frameError(options_);  // shared by the frame's lines
  const double d2 = gateDistance2(observed, difference(toVec(fit->pose), prior), covariance_, frame_error);
  const boost::math::chi_squared_distribution<double> chi2(dof);
  const double limit = boost::math::quantile(chi2, options_.gate_probability);
  if (!(d2 <= limit)) {
    CurrentPosition out = current(
        timestamp,
        strprintf("rejected: the lines disagree with the prior (Mahalanobis d^2 = %.1f > %.1f, %d dof); odometry only",
               d2, limit, dof));
    out.status = PositionStatus::Rejected;
    out.mahalanobis_d2 = d2;
    out.gate_dof = dof;
    out.outliers = fit->outliers;
    out.rejected_fit = fit->pose;
    out.rejected_fit_rms_m = fit->rms_m;
    return out;
  }

  // 3. Iterated EKF update with the inliers' point-to-line distances (measured 0) as the
  //    measurement: Gauss-Newton on |x - prior|^2_{P^-1} + sum r_i(x)^2 / sigma_i^2.
  //    Lines with candidates start from the fit's association and are re-associated at every iterate.
  const std::vector<LineCorrespondence> inliers = inliersOf(lines, *fit);
  //    The measurement is used only in the observed directions U (J projected onto U): a direction
  //    the lines determine worse than min_information allows (a line a few degrees off the road's
  //    direction "observes" the along-road position through its slant alone, where a few
  //    centimetres of map or detection error become decimetres) gets no correction.
  Problem problem(inliers, mo.reassociate_max_angle_deg);
  const std::vector<PointObs>& pts = problem.pts;
  const std::vector<char> all(inliers.size(), 1);
  //    Over the full state (the scale and biases move through their correlation with the pose), in
  //    the form that needs no inverse of the prior covariance P (a state not estimated has variance
  //    0): with A = J^T W J and g = J^T W r (projected, zero for e and b) the step solves
  //    (P^-1 + A) step = -P^-1 (x - prior) - g, i.e. (I + P A) step = -(x - prior) - P g, and the
  //    posterior is (P^-1 + A)^-1 = (I + P A)^-1 P.
  const Mat3 project = u * u.transpose();
  //    The frame's shared error R (sharedErrorFactor, fullInformation).
  StateVector prior_state;
  prior_state << prior, scale_error_, gyro_bias_, gnss_bias_;
  //    The scale and the biases are estimated from frames whose lines observe the position along
  //    the road (crossing lines); from the others (road edges or a centre line alone: park mode)
  //    they are considered, not updated (Schmidt): on a curve an along-road error the lines do not
  //    see turns into lateral and heading corrections, which through the correlations would be
  //    taken for a scale or bias error (on park_loop's bends these corrections pull 1-2 m per bend
  //    whatever the scale). On a map that is not exact (known worse than the frame's shared error,
  //    a survey's) so is the position along the road: its bends and kinks are as uncertain as the
  //    map (on OpenStreetMap's Ostring, 0.5 m off in places, a lateral correction of 0.1 m moved the
  //    estimate 2-4 m along). The update then uses the updated directions' block of P, and their
  //    correlation with the considered ones shrinks as their covariance does (UpdateBasis).
  const UpdateBasis basis = updateBasis(
      observability(project * informationOf(pts, all, prior) * project, pose_.heading(), mo.min_information).along,
      map_sigma_m_ <= options_.frame_sigma_m, pose_.heading());
  const StateMatrix updated = basis.updatedProjector();
  const StateVector x =
      iterateUpdate(problem, project, frame_error, prior_state, basis.decoupled(full_), updated, options_);
  const Mat3 information = project * informationOf(pts, all, x.head<3>()) * project;
  const StateMatrix posterior = posteriorCovariance(
      full_, updated * fullInformation(sharedErrorFactor(information, frame_error), information) * updated, basis);

  pose_ = toPose(x.head<3>());
  scale_error_ = x(3);
  gyro_bias_ = x(4);
  gnss_bias_ = x.tail<2>();
  full_ = posterior;
  covariance_ = full_.topLeftCorner<3, 3>();
  CurrentPosition out = current(timestamp, "");
  out.status = PositionStatus::Corrected;
  out.information = information;
  const Observability seen = observability(information, pose_.heading(), mo.min_information);
  out.observed_lateral = seen.lateral;
  out.observed_along = seen.along;
  if (seen.along) along_since_fix_m_ = 0;
  out.observed_heading = seen.heading;
  out.lines_used = static_cast<int>(inliers.size());
  out.outliers = fit->outliers;
  out.mahalanobis_d2 = d2;
  out.gate_dof = dof;
  out.reason = "corrected from " + std::to_string(inliers.size()) + " line(s)";
  if (!fit->outliers.empty()) out.reason += ", outliers rejected: " + joined(fit->outliers);
  if (!seen.along) out.reason += "; along-road position from odometry";
  if (!seen.lateral) out.reason += "; lateral position from odometry";
  return out;
}

}  // namespace mapnav
