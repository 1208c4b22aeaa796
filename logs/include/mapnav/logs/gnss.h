#pragma once
// GNSS fixes as a receiver gives them: the true position plus a bias that drifts slowly (multipath,
// the atmosphere, the satellites in view: a first-order Gauss-Markov process per axis) and white
// noise per fix. A KITTI raw import degrades the OXTS positions with it (kitti_raw_import.h), so a
// log's fixes are never its truth. Positions in the world frame, m; times in s.
#include <cstdint>
#include <optional>
#include <random>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/types.h"
#include "mapnav/logs/replay_log.h"

namespace mapnav {

struct GnssReceiverOptions {
  std::uint64_t seed = 1;     ///< the same seed gives the same errors
  /// White noise of each fix, 1-sigma per axis, m (>= 0).
  double sigma_m = 1.0;
  /// The drifting bias's steady 1-sigma per axis, m (>= 0). With sigma_m, 1.8 m per axis: a consumer
  /// receiver's 1.5-3 m horizontal accuracy.
  double bias_sigma_m = 1.5;
  /// The bias's correlation time, s (> 0): over this long it forgets itself to 1/e.
  double bias_time_s = 60.0;

  /// The fixes' stated 1-sigma per axis, m: sqrt(sigma_m² + bias_sigma_m²).
  double statedSigma() const;
  /// Throws InvalidInput naming the first bad field and its value (gnssReceiverOptionTable()'s rules).
  void validate() const;
};

const OptionTable<GnssReceiverOptions>& gnssReceiverOptionTable();

class GnssReceiver {
 public:
  /// Throws InvalidInput for bad options.
  explicit GnssReceiver(const GnssReceiverOptions& options = {});
  /// The fix for the true position `truth` at time `t` (s, not decreasing from call to call); its
  /// sigma_m is the stated one (at least 0.05 m: a fix's sigma is > 0). The first fix draws the bias from its steady distribution.
  GnssFix measure(const Vec2& truth, double t);
  const Vec2& bias() const { return bias_; }

 private:
  GnssReceiverOptions options_;
  std::mt19937_64 rng_;
  Vec2 bias_ = Vec2::Zero();
  std::optional<double> last_t_;
};

}  // namespace mapnav
