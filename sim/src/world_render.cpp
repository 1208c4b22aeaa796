// The synthetic world's renderer: the ray table of a camera (each pixel's ground point, range and
// footprint, or its sky elevation), and World::render, which shades every pixel and its mask,
// re-samples the pixels the paved edge crosses, then applies the camera's illumination drift, TV
// colour shift and sensor noise.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "world_scene.h"

namespace mapnav {

using namespace world_detail;

namespace {

/// Runs body(v0, v1) on bands of the rows [0, h), one band per thread (this one included).
template <class Body>
void forRowBands(int h, int threads, const Body& body) {
  const int n = std::clamp(threads, 1, std::max(1, h));
  if (n == 1) {
    body(0, h);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(n - 1));
  for (int k = 1; k < n; ++k) pool.emplace_back([&body, h, n, k] { body(h * k / n, h * (k + 1) / n); });
  body(0, h / n);
  for (std::thread& th : pool) th.join();
}

/// Each pixel's unit ray in the vehicle frame (3 floats; 0 outside the lens' field).
std::vector<float> rayDirections(const RayTable& rays) {
  const int w = rays.width(), h = rays.height();
  std::vector<float> dirs(3 * static_cast<std::size_t>(w) * h, 0.0f);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const auto d = rays.camera().ray(Vec2(u, v));
      if (!d) continue;
      const Vec3 n = d->normalized();
      float* out = dirs.data() + 3 * (static_cast<std::size_t>(v) * w + u);
      out[0] = static_cast<float>(n.x()), out[1] = static_cast<float>(n.y()), out[2] = static_cast<float>(n.z());
    }
  return dirs;
}

}  // namespace

RayTable::RayTable(const Camera& camera)
    : model_(camera.model()), intrinsics_(camera.intrinsics()), mount_(camera.mount()),
      width_(camera.width()), height_(camera.height()),
      camera_(createCamera(camera.model(), camera.intrinsics(), camera.mount())),
      rays_(static_cast<std::size_t>(width_) * height_) {
  static std::atomic<std::uint64_t> next_id{1};
  id_ = next_id.fetch_add(1, std::memory_order_relaxed);
  const Vec3 center = camera.center();
  for (int v = 0; v < height_; ++v) {
    for (int u = 0; u < width_; ++u) {
      Ray& r = rays_[static_cast<std::size_t>(v) * width_ + u];
      const Vec2 pixel(u, v);
      const auto dir = camera.ray(pixel);
      if (!dir) continue;
      const auto ground = (dir->z() < 0) ? camera.backproject(pixel) : std::nullopt;
      if (ground) {
        r.kind = Kind::Ground;
        r.x = static_cast<float>(ground->x());
        r.y = static_cast<float>(ground->y());
        r.range = static_cast<float>((Vec3(ground->x(), ground->y(), 0.0) - center).norm());
      } else {
        r.kind = Kind::Sky;
        r.elevation = static_cast<float>(std::asin(std::clamp(dir->z(), -1.0, 1.0)));
      }
    }
  }
  // Footprint: the largest distance to a neighbouring pixel's ground point.
  for (int v = 0; v < height_; ++v) {
    for (int u = 0; u < width_; ++u) {
      Ray& r = rays_[static_cast<std::size_t>(v) * width_ + u];
      if (r.kind != Kind::Ground) continue;
      float fp = 0;
      const std::array<std::pair<int, int>, 4> nb{{{u - 1, v}, {u + 1, v}, {u, v - 1}, {u, v + 1}}};
      for (const auto& [nu, nv] : nb) {
        if (nu < 0 || nv < 0 || nu >= width_ || nv >= height_) continue;
        const Ray& o = rays_[static_cast<std::size_t>(nv) * width_ + nu];
        if (o.kind == Kind::Ground) fp = std::max(fp, std::hypot(o.x - r.x, o.y - r.y));
        else fp = std::max(fp, r.range * 0.05f);  // next to the horizon: very oblique
      }
      r.footprint = fp > 0 ? fp : r.range * 0.01f;
    }
  }
}

bool RayTable::matches(const Camera& camera) const {
  return camera.model() == model_ && camera.intrinsics() == intrinsics_ && camera.mount() == mount_;
}

