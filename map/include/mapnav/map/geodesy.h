#pragma once
// Geodetic ↔ local metric frame (ENU about an origin) with GeographicLib's LocalCartesian, kept
// behind a private pointer so GeographicLib stays out of every other translation unit.
#include <memory>

#include "mapnav/geometry/types.h"
#include "mapnav/map/map.h"

namespace mapnav {

struct LatLon {
  double lat = 0, lon = 0;  ///< degrees, WGS84
};

class LocalFrame {
 public:
  explicit LocalFrame(const GeoOrigin& origin);
  ~LocalFrame();
  LocalFrame(LocalFrame&&) noexcept;
  LocalFrame& operator=(LocalFrame&&) noexcept;

  const GeoOrigin& origin() const { return origin_; }
  /// lat/lon (at the origin's altitude) → east, north metres.
  Vec2 toLocal(const LatLon& p) const;
  /// east, north metres (at the origin's altitude) → lat/lon.
  LatLon toGeodetic(const Vec2& p) const;

 private:
  struct Impl;
  GeoOrigin origin_;
  std::unique_ptr<Impl> impl_;
};

/// Geodesic distance (m) on the WGS84 ellipsoid (GeographicLib Geodesic::Inverse).
double geodesicDistance(const LatLon& a, const LatLon& b);

}  // namespace mapnav
