// The map's landmarks in the synthetic world (see world.h and world_landmarks.h): their bodies and
// the marks they leave on the ground, built once from the map; where a ray meets a body; the
// colour of a body and of a manhole cover; the landmarks' shadows on the ground.
#include "world_landmarks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "mapnav/geometry/polygon.h"

namespace mapnav {

using namespace world_detail;

namespace {

/// The ray's first entry into a vertical cylinder (centre c, radius r, from the ground up to `top`)
/// through its side or its top: the pixel of an eye above a bollard sees its cap.
bool hitCylinder(const Vec2& c, double r, double top, const Vec3& o, const Vec3& d, double t_max, BodyHit& hit) {
  const double ox = o.x() - c.x(), oy = o.y() - c.y();
  const double a = d.x() * d.x() + d.y() * d.y();
  const double b = ox * d.x() + oy * d.y();
  const double cc = ox * ox + oy * oy - r * r;
  if (!(cc > 0) || !(a > 0)) return false;  // the eye inside it, or a vertical ray beside it
  const double disc = b * b - a * cc;
  if (disc < 0) return false;
  const double root = std::sqrt(disc);
  const double t = (-b - root) / a;
  if (!(t > 0 && t < t_max)) return false;
  const double z = o.z() + t * d.z();
  if (z >= 0 && z <= top) {
    hit = {t, Vec3((ox + t * d.x()) / r, (oy + t * d.y()) / r, 0.0), Part::Post};
    return true;
  }
  if (!(z > top && d.z() < 0)) return false;
  // Above the side: the top, if the ray comes down to it before it leaves the cylinder.
  const double tc = (top - o.z()) / d.z();
  if (!(tc <= (-b + root) / a && tc < t_max)) return false;
  hit = {tc, Vec3::UnitZ(), Part::Cap};
  return true;
}

/// How far a crown's outline reaches toward the unit direction u from its centre: 1 − kCrownRag
/// … 1 of its radius (seeded value noise on the sphere of directions, two octaves).
double crownRag(std::uint64_t salt, const Vec3& u) {
  const double x = u.x() + 0.5 * u.z(), y = u.y() - 0.7 * u.z();
  const double n = 0.55 * valueNoise(salt, 2.5 * x + 11.0, 2.5 * y + 7.0) + 0.45 * valueNoise(salt + 1, 9.0 * x, 9.0 * y);
  return 1.0 - kCrownRag * (0.5 + 0.5 * n);
}

/// The ray's entry into a tree's crown: a sphere whose radius toward the ray's closest approach
/// to its centre is ragged (crownRag), so its outline is leafy and its top stays at the height.
bool hitCrown(const Body& body, const Vec3& o, const Vec3& d, double t_max, BodyHit& hit) {
  const Vec3 oc = o - Vec3(body.c.x(), body.c.y(), body.crown_z);
  const double b = oc.dot(d);
  const Vec3 q = oc - b * d;  // the closest approach, from the centre
  const double q2 = q.squaredNorm();
  if (q2 >= body.crown_r * body.crown_r) return false;
  const double qn = std::sqrt(q2);
  const double radius = body.crown_r * crownRag(body.salt, qn > 1e-9 ? Vec3(q / qn) : d);
  const double c = oc.squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (!(c > 0) || disc < 0) return false;
  const double t = -b - std::sqrt(disc);
  if (!(t > 0 && t < t_max)) return false;
  hit = {t, Vec3((oc + t * d) / radius), Part::Crown};
  return true;
}

/// The ray's entry into the box [lo, hi] (its own frame) at 0 < t < t_max: t and the axis and
/// side (±1) of the face it enters.
bool hitBox(const Vec3& o, const Vec3& d, const Vec3& lo, const Vec3& hi, double t_max, double& t, int& axis,
            double& side) {
  double t0 = 0, t1 = t_max;
  axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (o[k] < lo[k] || o[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    if (ta > t0) t0 = ta, axis = k;
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  if (axis < 0) return false;  // the eye inside the box
  t = t0;
  side = d[axis] > 0 ? -1.0 : 1.0;
  return true;
}

/// The ray's entry into a bench: its seat's box and its back's.
bool hitBench(const Body& body, const Vec3& o, const Vec3& d, double t_max, BodyHit& hit) {
  const Vec2 rel(o.x() - body.c.x(), o.y() - body.c.y()), dxy(d.x(), d.y());
  const Vec3 lo(rel.dot(body.axis), rel.dot(body.back), o.z()), ld(dxy.dot(body.axis), dxy.dot(body.back), d.z());
  const double half = kBenchDepth / 2, seat = std::min(kBenchSeat, body.h);
  struct Box {
    Vec3 lo, hi;
    Part part;
  };
  const std::array<Box, 2> boxes{{{Vec3(-body.r, -half, 0), Vec3(body.r, half, seat), Part::Seat},
                                  {Vec3(-body.r, half - kBenchBack, 0), Vec3(body.r, half, body.h), Part::Back}}};
  bool found = false;
  for (const Box& box : boxes) {
    double t = 0, side = 0;
    int axis = 0;
    if (!hitBox(lo, ld, box.lo, box.hi, found ? hit.t : t_max, t, axis, side)) continue;
    const Vec2 n2 = axis == 0 ? Vec2(body.axis * side) : axis == 1 ? Vec2(body.back * side) : Vec2::Zero();
    hit = {t, axis == 2 ? Vec3(0, 0, side) : Vec3(n2.x(), n2.y(), 0.0), box.part};
    found = true;
  }
  return found;
}

/// A shadow's coverage where its edge is `dist` m away (inside negative), over a soft edge `edge` wide.
float softInside(double dist, double edge) {
  const auto e = static_cast<float>(std::min(edge, kMarkEdgeMax));
  return 1.0f - smoothstep(-0.5f * e, 0.5f * e, static_cast<float>(dist));
}

/// A manhole cover's colour at p over the ground colour `c`.
C3 coverColour(const GroundMark& m, const Vec2& p, double footprint, C3 c) {
  const Vec2 q = p - m.a;
  const double d = q.norm(), fp = std::max(footprint, 1e-3);
  const auto inside = static_cast<float>(std::clamp((m.r - d) / fp + 0.5, 0.0, 1.0));
  if (!(inside > 0)) return c;
  // Cast iron: a raised grid of 5 cm squares, a frame 4 cm wide around it, rust and wear.
  constexpr double kGrid = 0.05;
  const auto toLine = [&](double x) { return std::abs(x / kGrid - std::round(x / kGrid)) * kGrid; };
  const float grid = std::max(lineCoverage(toLine(q.x()), 0.012, fp), lineCoverage(toLine(q.y()), 0.012, fp));
  C3 iron = lerp(C3{60, 60, 62}, C3{84, 83, 81}, 0.8f * grid);
  iron = lerp(iron, C3{100, 98, 94}, lineCoverage(std::abs(d - (m.r - 0.02)), 0.04, fp));
  iron = iron * (1.0f + 0.08f * valueNoise(m.salt, p.x() * 6, p.y() * 6) * filterWeight(6.0, fp));
  return lerp(c, iron, inside);
}

}  // namespace

Sun world_detail::sunOf(double azimuth_rad, double elevation_rad) {
  Sun s;
  const double ce = std::cos(elevation_rad), se = std::sin(elevation_rad);
  s.toward = Vec3(ce * std::cos(azimuth_rad), ce * std::sin(azimuth_rad), se);
  s.shadow_dir = -unitVector(azimuth_rad);
  s.shadow_per_m = ce / se;
  s.sin_elevation = se;
  return s;
}

bool world_detail::hitBody(const Body& body, const Vec3& o, const Vec3& d, double t_max, BodyHit& hit) {
  switch (body.kind) {
    case LandmarkKind::Pole:
    case LandmarkKind::Bollard: return hitCylinder(body.c, body.r, body.post_top, o, d, t_max, hit);
    case LandmarkKind::Tree: {
      const bool trunk = hitCylinder(body.c, body.r, body.post_top, o, d, t_max, hit);
      return hitCrown(body, o, d, trunk ? hit.t : t_max, hit) || trunk;
    }
    case LandmarkKind::Bench: return hitBench(body, o, d, t_max, hit);
    case LandmarkKind::Manhole: return false;
  }
  return false;
}

int LandmarkView::slot(std::uint32_t landmark) const {
  const auto it = std::lower_bound(items.begin(), items.end(), landmark,
                                   [](const Item& item, std::uint32_t l) { return item.landmark < l; });
  return it != items.end() && it->landmark == landmark ? static_cast<int>(it - items.begin()) : -1;
}

Landmarks::Landmarks(const Map& map, const WorldOptions& options)
    : sun(sunOf(options.sun_azimuth_rad, options.sun_elevation_rad)),
      shadow_k(static_cast<float>(options.shadow_k)), blue_shift(static_cast<float>(options.shadow_blue_shift)) {
  const std::vector<Landmark>& all = map.landmarks();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Landmark& lm = all[i];
    const auto id = static_cast<std::uint32_t>(i);
    Body b;
    b.kind = lm.kind;
    b.c = lm.position;
    b.r = lm.radius;
    b.h = lm.height;
    b.salt = mix64(options.seed ^ (0x1A9D3A2CULL + 0x9E3779B97F4A7C15ULL * (i + 1)));
    b.first_mark = static_cast<std::uint32_t>(marks.size());
    b.box = Box2(b.c - Vec2(b.r, b.r), b.c + Vec2(b.r, b.r));
    const double reach = b.r + 0.5 * kMarkEdgeMax;
    if (lm.kind == LandmarkKind::Bench) {
      placeBench(map, lm, id, b);
    } else if (lm.kind == LandmarkKind::Manhole) {
      GroundMark m{GroundMark::Kind::Cover, id, Box2(b.c - Vec2(reach, reach), b.c + Vec2(reach, reach)), b.c};
      m.r = b.r;
      m.salt = b.salt;
      marks.push_back(m);
    } else {
      b.post_top = lm.kind == LandmarkKind::Tree ? kTrunkTop * b.h : b.h;
      GroundMark m{GroundMark::Kind::Capsule, id, Box2(), b.c, b.c + sun.shadow_dir * (b.post_top * sun.shadow_per_m)};
      m.r = b.r;
      m.box = Box2(m.a.cwiseMin(m.b) - Vec2(reach, reach), m.a.cwiseMax(m.b) + Vec2(reach, reach));
      marks.push_back(m);
    }
    if (lm.kind == LandmarkKind::Tree) placeCrown(id, b);
    b.n_marks = static_cast<std::uint32_t>(marks.size()) - b.first_mark;
    any_upright = any_upright || b.upright();
    bodies.push_back(b);
  }
}

void Landmarks::placeCrown(std::uint32_t id, Body& b) {
  b.crown_z = kCrownCentre * b.h;
  b.crown_r = kCrownRadius * b.h;
  b.box.extend(b.c - Vec2(b.crown_r, b.crown_r));
  b.box.extend(b.c + Vec2(b.crown_r, b.crown_r));
  // A sphere's shadow: an ellipse r across, r / sin(elevation) along the sun, its outline ragged.
  GroundMark m{GroundMark::Kind::Ellipse, id, Box2(), b.c + sun.shadow_dir * (b.crown_z * sun.shadow_per_m),
               sun.shadow_dir};
  m.r = b.crown_r;
  m.r_along = b.crown_r / sun.sin_elevation;
  m.salt = b.salt + 2;
  const double reach = m.r_along + 0.5 * kMarkEdgeMax;
  m.box = Box2(m.a - Vec2(reach, reach), m.a + Vec2(reach, reach));
  marks.push_back(m);
}

void Landmarks::placeBench(const Map& map, const Landmark& lm, std::uint32_t id, Body& b) {
  // Along its road, its back away from it.
  if (const Road* road = map.roadBeside(lm)) {
    const Polyline2::Projection pr = road->centerline.project(lm.position);
    b.axis = road->centerline.tangentAt(pr.arc_length);
    b.back = pr.lateral >= 0 ? leftNormal(b.axis) : Vec2(-leftNormal(b.axis));
  }
  const auto footprint = [&](double y0, double y1) {
    return std::array<Vec2, 4>{b.c - b.r * b.axis + y0 * b.back, b.c + b.r * b.axis + y0 * b.back,
                               b.c + b.r * b.axis + y1 * b.back, b.c - b.r * b.axis + y1 * b.back};
  };
  const double half = kBenchDepth / 2;
  const std::array<Vec2, 4> seat = footprint(-half, half);
  b.box = Box2();
  for (const Vec2& p : seat) b.box.extend(p);
  addBoxShadow(id, seat, std::min(kBenchSeat, b.h));
  if (b.h > kBenchSeat) addBoxShadow(id, footprint(half - kBenchBack, half), b.h);
}

void Landmarks::addBoxShadow(std::uint32_t landmark, const std::array<Vec2, 4>& footprint, double height) {
  std::vector<Vec2> pts(footprint.begin(), footprint.end());
  for (const Vec2& p : footprint) pts.push_back(p + sun.shadow_dir * (height * sun.shadow_per_m));
  const Polygon2 hull = convexHull(pts);
  GroundMark m{GroundMark::Kind::Polygon, landmark, Box2()};
  m.first = static_cast<std::uint32_t>(mark_points.size());
  m.count = static_cast<std::uint32_t>(hull.size());
  for (const Vec2& p : hull) m.box.extend(p);
  m.box = Box2(m.box.min() - Vec2::Constant(0.5 * kMarkEdgeMax), m.box.max() + Vec2::Constant(0.5 * kMarkEdgeMax));
  mark_points.insert(mark_points.end(), hull.begin(), hull.end());
  marks.push_back(m);
}

float Landmarks::markShadow(const GroundMark& m, const Vec2& p, double footprint) const {
  switch (m.kind) {
    case GroundMark::Kind::Capsule: {
      // A post's: its edge blurred by the sun's half-degree disc, more the farther from the post.
      const Vec2 ab = m.b - m.a;
      const double len2 = ab.squaredNorm();
      const double s = len2 > 0 ? std::clamp((p - m.a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const double d2 = (p - (m.a + s * ab)).squaredNorm();
      const double along = s * std::sqrt(len2), edge = std::max(footprint, 0.02 + 0.0093 * along);
      const double reach = m.r + 0.5 * std::min(edge, kMarkEdgeMax);
      if (d2 >= reach * reach) return 0;  // beyond the soft edge (no root)
      return softInside(std::sqrt(d2) - m.r, edge);
    }
    case GroundMark::Kind::Ellipse: {
      const Vec2 q = p - m.a;
      const double x = q.dot(m.b) / m.r_along, y = cross2(m.b, q) / m.r;
      const double dist = (std::sqrt(x * x + y * y) - 1) * m.r, half = 0.5 * std::min(std::max(footprint, 0.25), kMarkEdgeMax);
      // The ragged outline reaches kCrownRag·r inward at most: beyond the soft edge or well inside, no noise.
      if (dist >= half) return 0;
      if (dist + kCrownRag * m.r <= -half) return 1;
      const double rag = kCrownRag * (0.5 + 0.5 * valueNoise(m.salt, p.x() * 1.3, p.y() * 1.3));
      return softInside(dist + rag * m.r, std::max(footprint, 0.25));
    }
    case GroundMark::Kind::Polygon: {
      double dist = -std::numeric_limits<double>::infinity();  // to the convex polygon's edges (outside positive)
      for (std::uint32_t i = 0; i < m.count; ++i) {
        const Vec2& a = mark_points[m.first + i];
        const Vec2& b = mark_points[m.first + (i + 1) % m.count];
        const Vec2 e = b - a;
        dist = std::max(dist, cross2(e, a - p) / e.norm());  // outward normal (e.y, −e.x) · (p − a)
      }
      return softInside(dist, std::max(footprint, 0.02));
    }
    case GroundMark::Kind::Cover: return 0;
  }
  return 0;
}

float Landmarks::marksAt(const Vec2& p, const std::uint32_t* ids, std::uint32_t n, double footprint, C3* c,
                         int* cover) const {
  float s = 0;
  if (cover != nullptr) *cover = -1;
  for (std::uint32_t i = 0; i < n; ++i) {
    const GroundMark& m = marks[ids[i]];
    if (!m.box.contains(p)) continue;  // the same answer from a cell's list and from a tile's
    if (m.kind != GroundMark::Kind::Cover) {
      s = std::max(s, markShadow(m, p, footprint));
    } else {
      if (c != nullptr) *c = coverColour(m, p, footprint, *c);
      if (cover != nullptr && (p - m.a).squaredNorm() < m.r * m.r) *cover = static_cast<int>(m.landmark);
    }
  }
  return s;
}

C3 Landmarks::sunlight(const Vec3& n) const {
  const float k = shadow_k, b = blue_shift;
  const double lit = std::max(0.0, n.dot(sun.toward)) / sun.sin_elevation;  // 1 for the ground
  const C3 c = lerp(C3{k * (1 - b), k, k * (1 + b)}, C3{1, 1, 1}, static_cast<float>(std::min(lit, 1.0)));
  return lit > 1 ? c * static_cast<float>(std::min(lit, 1.4)) : c;
}

C3 Landmarks::metal(C3 base, const Vec3& rel, const Vec3& n, const Vec3& ray, std::uint64_t salt, double fp,
                      float shine) const {
  // Grime, then the sun's light across the post and a highlight where it mirrors the sun.
  const C3 c = base * (1.0f + 0.05f * valueNoise(salt, rel.z() * 3.0, (rel.x() + rel.y()) * 3.0) * filterWeight(3.0, fp));
  const double facing = n.dot(sun.toward);
  const double spec = facing > 0 ? std::pow(std::max(0.0, n.dot((sun.toward - ray).normalized())), 24.0) : 0.0;
  return c * sunlight(n) + C3{1, 1, 1} * static_cast<float>(70.0 * shine * spec);
}

C3 Landmarks::bark(const Vec3& rel, const Vec3& n, std::uint64_t salt, double fp) const {
  // Fissures: noise fast around the trunk, slow up it; patches of grey-green lichen.
  const float fissure = valueNoise(salt + 5, rel.x() * 28 + 3.1, rel.z() * 1.8 + rel.y() * 28) * filterWeight(28.0, fp);
  const float patch = valueNoise(salt + 6, rel.z() * 1.2, (rel.x() - rel.y()) * 6) * filterWeight(6.0, fp);
  C3 c = C3{86, 74, 64} * (1.0f + 0.35f * fissure + 0.12f * patch);
  c = lerp(c, C3{92, 96, 84}, 0.3f * std::max(0.0f, patch));
  return c * sunlight(n);
}

C3 Landmarks::foliage(const Vec3& p, const Vec3& n, std::uint64_t salt, double fp) const {
  const double x = p.x() + 0.5 * p.z(), y = p.y() - 0.4 * p.z();
  const float n1 = valueNoise(salt + 7, x * 1.6, y * 1.6);
  const float n2 = valueNoise(salt + 8, x * 5, y * 5) * filterWeight(5.0, fp);
  const float n3 = valueNoise(salt + 9, x * 14, y * 14) * filterWeight(14.0, fp);
  // Clumps of leaves: the normal bent by the noise, so the crown's light breaks up; yellower clumps.
  const Vec3 bent = (n + Vec3(0.45 * n2, 0.45 * n3, 0.35 * n1)).normalized();
  const C3 c = lerp(C3{50, 84, 36}, C3{96, 116, 46}, 0.5f + 0.5f * n1) * (1.0f + 0.25f * n3);
  return c * sunlight(bent);
}

C3 Landmarks::wood(const Body& body, const Vec3& p, const BodyHit& hit, double fp) const {
  const Vec2 q(p.x() - body.c.x(), p.y() - body.c.y());
  const double along = q.dot(body.axis), across = q.dot(body.back);
  C3 c = C3{136, 94, 56} *
         (1.0f + 0.12f * valueNoise(body.salt + 10, along * 1.5, p.z() * 30 + across * 30) * filterWeight(30.0, fp));
  // Boards: gaps 1.5 cm wide every 12 cm up the back and the seat's front, every 10 cm across the top.
  const bool top = hit.n.z() > 0.5;
  const double x = top ? across : p.z(), period = top ? 0.10 : 0.12;
  c = c * (1.0f - 0.5f * lineCoverage(std::abs(x / period - std::round(x / period)) * period, 0.015, fp));
  // Below the seat's boards: the gloom between its legs.
  if (hit.part == Part::Seat && !top && p.z() < kBenchSeat - 0.1 && std::abs(along) < body.r - 0.08) c = C3{46, 40, 34};
  return c * sunlight(hit.n);
}

C3 Landmarks::bodyColour(const Body& body, const Vec3& p, const Vec3& ray, const BodyHit& hit, double fp) const {
  const Vec3 rel(p.x() - body.c.x(), p.y() - body.c.y(), p.z());
  switch (body.kind) {
    case LandmarkKind::Pole: return metal(C3{112, 114, 118}, rel, hit.n, ray, body.salt, fp, 1.0f);
    case LandmarkKind::Bollard: {
      // Dark grey with a light reflective band at 72–84 % of its height.
      const float band = hit.part == Part::Post ? lineCoverage(std::abs(p.z() - 0.78 * body.h), 0.12 * body.h, fp) : 0.0f;
      return metal(lerp(C3{92, 93, 96}, C3{226, 226, 218}, band), rel, hit.n, ray, body.salt, fp, 0.6f);
    }
    case LandmarkKind::Tree: return hit.part == Part::Crown ? foliage(p, hit.n, body.salt, fp) : bark(rel, hit.n, body.salt, fp);
    case LandmarkKind::Bench: return wood(body, p, hit, fp);
    case LandmarkKind::Manhole: break;
  }
  return {};
}

}  // namespace mapnav