World::Impl::Impl(const Map& map, const WorldOptions& opts) : Shading(map, opts) {
  if (options.texel_cache_mib > 0)
    texels = std::make_unique<TexelCache>(
        std::max<std::size_t>(1, static_cast<std::size_t>(options.texel_cache_mib * 1048576.0 / sizeof(TexelTile))));
}

void World::Impl::shadeRow(const RayTable& rays, int v, const std::array<double, 4>& pose, const RenderTiles& tiles,
                           RowScratch& rs, NoiseCache& nc, TexelReader* texels, const TexelLod* lod, const float* haze,
                           float* rgb, std::uint8_t* mask, const LandmarkView* view, std::uint8_t* lmask) const {
  const auto w = static_cast<std::size_t>(rays.width());
  const auto [ch, sh, tx, ty] = pose;
  rs.begin(w);
  // The pixels that show a landmark's body are done; the others show the ground or the sky.
  const bool bodies_here = view != nullptr && view->bodies && bodyRow(rays, *view, v, rs, rgb, mask, lmask);
  // The ground pixels the texels give; where each of the others lies, grouped by their texture's
  // material; the sky.
  for (std::size_t u = 0; u < w; ++u) {
    const RayTable::Ray& r = rays.at(static_cast<int>(u), v);
    C3 c;
    if (bodies_here && rs.hit_slot[u] >= 0) {
      rs.ground[u] = GroundPoint{};  // no canopy lookups for it
      continue;
    }
    if (r.kind == RayTable::Kind::Ground) {
      const Vec2 p(ch * r.x - sh * r.y + tx, sh * r.x + ch * r.y + ty);
      const CellLists lists = tileLists(tiles, static_cast<int>(u) / kTileW, p);
      if (texels == nullptr || !texelPixel(p, r, lists, lod[u], haze != nullptr ? haze[u] : 0.0f, *texels, nc, c, mask[u])) {
        addPoint(rs, u, p, r.footprint, lists, nc);
        mask[u] = rs.ground[u].paved ? 255 : 0;
        continue;
      }
    } else if (r.kind == RayTable::Kind::Sky) {
      c = sky(r.elevation);
    }
    rgb[3 * u] = c.r;
    rgb[3 * u + 1] = c.g;
    rgb[3 * u + 2] = c.b;
  }
  shadeLocated(w, rs, nc, haze, rgb, nullptr, view, lmask);
}

bool World::Impl::texelPixel(const Vec2& p, const RayTable::Ray& r, const CellLists& lists, TexelLod lod, float haze,
                             TexelReader& texels, NoiseCache& nc, C3& c, std::uint8_t& mask) const {
  // On a cover, or beside the paved area's edge (texels of the other class): shaded on its own.
  const bool paved = pavedAt(p, lists) >= 0;
  int cover = -1;  // the landmarks' shadow here (the texels lack it), then the canopies' from the texels
  const float marks = lists.n_marks > 0 ? landmarks.marksAt(p, lists.marks, lists.n_marks, r.footprint, nullptr, &cover) : 0.0f;
  float shadow = 0;
  if (cover >= 0 || !texelColour(p, lod, paved, texels, nc, c, shadow)) return false;
  c = hazed(shadowed(c, std::max(shadow, marks)), haze);
  mask = paved ? 255 : 0;
  return true;
}

std::shared_ptr<const RayExtras> World::Impl::rayExtras(const RayTable& rays) const {
  {
    std::lock_guard lock(cache_mutex);
    if (extras && extras_id == rays.id()) return extras;
  }
  auto table = std::make_shared<RayExtras>();
  const std::vector<RayTable::Ray>& all = rays.rays();
  if (options.haze_distance_m > 0) {
    table->haze.resize(all.size());
    for (std::size_t i = 0; i < all.size(); ++i)
      if (all[i].kind == RayTable::Kind::Ground) table->haze[i] = hazeAt(all[i].range);
  }
  table->any_outside = std::any_of(all.begin(), all.end(), [](const RayTable::Ray& r) { return r.kind == RayTable::Kind::None; });
  if (texels) {
    table->lod.resize(all.size());
    for (std::size_t i = 0; i < all.size(); ++i)
      if (all[i].kind == RayTable::Kind::Ground) table->lod[i] = texelLod(all[i].footprint);
  }
  const int w = rays.width(), h = rays.height();
  if (landmarks.any_upright) table->dirs = rayDirections(rays);
  table->tiles_x = (w + kTileW - 1) / kTileW;
  table->tiles.resize(static_cast<std::size_t>(table->tiles_x) * ((h + kTileH - 1) / kTileH));
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const RayTable::Ray& r = rays.at(u, v);
      if (r.kind != RayTable::Kind::Ground) continue;
      RayExtras::TileBox& b = table->tiles[static_cast<std::size_t>(v / kTileH) * table->tiles_x + u / kTileW];
      if (!b.ground) b = {r.x, r.y, r.x, r.y, true};
      b.x0 = std::min<double>(b.x0, r.x), b.y0 = std::min<double>(b.y0, r.y);
      b.x1 = std::max<double>(b.x1, r.x), b.y1 = std::max<double>(b.y1, r.y);
    }
  for (const RayExtras::TileBox& b : table->tiles) {
    if (!b.ground) continue;
    RayExtras::TileBox& g = table->ground;
    if (!g.ground) g = b;
    g.x0 = std::min(g.x0, b.x0), g.y0 = std::min(g.y0, b.y0), g.x1 = std::max(g.x1, b.x1), g.y1 = std::max(g.y1, b.y1);
  }
  std::lock_guard lock(cache_mutex);
  extras_id = rays.id();
  extras = table;
  return table;
}

