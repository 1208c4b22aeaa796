#pragma once
// The synthetic world's noise (internal to sim/src): hashing, value noise and its fractal sums
// filtered by a pixel's footprint, coverage of thin lines and cracks, and colour arithmetic. All of
// it is a pure function of the seed and the world point, so frames are deterministic.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapnav/geometry/types.h"

namespace mapnav::world_detail {

// ---------------------------------------------------------------------------------------------
// Hashing and noise.

[[gnu::always_inline]] inline std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}
[[gnu::always_inline]] inline std::uint64_t hash2(std::uint64_t salt, std::int64_t a, std::int64_t b) {
  return mix64(salt ^ (static_cast<std::uint64_t>(a) * 0x9E3779B97F4A7C15ULL) ^
               (static_cast<std::uint64_t>(b) * 0xC2B2AE3D27D4EB4FULL));
}
/// [0, 1)
[[gnu::always_inline]] inline float unit01(std::uint64_t h) { return static_cast<float>(h >> 40) * (1.0f / 16777216.0f); }
/// [-1, 1)
[[gnu::always_inline]] inline float unitSigned(std::uint64_t h) { return unit01(h) * 2.0f - 1.0f; }

/// The last lattice cell one noise channel (one salt, one octave) looked up, with its four corner
/// values. Neighbouring pixels mostly fall in the same cell (every pixel of a frame does for the
/// coarse octaves), so the corners' four hashes are computed once per cell run, not per pixel; the
/// values are the very same, so the picture does not change.
struct NoiseMemo {
  std::uint64_t salt = 0;
  std::int64_t ix = INT64_MIN, iy = INT64_MIN;  // no finite point's cell
  float a = 0, b = 0, c = 0, d = 0;
};

/// The last cell of a hash2 lattice (a concrete slab, a leaf's cell) and its hash: neighbouring
/// pixels mostly share it.
struct HashMemo {
  std::uint64_t salt = 0;
  std::int64_t a = INT64_MIN, b = INT64_MIN;  // no finite point's cell
  std::uint64_t hash = 0;
};

/// One memo per noise channel (a texture's fractal sum, the shoulder's wobble, ...) and octave.
/// One per thread that renders; a lookup without one (nullptr) hashes the corners each time.
struct NoiseCache {
  static constexpr int kOctaves = 8;
  static constexpr int kChannels = 64;
  NoiseMemo memo[kChannels * kOctaves];
  HashMemo slab, leaf;
  /// The memos of channel k (< kChannels), one per octave.
  NoiseMemo* channel(int k) { return memo + k * kOctaves; }
};
/// hash2(salt, a, b), kept in `memo` (may be nullptr) for the next call with the same cell.
inline std::uint64_t hash2(std::uint64_t salt, std::int64_t a, std::int64_t b, HashMemo* memo) {
  if (memo == nullptr) return hash2(salt, a, b);
  if (memo->a != a || memo->b != b || memo->salt != salt) *memo = {salt, a, b, hash2(salt, a, b)};
  return memo->hash;
}

/// A channel's memos, or nullptr without a cache.
inline NoiseMemo* channelOf(NoiseCache* cache, int k) { return cache != nullptr ? cache->channel(k) : nullptr; }

/// std::floor(x), inline (without SSE4.1 the library's is a call): the truncation, one less below a
/// negative non-whole x. Exact for |x| < 2^52; beyond, x is whole and the library answers.
[[gnu::always_inline]] inline double floorInline(double x) {
  if (!(std::abs(x) < 0x1p52)) return std::floor(x);
  const auto t = static_cast<double>(static_cast<std::int64_t>(x));
  return t > x ? t - 1.0 : t;
}

/// x − std::round(x) as |·|: the distance from x to its nearest whole number, inline. std::round
/// rounds half away from zero; the truncation t leaves x − t exact (Sterbenz), and |x − t| ≥ 0.5 takes
/// the next whole number away from zero, as std::round does. (The sign of a zero t does not change
/// |x − t|.) Exact for |x| < 2^52; beyond, x is whole.
[[gnu::always_inline]] inline double distanceToWhole(double x) {
  if (!(std::abs(x) < 0x1p52)) return std::abs(x - std::round(x));
  const auto t = static_cast<double>(static_cast<std::int64_t>(x));
  const double r = std::abs(x - t);
  return r >= 0.5 ? std::abs(x - (x < 0 ? t - 1.0 : t + 1.0)) : r;
}

