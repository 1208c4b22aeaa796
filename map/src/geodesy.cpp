#include "mapnav/map/geodesy.h"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/LocalCartesian.hpp>

namespace mapnav {

struct LocalFrame::Impl {
  GeographicLib::LocalCartesian frame;
};

LocalFrame::LocalFrame(const GeoOrigin& origin)
    : origin_(origin),
      impl_(std::make_unique<Impl>(Impl{GeographicLib::LocalCartesian(origin.lat, origin.lon, origin.alt,
                                                                       GeographicLib::Geocentric::WGS84())})) {}
LocalFrame::~LocalFrame() = default;
LocalFrame::LocalFrame(LocalFrame&&) noexcept = default;
LocalFrame& LocalFrame::operator=(LocalFrame&&) noexcept = default;

Vec2 LocalFrame::toLocal(const LatLon& p) const {
  double x = 0, y = 0, z = 0;
  impl_->frame.Forward(p.lat, p.lon, origin_.alt, x, y, z);
  return {x, y};
}

LatLon LocalFrame::toGeodetic(const Vec2& p) const {
  // The point at the origin's altitude whose east/north are p: the surface drops below the tangent
  // plane (z < 0) away from the origin, so find its z by fixed-point iteration (converges to
  // nanometres in a few steps for any distance a campus map spans), making toLocal ∘ toGeodetic exact.
  double z = 0, lat = 0, lon = 0, h = 0;
  for (int i = 0; i < 5; ++i) {
    impl_->frame.Reverse(p.x(), p.y(), z, lat, lon, h);
    double x2 = 0, y2 = 0, z2 = 0;
    impl_->frame.Forward(lat, lon, origin_.alt, x2, y2, z2);
    z = z2;
  }
  impl_->frame.Reverse(p.x(), p.y(), z, lat, lon, h);
  return {lat, lon};
}

double geodesicDistance(const LatLon& a, const LatLon& b) {
  double s12 = 0;
  GeographicLib::Geodesic::WGS84().Inverse(a.lat, a.lon, b.lat, b.lon, s12);
  return s12;
}

}  // namespace mapnav