Frame World::render(const Camera& camera, const Pose2& pose, double t) const {
  std::shared_ptr<const RayTable> table;
  {
    std::lock_guard lock(impl_->cache_mutex);
    auto& cache = impl_->cache;
    for (std::size_t i = 0; i < cache.size(); ++i) {
      if (cache[i]->matches(camera)) {
        table = cache[i];
        std::rotate(cache.begin(), cache.begin() + static_cast<std::ptrdiff_t>(i), cache.begin() + static_cast<std::ptrdiff_t>(i) + 1);
        break;
      }
    }
  }
  if (!table) {
    table = std::make_shared<const RayTable>(camera);
    std::lock_guard lock(impl_->cache_mutex);
    impl_->cache.insert(impl_->cache.begin(), table);
    if (impl_->cache.size() > 4) impl_->cache.pop_back();
  }
  return render(*table, pose, t);
}

void World::Impl::edgeSamples(const RayTable& rays, int v0, int v1, const std::array<double, 4>& pose,
                              const std::uint8_t* mask, const std::uint8_t* lmask, NoiseCache& nc, float* buf) const {
  // The pixels the paved area's edge crosses: the mean of n × n samples spread over the pixel's
  // ground footprint, its sides taken from the neighbouring pixels' rays (locally affine).
  const int w = rays.width(), h = rays.height();
  const int ns = options.paved_edge_samples;
  const auto [ch, sh, tx, ty] = pose;
  const auto ground = [&](int u, int v) {
    return u >= 0 && u < w && v >= 0 && v < h && rays.at(u, v).kind == RayTable::Kind::Ground;
  };
  const auto point = [&](int u, int v) { return Vec2(rays.at(u, v).x, rays.at(u, v).y); };
  // Half the step to the next pixel along u (dv = 0) or v, from the neighbours that are ground.
  const auto halfStep = [&](int u, int v, int du, int dv) {
    const bool fwd = ground(u + du, v + dv), back = ground(u - du, v - dv);
    if (fwd && back) return Vec2(0.25 * (point(u + du, v + dv) - point(u - du, v - dv)));
    if (fwd) return Vec2(0.5 * (point(u + du, v + dv) - point(u, v)));
    if (back) return Vec2(0.5 * (point(u, v) - point(u - du, v - dv)));
    return Vec2(0, 0);
  };
  // mask: the centres' classes (mixing leaves them); a landmark's body is no ground
  const auto body = [&](std::size_t i) { return lmask != nullptr && lmask[i] == kShowsBody; };
  const auto differs = [&](int u, int v, std::uint8_t m) {
    const std::size_t i = static_cast<std::size_t>(v) * w + u;
    return ground(u, v) && mask[i] != m && !body(i);
  };
  for (int v = v0; v < v1; ++v)
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      const std::uint8_t m = mask[i];
      if (!ground(u, v) || body(i) ||
          !(differs(u - 1, v, m) || differs(u + 1, v, m) || differs(u, v - 1, m) || differs(u, v + 1, m)))
        continue;
      const RayTable::Ray& r = rays.at(u, v);
      const Vec2 su = halfStep(u, v, 1, 0), sv = halfStep(u, v, 0, 1);
      C3 sum{0, 0, 0};
      for (int a = 0; a < ns; ++a)
        for (int b = 0; b < ns; ++b) {
          const double fa = (2.0 * a + 1.0) / ns - 1.0, fb = (2.0 * b + 1.0) / ns - 1.0;  // in (−1, 1)
          const Vec2 q = Vec2(r.x, r.y) + fa * su + fb * sv;
          const Vec2 p(ch * q.x() - sh * q.y() + tx, sh * q.x() + ch * q.y() + ty);
          bool paved = false;
          sum = sum + shade(p, r.footprint, r.range, paved, &nc);
        }
      const float k = 1.0f / static_cast<float>(ns * ns);
      buf[3 * i] = sum.r * k;
      buf[3 * i + 1] = sum.g * k;
      buf[3 * i + 2] = sum.b * k;
    }
}