/// Smooth value noise in [-1, 1], unit lattice. `memo` (may be nullptr) keeps the last cell's corners.
[[gnu::always_inline]] inline float valueNoise(std::uint64_t salt, double x, double y, NoiseMemo* memo = nullptr) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const float tx = static_cast<float>(x - fx), ty = static_cast<float>(y - fy);
  const float ux = tx * tx * (3.0f - 2.0f * tx), uy = ty * ty * (3.0f - 2.0f * ty);
  float a, b, c, d;
  if (memo != nullptr && memo->ix == ix && memo->iy == iy && memo->salt == salt) {
    a = memo->a, b = memo->b, c = memo->c, d = memo->d;
  } else {
    a = unitSigned(hash2(salt, ix, iy)), b = unitSigned(hash2(salt, ix + 1, iy));
    c = unitSigned(hash2(salt, ix, iy + 1)), d = unitSigned(hash2(salt, ix + 1, iy + 1));
    if (memo != nullptr) *memo = {salt, ix, iy, a, b, c, d};
  }
  const float ab = a + (b - a) * ux, cd = c + (d - c) * ux;
  return ab + (cd - ab) * uy;
}

/// How much of a pattern of `freq` cycles/m survives a pixel `footprint` m wide.
[[gnu::always_inline]] inline float filterWeight(double freq, double footprint) {
  return static_cast<float>(std::clamp(2.0 - 4.0 * freq * footprint, 0.0, 1.0));
}

/// Fractal value noise, octaves from base_freq doubling; octaves finer than the footprint fade out
/// (the result keeps its normalisation, so far away it tends to 0 = the mean colour).
/// `memo` (may be nullptr): one per octave.
[[gnu::always_inline]] inline float fbm(std::uint64_t salt, const Vec2& p, double base_freq, int octaves, double footprint,
                 NoiseMemo* memo = nullptr) {
  float sum = 0, norm = 0, amp = 1;
  double f = base_freq;
  for (int o = 0; o < octaves; ++o) {
    const float w = filterWeight(f, footprint);
    if (w > 0)
      sum += amp * w * valueNoise(salt + static_cast<std::uint64_t>(o) * 0x51ED27ULL, p.x() * f, p.y() * f,
                                  memo != nullptr ? memo + o : nullptr);
    norm += amp;
    amp *= 0.5f;
    f *= 2.0;
  }
  return sum / norm;
}

/// fbm of m points at once (the same values as m calls): point j is (xs[j], ys[j]), `footprints[j]`
/// wide; its sum goes to out[j]. Octave by octave, so that the last lattice cell stays at hand.
inline void fbmBatch(std::uint64_t salt, const double* xs, const double* ys, const float* footprints, std::size_t m,
                     double base_freq, int octaves, float* out) {
  std::fill(out, out + m, 0.0f);
  float norm = 0, amp = 1;
  double f = base_freq;
  for (int o = 0; o < octaves; ++o) {
    const std::uint64_t s = salt + static_cast<std::uint64_t>(o) * 0x51ED27ULL;
    NoiseMemo memo;
    for (std::size_t j = 0; j < m; ++j) {
      const float w = filterWeight(f, footprints[j]);
      if (w > 0) out[j] += amp * w * valueNoise(s, xs[j] * f, ys[j] * f, &memo);
    }
    norm += amp;
    amp *= 0.5f;
    f *= 2.0;
  }
  for (std::size_t j = 0; j < m; ++j) out[j] = out[j] / norm;
}

/// fbmBatch's values (bit for bit), with the CPU's vector units where it has AVX2
/// (world_noise_batch.cpp).
void fbmRow(std::uint64_t salt, const double* xs, const double* ys, const float* footprints, std::size_t m,
            double base_freq, int octaves, float* out);

/// The camera's sensor noise of subpixel j (3 × pixel + channel) of a frame: the four 16-bit fields of
/// mix64(frame_seed + j·φ) summed (a sum of four uniforms, ≈ Gaussian), scaled to [−2, 2) (sd 1/√3).
inline float sensorNoise(std::uint64_t frame_seed, std::uint64_t j) {
  const std::uint64_t hsh = mix64(frame_seed + j * 0x9E3779B97F4A7C15ULL);
  const float s = static_cast<float>(hsh & 0xFFFF) + static_cast<float>((hsh >> 16) & 0xFFFF) +
                  static_cast<float>((hsh >> 32) & 0xFFFF) + static_cast<float>(hsh >> 48);
  return s / 65536.0f - 2.0f;
}

