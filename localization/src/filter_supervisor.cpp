#include "mapnav/localization/filter_supervisor.h"

#include <algorithm>

#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

const OptionTable<FilterSupervisorOptions>& filterSupervisorOptionTable() {
  using O = FilterSupervisorOptions;
  static const OptionTable<O> table =
      OptionTable<O>("FilterSupervisorOptions")
          .field("after_rejections", &O::after_rejections, atLeast(0),
                 "widen the covariance after this many consecutive frames the gate rejected (0: never; 3: as the rule was made)")
          .field("sigma_m", &O::sigma_m, above(0), "the widened position sigma, m")
          .field("heading_sigma_deg", &O::heading_sigma_deg, above(0), "the widened heading sigma, degrees")
          .field("agreement_m", &O::agreement_m, above(0),
                 "widen only when the rejected frames' fits agree within this across the road, m")
          .field("agreement_deg", &O::agreement_deg, above(0), "... and within this in heading, degrees")
          .field("max_rms_m", &O::max_rms_m, above(0),
                 "... and when each rejected frame's lines fit together: no outlier, within this RMS distance of their "
                 "map lines, m");
  return table;
}

void FilterSupervisorOptions::validate() const { filterSupervisorOptionTable().validate(*this); }

FilterSupervisor::FilterSupervisor(const FilterSupervisorOptions& options) : options_(options) { options_.validate(); }

SupervisorDecision FilterSupervisor::observe(const CurrentPosition& outcome) {
  const std::size_t n = static_cast<std::size_t>(std::max(0, options_.after_rejections));
  const bool good_rejection = n > 0 && outcome.status == PositionStatus::Rejected && outcome.rejected_fit &&
                              outcome.outliers.empty() && outcome.rejected_fit_rms_m <= options_.max_rms_m;
  if (!good_rejection) {
    fits_.clear();
    return {};
  }
  const Pose2 change = outcome.pose.inverse() * *outcome.rejected_fit;
  fits_.emplace_back(change.x(), change.y(), change.heading());
  if (fits_.size() > n) fits_.pop_front();
  if (fits_.size() < n || !fitsAgree()) return {};
  const double s = options_.sigma_m, h = degToRad(options_.heading_sigma_deg);
  SupervisorDecision widen{.widen = true, .covariance = Vec3(s * s, s * s, h * h).asDiagonal(), .rejections = n};
  fits_.clear();
  return widen;
}

bool FilterSupervisor::fitsAgree() const {
  double lo_y = 1e9, hi_y = -1e9, lo_h = 1e9, hi_h = -1e9;
  for (const Vec3& c : fits_) {
    lo_y = std::min(lo_y, c.y()), hi_y = std::max(hi_y, c.y());
    lo_h = std::min(lo_h, c.z()), hi_h = std::max(hi_h, c.z());
  }
  return hi_y - lo_y <= options_.agreement_m && hi_h - lo_h <= degToRad(options_.agreement_deg);
}

}  // namespace mapnav