void World::Impl::camera(const RayTable& rays, bool any_outside, int v0, int v1, const Pose2& pose, double t,
                         float* buf, std::uint8_t* rgb) const {
  const WorldOptions& o = options;
  const int w = rays.width();
  const std::size_t i0 = static_cast<std::size_t>(v0) * w, i1 = static_cast<std::size_t>(v1) * w;
  // Slow drifts of brightness and white balance along the mission.
  const double phase = 2 * kPi * t / o.illumination_period_s;
  const auto gain = static_cast<float>(1.0 + o.illumination_drift * std::sin(phase));
  const auto wb = static_cast<float>(o.white_balance_drift * std::sin(phase / 1.618));
  const std::array<float, 3> g{gain * (1 + wb), gain, gain * (1 - wb)};
  std::vector<float> row_gain(3 * static_cast<std::size_t>(w));  // g repeated along a row: one vector loop
  for (std::size_t j = 0; j < row_gain.size(); ++j) row_gain[j] = g[j % 3];
  for (std::size_t r0 = 3 * i0; r0 < 3 * i1; r0 += row_gain.size())
    for (std::size_t j = 0; j < row_gain.size(); ++j) buf[r0 + j] *= row_gain[j];

  if (o.tv_color_shift) {
    // Chroma (B − Y, R − Y) turned, scaled and smeared along rows, as by the TV link.
    const double theta = o.tv_hue_shift_rad + 0.05 * std::sin(2 * kPi * t / 37.0);
    const auto cs = static_cast<float>(std::cos(theta) * o.tv_chroma_gain);
    const auto sn = static_cast<float>(std::sin(theta) * o.tv_chroma_gain);
    std::vector<float> y(static_cast<std::size_t>(w)), cb(static_cast<std::size_t>(w)), cr(static_cast<std::size_t>(w));
    const int rad = o.tv_chroma_blur_px;
    for (int v = v0; v < v1; ++v) {
      float* row = buf + static_cast<std::size_t>(v) * w * 3;
      for (int u = 0; u < w; ++u) {
        const float R = row[3 * u], G = row[3 * u + 1], B = row[3 * u + 2];
        const float Y = 0.299f * R + 0.587f * G + 0.114f * B;
        const float b = B - Y, r = R - Y;
        y[static_cast<std::size_t>(u)] = Y;
        cb[static_cast<std::size_t>(u)] = cs * b - sn * r;
        cr[static_cast<std::size_t>(u)] = sn * b + cs * r;
      }
      for (int u = 0; u < w; ++u) {
        float sb = 0, sr = 0;
        int cnt = 0;
        for (int d = -rad; d <= rad; ++d) {
          const int uu = std::clamp(u + d, 0, w - 1);
          sb += cb[static_cast<std::size_t>(uu)];
          sr += cr[static_cast<std::size_t>(uu)];
          ++cnt;
        }
        const float b = sb / static_cast<float>(cnt), r = sr / static_cast<float>(cnt), Y = y[static_cast<std::size_t>(u)];
        const float R = Y + r, B = Y + b;
        const float G = (Y - 0.299f * R - 0.114f * B) / 0.587f;
        row[3 * u] = R;
        row[3 * u + 1] = G;
        row[3 * u + 2] = B;
      }
    }
  }

  // Sensor noise: seeded per frame (seed, pose, time), ≈ Gaussian (a sum of four uniforms).
  std::uint64_t frame_seed = mix64(o.seed ^ 0x5E45ULL);
  for (double v : {pose.x(), pose.y(), pose.heading(), t}) frame_seed = mix64(frame_seed ^ std::bit_cast<std::uint64_t>(v));
  const auto sigma = static_cast<float>(o.noise_sigma * 1.7320508);  // sum of 4 U(-.5,.5) has sd 1/√3
  const float lo = o.low_dynamic_range ? 37.0f : 0.0f;
  // A pixel outside the lens' field gets no noise: a 0 added leaves its byte (toByte(v + 0) = toByte(v)).
  std::vector<float> noise(3 * static_cast<std::size_t>(w), 0.0f);
  for (std::size_t r0 = i0; r0 < i1; r0 += static_cast<std::size_t>(w)) {  // a row at a time
    if (sigma > 0) {
      sensorNoiseRow(frame_seed, 3 * r0, noise.size(), noise.data());
      if (any_outside)
        for (std::size_t i = r0; i < r0 + static_cast<std::size_t>(w); ++i)
          if (rays.rays()[i].kind == RayTable::Kind::None) std::fill_n(noise.data() + 3 * (i - r0), 3, 0.0f);
    }
    bytesRow(buf + 3 * r0, noise.data(), sigma, noise.size(), lo, rgb + 3 * r0);
  }
}