/// sensorNoise of subpixels j0 … j0 + n − 1 into out[0 … n − 1] (bit for bit; AVX2 where the CPU has
/// it, world_noise_batch.cpp: the sums are whole numbers below 2^18, exact in any order).
void sensorNoiseRow(std::uint64_t frame_seed, std::uint64_t j0, std::size_t n, float* out);

/// std::round(std::clamp(v, lo, 255)) as a byte (lo ≥ 0 whole; clamping first is the same, the bounds
/// being whole), inline rather than the library call and without a branch on the fraction (the
/// sensor noise makes its side a coin toss).
inline std::uint8_t toByte(float v, float lo) {
  const float c = std::clamp(v, lo, 255.0f);
  const auto t = static_cast<std::int32_t>(c);
  return static_cast<std::uint8_t>(t + static_cast<std::int32_t>(c - static_cast<float>(t) >= 0.5f));  // exact
}

/// out[j] = toByte(v[j] + sigma · noise[j], lo) for j < n (bit for bit; AVX2 where the CPU has it,
/// world_noise_batch.cpp).
void bytesRow(const float* v, const float* noise, float sigma, std::size_t n, float lo, std::uint8_t* out);

[[gnu::always_inline]] inline float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

/// Coverage (0..1) of a dark line of `width` at distance `d` from the pixel centre, for a pixel
/// `footprint` wide (box-filtered).
[[gnu::always_inline]] inline float lineCoverage(double d, double width, double footprint) {
  const double fp = std::max(footprint, 1e-4);
  // Beyond the line's reach the overlap below is negative: coverage 0 (the same +0 the clamp gives).
  if (d - fp / 2 > width / 2) return 0.0f;
  const double overlap = std::min(d + fp / 2, width / 2) - std::max(d - fp / 2, -width / 2);
  return static_cast<float>(std::clamp(overlap / fp, 0.0, 1.0));
}

/// Thin wandering crack lines: where ridged noise is near zero. Returns coverage 0..1.
/// `memo` (may be nullptr): three, one per octave.
inline float crackCoverage(std::uint64_t salt, const Vec2& p, double footprint, double width, NoiseMemo* memo = nullptr) {
  constexpr double kFreq = 0.9;
  if (footprint > 0.08) return 0.0f;
  const auto at = [memo](int i) { return memo != nullptr ? memo + i : nullptr; };
  // Whether the sum so far, `n`, leaves the line out of the pixel's reach whatever the finer octaves
  // add (they move n by at most `rest`: their values are within [−1, 1]); lineCoverage's 0, times
  // the fade, is then the same +0.
  const auto outOfReach = [&](double n, double rest) {
    return (std::abs(n) - rest) / (2.4 * kFreq) > (width + std::max(footprint, 1e-4)) / 2 + 1e-9;
  };
  const float n0 = valueNoise(salt, p.x() * kFreq, p.y() * kFreq, at(0));
  if (outOfReach(n0, 0.3000001)) return 0.0f;
  const double n01 = n0 + 0.22 * valueNoise(salt + 7, p.x() * kFreq * 5, p.y() * kFreq * 5, at(1));
  // Most pixels stop here, before the finest octave's lattice, whose cells change every few pixels.
  if (outOfReach(n01, 0.0800001)) return 0.0f;
  const double n = n01 + 0.08 * valueNoise(salt + 9, p.x() * kFreq * 23, p.y() * kFreq * 23, at(2));
  // |grad| of the noise is ~2.4 × freq per unit: distance to the zero line in metres.
  const double d = std::abs(n) / (2.4 * kFreq);
  return lineCoverage(d, width, footprint) * (1.0f - static_cast<float>(footprint / 0.08));
}

struct C3 {
  float r = 0, g = 0, b = 0;
};
[[gnu::always_inline]] inline C3 operator+(C3 a, C3 b) { return {a.r + b.r, a.g + b.g, a.b + b.b}; }
[[gnu::always_inline]] inline C3 operator*(C3 a, float k) { return {a.r * k, a.g * k, a.b * k}; }
[[gnu::always_inline]] inline C3 operator*(C3 a, C3 b) { return {a.r * b.r, a.g * b.g, a.b * b.b}; }
[[gnu::always_inline]] inline C3 lerp(C3 a, C3 b, float t) { return a + (b + a * -1.0f) * t; }
inline C3 fromVec(const Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

}  // namespace mapnav::world_detail
