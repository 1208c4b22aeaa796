// The map's landmarks in one frame (see world_landmarks.h): which may show (culled by the ground
// the frame sees, then by the box of pixels each body projects to), the pixels whose rays meet a
// body before the ground, and what the frame lists of them (Frame::landmarks).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "world_scene.h"

namespace mapnav {

using namespace world_detail;

namespace {

/// World point → vehicle frame for a pose (cos, sin of the heading, x, y).
Vec3 toVehicle(const std::array<double, 4>& pose, const Vec3& p) {
  const auto [ch, sh, tx, ty] = pose;
  const double dx = p.x() - tx, dy = p.y() - ty;
  return {ch * dx + sh * dy, -sh * dx + ch * dy, p.z()};
}

/// The corners of a body's footprint, in order around it.
std::array<Vec2, 4> footprintCorners(const Body& b) {
  if (b.kind == LandmarkKind::Bench) {
    const Vec2 x = b.r * b.axis, y = 0.5 * kBenchDepth * b.back;
    return {b.c - x - y, b.c + x - y, b.c + x + y, b.c - x + y};
  }
  return corners(b.box);
}

/// Where a body meets the ground nearest the ground point g (LandmarkInView::base_px).
Vec2 baseOf(const Body& b, const Vec2& g) {
  if (b.kind == LandmarkKind::Manhole) return b.c;
  const Vec2 q = g - b.c;
  if (b.kind == LandmarkKind::Bench) {
    const double x = std::clamp(q.dot(b.axis), -b.r, b.r), y = std::clamp(q.dot(b.back), -0.5 * kBenchDepth, 0.5 * kBenchDepth);
    return b.c + x * b.axis + y * b.back;
  }
  const double n = q.norm();
  return n > 1e-9 ? Vec2(b.c + q * (b.r / n)) : b.c;
}

/// The points whose projections bound a box's (8 corners, vehicle frame): the corners in front of a
/// plain pin-hole's near plane and where the edges cross it (a pin-hole maps the box clipped by
/// that plane into their hull); for other lenses the corners and 3 points along each edge.
std::vector<Vec3> boundingPoints(const Camera& cam, const std::array<Vec3, 8>& corner) {
  const bool pinhole = cam.model() == LensModel::Pinhole && cam.intrinsics().distortion.empty();
  std::vector<Vec3> pts;
  const auto depth = [&](const Vec3& p) { return (cam.rotation().transpose() * (p - cam.center())).z(); };
  constexpr double kNear = 1e-3;
  for (int i = 0; i < 8; ++i) {
    if (!pinhole || depth(corner[i]) >= kNear) pts.push_back(corner[i]);
    for (int bit : {1, 2, 4}) {
      const int j = i | bit;
      if (j == i) continue;  // each edge once: from its corner without the bit
      const Vec3 &a = corner[i], &b = corner[j];
      if (!pinhole) {
        for (double f : {0.25, 0.5, 0.75}) pts.push_back(a + f * (b - a));
        continue;
      }
      const double da = depth(a), db = depth(b);
      if ((da < kNear) != (db < kNear)) pts.push_back(a + (b - a) * ((kNear - da) / (db - da)));
    }
  }
  return pts;
}

/// The box of pixels that a box above the ground may cover: its footprint's corners in order around
/// it (world), the heights of its bottom and top. False: none (outside the image, or behind the camera).
bool boxPixels(const Camera& cam, const std::array<Vec2, 4>& f, double bottom, double top,
               const std::array<double, 4>& pose, PixelBox& box) {
  std::array<Vec3, 8> corner;
  for (int i = 0; i < 8; ++i) {  // bit 1 and 2 pick the footprint's corner, bit 4 the top
    const Vec2& g = f[static_cast<std::size_t>((i & 3) == 3 ? 2 : (i & 3) == 2 ? 3 : (i & 3))];
    corner[static_cast<std::size_t>(i)] = toVehicle(pose, Vec3(g.x(), g.y(), (i & 4) != 0 ? top : bottom));
  }
  Box2 px;
  bool lost = false;  // a point the lens cannot image: the box may reach anywhere
  for (const Vec3& p : boundingPoints(cam, corner)) {
    if (const auto at = cam.project(p)) px.extend(*at);
    else lost = true;
  }
  if (px.isEmpty()) return false;  // behind the camera, or beyond the lens' field
  const int w = cam.width(), h = cam.height();
  const auto clampPx = [](double x, int n) { return static_cast<int>(std::clamp(x, -1.0, static_cast<double>(n))); };
  if (lost) {
    box.u0 = 0, box.v0 = 0, box.u1 = w - 1, box.v1 = h - 1;
  } else {  // widened by a pixel for the rounding, and by one more for a lens' curving of edges
    box.u0 = std::max(0, clampPx(std::floor(px.min().x()) - 2, w));
    box.v0 = std::max(0, clampPx(std::floor(px.min().y()) - 2, h));
    box.u1 = std::min(w - 1, clampPx(std::ceil(px.max().x()) + 2, w));
    box.v1 = std::min(h - 1, clampPx(std::ceil(px.max().y()) + 2, h));
  }
  return box.u0 <= box.u1 && box.v0 <= box.v1;
}

/// The boxes of pixels a body may cover (false: none).
bool bodyPixels(const Camera& cam, const Body& b, const std::array<double, 4>& pose, LandmarkView::Item& item) {
  if (b.kind != LandmarkKind::Tree) return boxPixels(cam, footprintCorners(b), 0.0, b.h, pose, item.parts[0]);
  // A trunk's pixels apart from its crown's: most rows hold one of them only.
  const Box2 trunk(b.c - Vec2(b.r, b.r), b.c + Vec2(b.r, b.r));
  const bool t = boxPixels(cam, corners(trunk), 0.0, b.post_top, pose, item.parts[0]);
  const bool c = boxPixels(cam, corners(b.box), b.crown_z - b.crown_r, b.h, pose, item.parts[1]);
  return t || c;
}

}  // namespace

LandmarkView World::Impl::landmarkView(const RayTable& rays, const RayExtras& extras,
                                       const std::array<double, 4>& pose) const {
  LandmarkView view;
  if (landmarks.bodies.empty()) return view;
  const auto [ch, sh, tx, ty] = pose;
  const Camera& cam = rays.camera();
  const Vec3 c = cam.center();
  view.eye = Vec3(ch * c.x() - sh * c.y() + tx, sh * c.x() + ch * c.y() + ty, c.z());
  view.ch = ch, view.sh = sh;
  view.dirs = extras.dirs.empty() ? nullptr : extras.dirs.data();
  // The ground the frame sees (world box) and, with the eye's ground point, where a ray may meet a
  // body before the ground. Without ground in view every body is projected.
  const bool ground = extras.ground.ground;
  Box2 seen, reach;
  if (ground) {
    const RayExtras::TileBox& g = extras.ground;
    for (const Vec2& q : {Vec2(g.x0, g.y0), Vec2(g.x1, g.y0), Vec2(g.x0, g.y1), Vec2(g.x1, g.y1)})
      seen.extend(Vec2(ch * q.x() - sh * q.y() + tx, sh * q.x() + ch * q.y() + ty));
    reach = seen;
    reach.extend(Vec2(view.eye.x(), view.eye.y()));
  }
  for (std::size_t i = 0; i < landmarks.bodies.size(); ++i) {
    const Body& b = landmarks.bodies[i];
    LandmarkView::Item item{static_cast<std::uint32_t>(i)};
    bool keep = b.upright() && (!ground || b.box.intersects(reach)) && bodyPixels(cam, b, pose, item);
    if (!keep) item = {static_cast<std::uint32_t>(i)};
    // Its shadow or cover: the marks on the ground in view.
    for (std::uint32_t k = 0; ground && !keep && k < b.n_marks; ++k) {
      const Box2& box = landmarks.marks[b.first_mark + k].box;
      PixelBox ignored;
      keep = box.intersects(seen) && boxPixels(cam, corners(box), 0.0, 0.0, pose, ignored);
    }
    if (!keep) continue;
    view.bodies = view.bodies || item.hasPixels();
    view.items.push_back(item);
  }
  if (view.dirs == nullptr) view.bodies = false;
  return view;
}

bool World::Impl::bodyRow(const RayTable& rays, const LandmarkView& view, int v, RowScratch& rs, float* rgb,
                          std::uint8_t* mask, std::uint8_t* lmask) const {
  const int w = rays.width();
  bool any = false;
  const auto rayAt = [&](int u) {
    const float* d = view.dirs + 3 * (static_cast<std::size_t>(v) * w + u);
    return Vec3(view.ch * d[0] - view.sh * d[1], view.sh * d[0] + view.ch * d[1], d[2]).normalized();
  };
  for (std::size_t s = 0; s < view.items.size(); ++s) {
    const LandmarkView::Item& item = view.items[s];
    int u0 = std::numeric_limits<int>::max(), u1 = -1;  // the row's columns in its parts' boxes
    for (const PixelBox& box : item.parts)
      if (box.holdsRow(v)) u0 = std::min(u0, box.u0), u1 = std::max(u1, box.u1);
    if (u1 < 0) continue;
    if (!any) rs.hit_slot.assign(static_cast<std::size_t>(w), -1), rs.hits.resize(static_cast<std::size_t>(w));
    any = true;
    const Body& body = landmarks.bodies[item.landmark];
    for (int u = u0; u <= u1; ++u) {
      const RayTable::Ray& r = rays.at(u, v);
      if (r.kind == RayTable::Kind::None) continue;
      const auto k = static_cast<std::size_t>(u);
      double t_max = r.kind == RayTable::Kind::Ground ? r.range : std::numeric_limits<double>::infinity();
      if (rs.hit_slot[k] >= 0) t_max = std::min(t_max, rs.hits[k].t);
      if (hitBody(body, view.eye, rayAt(u), t_max, rs.hits[k])) rs.hit_slot[k] = static_cast<int>(s);
    }
  }
  if (!any) return false;
  for (int u = 0; u < w; ++u) {
    const auto k = static_cast<std::size_t>(u);
    if (rs.hit_slot[k] < 0) continue;
    const BodyHit& hit = rs.hits[k];
    const Vec3 d = rayAt(u);
    // The pixel's size where it meets the body: the range times the angle to the next pixel's ray.
    const int un = u + 1 < w && rays.at(u + 1, v).kind != RayTable::Kind::None ? u + 1 : u - 1;
    const double angle = un >= 0 && rays.at(un, v).kind != RayTable::Kind::None ? (rayAt(un) - d).norm() : 1e-3;
    const Body& body = landmarks.bodies[view.items[static_cast<std::size_t>(rs.hit_slot[k])].landmark];
    C3 c = landmarks.bodyColour(body, view.eye + hit.t * d, d, hit, hit.t * angle);
    if (options.haze_distance_m > 0) c = lerp(c, C3{196, 206, 218}, hazeAt(hit.t));
    rgb[3 * k] = c.r, rgb[3 * k + 1] = c.g, rgb[3 * k + 2] = c.b;
    mask[k] = 0;
    lmask[k] = kShowsBody;
    ++rs.shown[static_cast<std::size_t>(rs.hit_slot[k])];
  }
  return true;
}

std::vector<LandmarkInView> World::Impl::landmarkTruth(const Camera& cam, const LandmarkView& view,
                                                       const std::array<double, 4>& pose,
                                                       const std::vector<int>& shown) const {
  std::vector<LandmarkInView> out;
  const Vec2 eye_ground(view.eye.x(), view.eye.y());
  for (std::size_t s = 0; s < view.items.size(); ++s) {
    const std::uint32_t index = view.items[s].landmark;
    const Body& b = landmarks.bodies[index];
    const auto at = cam.project(toVehicle(pose, Vec3(b.c.x(), b.c.y(), 0.0)));
    if (!at || !cam.inImage(*at)) continue;
    const Vec2 base = baseOf(b, eye_ground);
    const Vec3 base3(base.x(), base.y(), 0.0);
    LandmarkInView lv;
    lv.index = index;
    lv.pixels = shown[s];
    lv.base_px = cam.project(toVehicle(pose, base3)).value_or(*at);
    lv.top_px = b.upright() ? cam.project(toVehicle(pose, Vec3(base.x(), base.y(), b.h))) : std::optional(lv.base_px);
    // The base hidden: a nearer body on the line of sight to it.
    const double dist = (base3 - view.eye).norm();
    const Vec3 d = (base3 - view.eye) / dist;
    lv.base_visible = true;
    for (const LandmarkView::Item& other : view.items) {
      BodyHit hit;
      if (other.landmark != index && other.hasPixels() &&
          hitBody(landmarks.bodies[other.landmark], view.eye, d, dist * (1 - 1e-9), hit))
        lv.base_visible = false;
    }
    if (lv.pixels > 0 || lv.base_visible) out.push_back(lv);  // else nearer landmarks hide it whole
  }
  return out;
}

std::vector<std::size_t> World::landmarksInView(const RayTable& rays, const Pose2& pose) const {
  const std::array<double, 4> pose4{std::cos(pose.heading()), std::sin(pose.heading()), pose.x(), pose.y()};
  const world_detail::LandmarkView view = impl_->landmarkView(rays, *impl_->rayExtras(rays), pose4);
  std::vector<std::size_t> out;
  for (const auto& item : view.items) out.push_back(item.landmark);
  return out;
}

}  // namespace mapnav
