// The fractal sums of a row of points (fbmRow): fbmBatch's values, with AVX2 where the CPU has it.
// Octave by octave, 8 points at a time in registers: the blend weights and lattice coordinates (two
// halves of 4 in doubles), the cells' corner values (broadcast when the 8 share a cell, as in the
// coarse octaves; else lane by lane, the last cell's reused), the blend (floats). Every lane
// performs fbm's own operations in its own order, in IEEE single and double precision, and no
// operation is fused (no FMA), so the sums are bit for bit fbm's.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "world_noise.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MAPNAV_WORLD_AVX2 1
#endif

namespace mapnav::world_detail {

#ifdef MAPNAV_WORLD_AVX2
namespace {

/// The corners of the lattice cell fbmRowAvx2 last hashed (cx, cy: the cell; NaN before any).
struct CellCorners {
  double cx = std::numeric_limits<double>::quiet_NaN(), cy = cx;
  float a = 0, b = 0, c = 0, d = 0;
  /// The corners of cell (fx, fy) of salt s: hashed when it is not the last one.
  void at(std::uint64_t s, double fx, double fy) {
    if (fx == cx && fy == cy) return;
    cx = fx, cy = fy;
    const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
    a = unitSigned(hash2(s, ix, iy)), b = unitSigned(hash2(s, ix + 1, iy));
    c = unitSigned(hash2(s, ix, iy + 1)), d = unitSigned(hash2(s, ix + 1, iy + 1));
  }
};

__attribute__((target("avx2"))) void fbmRowAvx2(std::uint64_t salt, const double* xs, const double* ys,
                                                 const float* footprints, std::size_t m, double base_freq, int octaves,
                                                 float* out) {
  std::fill(out, out + m, 0.0f);
  const std::size_t m8 = m & ~std::size_t{7};
  float norm = 0, amp = 1;
  double f = base_freq;
  const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0), two = _mm256_set1_pd(2.0);
  const __m256 three = _mm256_set1_ps(3.0f), twof = _mm256_set1_ps(2.0f), zerof = _mm256_setzero_ps();
  for (int o = 0; o < octaves; ++o) {
    const std::uint64_t s = salt + static_cast<std::uint64_t>(o) * 0x51ED27ULL;
    const __m256d vf = _mm256_set1_pd(f), v4f = _mm256_set1_pd(4.0 * f);
    const __m256 vamp = _mm256_set1_ps(amp);
    CellCorners last;
    bool shows = false;  // a point's weight is > 0
    for (std::size_t j = 0; j < m8; j += 8) {
      // The footprint's weight, 4 points at a time in doubles (filterWeight's operations).
      const __m256d fp0 = _mm256_cvtps_pd(_mm_loadu_ps(footprints + j));
      const __m256d fp1 = _mm256_cvtps_pd(_mm_loadu_ps(footprints + j + 4));
      const __m256d w0 = _mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(two, _mm256_mul_pd(v4f, fp0)), zero), one);
      const __m256d w1 = _mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(two, _mm256_mul_pd(v4f, fp1)), zero), one);
      const __m256 w = _mm256_set_m128(_mm256_cvtpd_ps(w1), _mm256_cvtpd_ps(w0));
      const __m256 seen = _mm256_cmp_ps(w, zerof, _CMP_GT_OQ);
      if (_mm256_testz_ps(seen, seen)) continue;  // no point of the 8 sees the octave: their sums stay
      shows = true;
      // Lattice cells and the offsets in them.
      const __m256d x0 = _mm256_mul_pd(_mm256_loadu_pd(xs + j), vf);
      const __m256d x1 = _mm256_mul_pd(_mm256_loadu_pd(xs + j + 4), vf);
      const __m256d y0 = _mm256_mul_pd(_mm256_loadu_pd(ys + j), vf);
      const __m256d y1 = _mm256_mul_pd(_mm256_loadu_pd(ys + j + 4), vf);
      const __m256d fx0 = _mm256_floor_pd(x0), fx1 = _mm256_floor_pd(x1);
      const __m256d fy0 = _mm256_floor_pd(y0), fy1 = _mm256_floor_pd(y1);
      const __m256 tx =
          _mm256_set_m128(_mm256_cvtpd_ps(_mm256_sub_pd(x1, fx1)), _mm256_cvtpd_ps(_mm256_sub_pd(x0, fx0)));
      const __m256 ty =
          _mm256_set_m128(_mm256_cvtpd_ps(_mm256_sub_pd(y1, fy1)), _mm256_cvtpd_ps(_mm256_sub_pd(y0, fy0)));
      // The corners: all 8 in one cell (the coarse octaves: broadcast), else lane by lane.
      const double cx = _mm256_cvtsd_f64(fx0), cy = _mm256_cvtsd_f64(fy0);
      const __m256d bx = _mm256_set1_pd(cx), by = _mm256_set1_pd(cy);
      const __m256d same_x = _mm256_and_pd(_mm256_cmp_pd(fx0, bx, _CMP_EQ_OQ), _mm256_cmp_pd(fx1, bx, _CMP_EQ_OQ));
      const __m256d same_y = _mm256_and_pd(_mm256_cmp_pd(fy0, by, _CMP_EQ_OQ), _mm256_cmp_pd(fy1, by, _CMP_EQ_OQ));
      const __m256d same = _mm256_and_pd(same_x, same_y);
      __m256 va, vb, vc, vd;
      if (_mm256_movemask_pd(same) == 0xF) {
        last.at(s, cx, cy);
        va = _mm256_set1_ps(last.a), vb = _mm256_set1_ps(last.b);
        vc = _mm256_set1_ps(last.c), vd = _mm256_set1_ps(last.d);
      } else {
        alignas(32) double lx[8], ly[8];
        alignas(32) float lw[8], ca[8], cb[8], cc[8], cd[8];
        _mm256_store_pd(lx, fx0), _mm256_store_pd(lx + 4, fx1), _mm256_store_pd(ly, fy0), _mm256_store_pd(ly + 4, fy1);
        _mm256_store_ps(lw, w);
        for (int l = 0; l < 8; ++l) {
          if (lw[l] > 0) last.at(s, lx[l], ly[l]);  // a hidden point's cell is never hashed (it may not fit 64 bits)
          ca[l] = last.a, cb[l] = last.b, cc[l] = last.c, cd[l] = last.d;
        }
        va = _mm256_load_ps(ca), vb = _mm256_load_ps(cb), vc = _mm256_load_ps(cc), vd = _mm256_load_ps(cd);
      }
      // The blend and the weighted sum (where the weight is 0, the sum stays).
      const __m256 ux = _mm256_mul_ps(_mm256_mul_ps(tx, tx), _mm256_sub_ps(three, _mm256_mul_ps(twof, tx)));
      const __m256 uy = _mm256_mul_ps(_mm256_mul_ps(ty, ty), _mm256_sub_ps(three, _mm256_mul_ps(twof, ty)));
      const __m256 ab = _mm256_add_ps(va, _mm256_mul_ps(_mm256_sub_ps(vb, va), ux));
      const __m256 cd = _mm256_add_ps(vc, _mm256_mul_ps(_mm256_sub_ps(vd, vc), ux));
      const __m256 v = _mm256_add_ps(ab, _mm256_mul_ps(_mm256_sub_ps(cd, ab), uy));
      const __m256 sum = _mm256_loadu_ps(out + j);
      const __m256 added = _mm256_add_ps(sum, _mm256_mul_ps(_mm256_mul_ps(vamp, w), v));
      _mm256_storeu_ps(out + j, _mm256_blendv_ps(sum, added, seen));
    }
    for (std::size_t j = m8; j < m; ++j) {  // the rest one at a time, the same operations
      const float w = filterWeight(f, footprints[j]);
      if (!(w > 0)) continue;
      shows = true;
      const double x = xs[j] * f, y = ys[j] * f;
      const double fx = std::floor(x), fy = std::floor(y);
      const auto tx = static_cast<float>(x - fx), ty = static_cast<float>(y - fy);
      last.at(s, fx, fy);
      const float ux = tx * tx * (3.0f - 2.0f * tx), uy = ty * ty * (3.0f - 2.0f * ty);
      const float ab = last.a + (last.b - last.a) * ux, cd = last.c + (last.d - last.c) * ux;
      out[j] += amp * w * (ab + (cd - ab) * uy);
    }
    if (!shows) {
      // No point sees this octave, nor a finer one (a weight falls as f doubles): the sums stay,
      // the normalisation counts them.
      for (; o < octaves; ++o) {
        norm += amp;
        amp *= 0.5f;
      }
      break;
    }
    norm += amp;
    amp *= 0.5f;
    f *= 2.0;
  }
  const __m256 vnorm = _mm256_set1_ps(norm);
  for (std::size_t j = 0; j < m8; j += 8) _mm256_storeu_ps(out + j, _mm256_div_ps(_mm256_loadu_ps(out + j), vnorm));
  for (std::size_t j = m8; j < m; ++j) out[j] = out[j] / norm;
}