Frame World::render(const RayTable& rays, const Pose2& pose, double t) const {
  const Impl& im = *impl_;
  const WorldOptions& o = im.options;
  const int w = rays.width(), h = rays.height();
  Frame frame{Image(w, h, 3), Image(w, h, 1), Image(w, h, 1), {}};
  std::vector<float> buf(static_cast<std::size_t>(w) * h * 3);
  const std::array<double, 4> pose4{std::cos(pose.heading()), std::sin(pose.heading()), pose.x(), pose.y()};
  const std::shared_ptr<const RayExtras> extras = im.rayExtras(rays);
  const float* haze = extras->haze.empty() ? nullptr : extras->haze.data();
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  // The landmarks that may show (none: the frame is what it was without landmarks, byte for byte).
  const LandmarkView view = im.landmarkView(rays, *extras, pose4);
  const LandmarkView* lv = view.items.empty() ? nullptr : &view;
  std::uint8_t* lmask = frame.landmark_mask.data.data();
  std::vector<int> shown(view.items.size(), 0);  // the pixels showing each, summed over the bands
  std::mutex shown_mutex;
  // Each pixel's colour depends on its row alone (the edge samples on the finished mask), so the
  // bands of rows and their threads do not change the frame.
  forRowBands(h, threads, [&](int v0, int v1) {
    const auto cache = std::make_unique<NoiseCache>();  // the noise lattice's last cells
    RowScratch scratch;
    scratch.shown.assign(view.items.size(), 0);
    RenderTiles tiles;
    TexelReader reader(im.texels.get());
    for (int v = v0; v < v1; ++v) {
      const std::size_t row = static_cast<std::size_t>(v) * w;
      if (tiles.band != v / kTileH) im.tileRow(*extras, v / kTileH, pose4, tiles);
      const float* haze_row = haze != nullptr ? haze + row : nullptr;
      im.shadeRow(rays, v, pose4, tiles, scratch, *cache, im.texels ? &reader : nullptr,
                  im.texels ? extras->lod.data() + row : nullptr, haze_row, buf.data() + 3 * row,
                  frame.mask.data.data() + row, lv, lmask + row);
    }
    const std::lock_guard lock(shown_mutex);
    for (std::size_t s = 0; s < shown.size(); ++s) shown[s] += scratch.shown[s];
  });
  forRowBands(h, threads, [&](int v0, int v1) {
    if (o.paved_edge_samples > 1) {
      const auto cache = std::make_unique<NoiseCache>();
      im.edgeSamples(rays, v0, v1, pose4, frame.mask.data.data(), lv != nullptr ? lmask : nullptr, *cache, buf.data());
    }
    im.camera(rays, extras->any_outside, v0, v1, pose, t, buf.data(), frame.rgb.data.data());
  });
  if (im.texels) im.texels->endFrame();
  if (lv != nullptr || !im.landmarks.marks.empty()) {
    for (std::uint8_t& m : frame.landmark_mask.data) m = m != 0 ? 255 : 0;
    frame.landmarks = im.landmarkTruth(rays.camera(), view, pose4, shown);
  }
  return frame;
}

}  // namespace mapnav