/// a · b modulo 2^64 in each 64-bit lane (AVX2 multiplies 32 × 32 bits): the low halves' product
/// plus the cross products shifted up (the high halves' product is beyond 2^64).
__attribute__((target("avx2"))) __m256i mul64(__m256i a, std::uint64_t b) {
  const __m256i lo = _mm256_set1_epi64x(static_cast<std::int64_t>(b & 0xFFFFFFFFULL));
  const __m256i hi = _mm256_set1_epi64x(static_cast<std::int64_t>(b >> 32));
  const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), lo), _mm256_mul_epu32(a, hi));
  return _mm256_add_epi64(_mm256_mul_epu32(a, lo), _mm256_slli_epi64(cross, 32));
}

__attribute__((target("avx2"))) void sensorNoiseRowAvx2(std::uint64_t frame_seed, std::uint64_t j0, std::size_t n,
                                                        float* out) {
  constexpr std::uint64_t kPhi = 0x9E3779B97F4A7C15ULL;
  const std::size_t n4 = n & ~std::size_t{3};
  const std::uint64_t x0 = frame_seed + j0 * kPhi;
  __m256i x = _mm256_set_epi64x(static_cast<std::int64_t>(x0 + 3 * kPhi), static_cast<std::int64_t>(x0 + 2 * kPhi),
                                static_cast<std::int64_t>(x0 + kPhi), static_cast<std::int64_t>(x0));
  const __m256i step = _mm256_set1_epi64x(static_cast<std::int64_t>(4 * kPhi));
  const __m256i field = _mm256_set1_epi64x(0xFFFF);
  const __m256i low32 = _mm256_setr_epi32(0, 2, 4, 6, 0, 0, 0, 0);
  const __m128 scale = _mm_set1_ps(1.0f / 65536.0f), two = _mm_set1_ps(2.0f);  // 1/65536: a power of two, exact
  for (std::size_t j = 0; j < n4; j += 4, x = _mm256_add_epi64(x, step)) {
    __m256i h = _mm256_xor_si256(x, _mm256_srli_epi64(x, 30));
    h = mul64(h, 0xbf58476d1ce4e5b9ULL);
    h = _mm256_xor_si256(h, _mm256_srli_epi64(h, 27));
    h = mul64(h, 0x94d049bb133111ebULL);
    h = _mm256_xor_si256(h, _mm256_srli_epi64(h, 31));
    const __m256i s = _mm256_add_epi64(
        _mm256_add_epi64(_mm256_and_si256(h, field), _mm256_and_si256(_mm256_srli_epi64(h, 16), field)),
        _mm256_add_epi64(_mm256_and_si256(_mm256_srli_epi64(h, 32), field), _mm256_srli_epi64(h, 48)));
    const __m128i s32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(s, low32));
    _mm_storeu_ps(out + j, _mm_sub_ps(_mm_mul_ps(_mm_cvtepi32_ps(s32), scale), two));
  }
  for (std::size_t j = n4; j < n; ++j) out[j] = sensorNoise(frame_seed, j0 + j);
}

__attribute__((target("avx2"))) void bytesRowAvx2(const float* v, const float* noise, float sigma, std::size_t n,
                                                  float lo, std::uint8_t* out) {
  const std::size_t n8 = n & ~std::size_t{7};
  const __m256 vs = _mm256_set1_ps(sigma), vlo = _mm256_set1_ps(lo), hi = _mm256_set1_ps(255.0f);
  const __m256 half = _mm256_set1_ps(0.5f);
  const __m256i one = _mm256_set1_epi32(1);
  for (std::size_t j = 0; j < n8; j += 8) {
    const __m256 x = _mm256_add_ps(_mm256_loadu_ps(v + j), _mm256_mul_ps(vs, _mm256_loadu_ps(noise + j)));
    const __m256 c = _mm256_min_ps(_mm256_max_ps(x, vlo), hi);  // finite x: std::clamp's value
    const __m256i t = _mm256_cvttps_epi32(c);
    const __m256 frac = _mm256_sub_ps(c, _mm256_cvtepi32_ps(t));
    const __m256i up = _mm256_and_si256(_mm256_castps_si256(_mm256_cmp_ps(frac, half, _CMP_GE_OQ)), one);
    const __m256i b = _mm256_add_epi32(t, up);  // 0 … 255
    const __m128i w16 = _mm_packus_epi32(_mm256_castsi256_si128(b), _mm256_extracti128_si256(b, 1));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + j), _mm_packus_epi16(w16, w16));
  }
  for (std::size_t j = n8; j < n; ++j) out[j] = toByte(v[j] + sigma * noise[j], lo);
}

}  // namespace
#endif

void bytesRow(const float* v, const float* noise, float sigma, std::size_t n, float lo, std::uint8_t* out) {
#ifdef MAPNAV_WORLD_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  if (avx2) {
    bytesRowAvx2(v, noise, sigma, n, lo, out);
    return;
  }
#endif
  for (std::size_t j = 0; j < n; ++j) out[j] = toByte(v[j] + sigma * noise[j], lo);
}

void sensorNoiseRow(std::uint64_t frame_seed, std::uint64_t j0, std::size_t n, float* out) {
#ifdef MAPNAV_WORLD_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  if (avx2) {
    sensorNoiseRowAvx2(frame_seed, j0, n, out);
    return;
  }
#endif
  for (std::size_t j = 0; j < n; ++j) out[j] = sensorNoise(frame_seed, j0 + j);
}

void fbmRow(std::uint64_t salt, const double* xs, const double* ys, const float* footprints, std::size_t m,
            double base_freq, int octaves, float* out) {
#ifdef MAPNAV_WORLD_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  if (avx2) {
    fbmRowAvx2(salt, xs, ys, footprints, m, base_freq, octaves, out);
    return;
  }
#endif
  fbmBatch(salt, xs, ys, footprints, m, base_freq, octaves, out);
}

}  // namespace mapnav::world_detail
