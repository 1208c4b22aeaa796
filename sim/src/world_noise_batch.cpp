// The fractal sums of a row of points (fbmRow): fbmBatch's values, with AVX2 where the CPU has it.
// Octave by octave: the lattice coordinates and blend weights of 4 points at a time (doubles), the
// runs of neighbours in one cell (4 at a time) and each run's corner values (scalar), then the blend
// of 8 points at a time (floats). Every lane performs fbm's own operations in its own order, in IEEE single and double
// precision, and no operation is fused (no FMA), so the sums are bit for bit fbm's.
#include <algorithm>
#include <array>
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

/// Marks the runs of points in one lattice cell (sc.fx, sc.fy from index 1, index 0 a NaN that no
/// cell equals): sc.run[j] is point j's run, sc.start[r] run r's first point. Returns the count.
__attribute__((target("avx2,popcnt"))) std::size_t markRuns(FbmScratch& sc, std::size_t m) {
  // For each mask of 4 starts: each lane's count of starts up to it, and the starting lanes packed.
  struct Lut {
    std::array<std::array<std::int32_t, 4>, 16> count{}, pack{};
    Lut() {
      for (int mask = 0; mask < 16; ++mask) {
        int n = 0;
        for (int i = 0; i < 4; ++i) {
          if ((mask >> i) & 1) pack[mask][n++] = i;
          count[mask][i] = n;
        }
      }
    }
  };
  static const Lut lut;
  sc.fx[0] = sc.fy[0] = std::numeric_limits<double>::quiet_NaN();
  const std::size_t m4 = m & ~std::size_t{3};
  std::size_t runs = 0;
  for (std::size_t j = 0; j < m4; j += 4) {
    const __m256d x = _mm256_loadu_pd(sc.fx.data() + 1 + j), px = _mm256_loadu_pd(sc.fx.data() + j);
    const __m256d y = _mm256_loadu_pd(sc.fy.data() + 1 + j), py = _mm256_loadu_pd(sc.fy.data() + j);
    const int mask = _mm256_movemask_pd(_mm256_or_pd(_mm256_cmp_pd(x, px, _CMP_NEQ_UQ), _mm256_cmp_pd(y, py, _CMP_NEQ_UQ)));
    const __m128i base = _mm_set1_epi32(static_cast<std::int32_t>(runs) - 1);
    const __m128i count = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lut.count[static_cast<std::size_t>(mask)].data()));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(sc.run.data() + j), _mm_add_epi32(base, count));
    const __m128i pack = _mm_loadu_si128(reinterpret_cast<const __m128i*>(lut.pack[static_cast<std::size_t>(mask)].data()));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(sc.start.data() + runs),
                     _mm_add_epi32(_mm_set1_epi32(static_cast<std::int32_t>(j)), pack));
    runs += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(mask)));
  }
  for (std::size_t j = m4; j < m; ++j) {
    sc.start[runs] = static_cast<std::uint32_t>(j);
    runs += static_cast<std::size_t>(!(sc.fx[j + 1] == sc.fx[j] && sc.fy[j + 1] == sc.fy[j]));
    sc.run[j] = static_cast<std::int32_t>(runs) - 1;
  }
  return runs;
}

__attribute__((target("avx2"))) void fbmRowAvx2(std::uint64_t salt, const double* xs, const double* ys,
                                                const float* footprints, std::size_t m, double base_freq, int octaves,
                                                float* out, FbmScratch& sc) {
  std::fill(out, out + m, 0.0f);
  sc.resize(m);
  const std::size_t m4 = m & ~std::size_t{3}, m8 = m & ~std::size_t{7};
  float norm = 0, amp = 1;
  double f = base_freq;
  for (int o = 0; o < octaves; ++o) {
    const std::uint64_t s = salt + static_cast<std::uint64_t>(o) * 0x51ED27ULL;
    // Lattice cells, offsets in the cell and the footprint's weight, 4 points at a time.
    const __m256d vf = _mm256_set1_pd(f), v4f = _mm256_set1_pd(4.0 * f);
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0), two = _mm256_set1_pd(2.0);
    int shows = 0;  // a point's weight is > 0
    for (std::size_t j = 0; j < m4; j += 4) {
      const __m256d x = _mm256_mul_pd(_mm256_loadu_pd(xs + j), vf), y = _mm256_mul_pd(_mm256_loadu_pd(ys + j), vf);
      const __m256d fx = _mm256_floor_pd(x), fy = _mm256_floor_pd(y);
      _mm256_storeu_pd(sc.fx.data() + 1 + j, fx);
      _mm256_storeu_pd(sc.fy.data() + 1 + j, fy);
      _mm_storeu_ps(sc.tx.data() + j, _mm256_cvtpd_ps(_mm256_sub_pd(x, fx)));
      _mm_storeu_ps(sc.ty.data() + j, _mm256_cvtpd_ps(_mm256_sub_pd(y, fy)));
      const __m256d fp = _mm256_cvtps_pd(_mm_loadu_ps(footprints + j));
      const __m256d w = _mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(two, _mm256_mul_pd(v4f, fp)), zero), one);
      const __m128 wf = _mm256_cvtpd_ps(w);
      _mm_storeu_ps(sc.w.data() + j, wf);
      shows |= _mm_movemask_ps(_mm_cmpgt_ps(wf, _mm_setzero_ps()));
    }
    for (std::size_t j = m4; j < m; ++j) {  // the tail one at a time, the same operations
      const double x = xs[j] * f, y = ys[j] * f;
      sc.fx[j + 1] = std::floor(x);
      sc.fy[j + 1] = std::floor(y);
      sc.tx[j] = static_cast<float>(x - sc.fx[j + 1]);
      sc.ty[j] = static_cast<float>(y - sc.fy[j + 1]);
      sc.w[j] = filterWeight(f, footprints[j]);
      shows |= static_cast<int>(sc.w[j] > 0);
    }
    if (shows == 0) {
      // No point sees this octave, nor a finer one (a weight falls as f doubles): the sums stay,
      // the normalisation counts them.
      for (; o < octaves; ++o) {
        norm += amp;
        amp *= 0.5f;
      }
      break;
    }
    // Runs of neighbours in the same lattice cell: each run's corners hashed once and every point
    // given its run, 4 points at a time without a branch (the hashes are the very values
    // valueNoise takes; a hidden point's run gets its cell's, or zeros when that cell is out of
    // range, and a zero weight then keeps them out of the sum).
    const std::size_t runs = markRuns(sc, m);
    for (std::size_t r = 0; r < runs; ++r) {
      const std::size_t j = sc.start[r];
      const double cx = sc.fx[j + 1], cy = sc.fy[j + 1];
      if (!(std::abs(cx) < 0x1p62 && std::abs(cy) < 0x1p62)) {
        sc.a[r] = sc.b[r] = sc.c[r] = sc.d[r] = 0;
        continue;
      }
      const auto ix = static_cast<std::int64_t>(cx), iy = static_cast<std::int64_t>(cy);
      sc.a[r] = unitSigned(hash2(s, ix, iy)), sc.b[r] = unitSigned(hash2(s, ix + 1, iy));
      sc.c[r] = unitSigned(hash2(s, ix, iy + 1)), sc.d[r] = unitSigned(hash2(s, ix + 1, iy + 1));
    }
    // The blend and the weighted sum, 8 points at a time (where the weight is 0, the sum stays).
    const __m256 three = _mm256_set1_ps(3.0f), twof = _mm256_set1_ps(2.0f), vamp = _mm256_set1_ps(amp);
    const __m256 zerof = _mm256_setzero_ps();
    for (std::size_t j = 0; j < m8; j += 8) {
      const __m256 tx = _mm256_loadu_ps(sc.tx.data() + j), ty = _mm256_loadu_ps(sc.ty.data() + j);
      const __m256 ux = _mm256_mul_ps(_mm256_mul_ps(tx, tx), _mm256_sub_ps(three, _mm256_mul_ps(twof, tx)));
      const __m256 uy = _mm256_mul_ps(_mm256_mul_ps(ty, ty), _mm256_sub_ps(three, _mm256_mul_ps(twof, ty)));
      __m256 va, vb, vc, vd;
      if (const auto r = static_cast<std::size_t>(sc.run[j]); sc.run[j + 7] == sc.run[j]) {  // one cell: broadcast
        va = _mm256_set1_ps(sc.a[r]), vb = _mm256_set1_ps(sc.b[r]);
        vc = _mm256_set1_ps(sc.c[r]), vd = _mm256_set1_ps(sc.d[r]);
      } else {
        const __m256i run = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(sc.run.data() + j));
        va = _mm256_i32gather_ps(sc.a.data(), run, 4), vb = _mm256_i32gather_ps(sc.b.data(), run, 4);
        vc = _mm256_i32gather_ps(sc.c.data(), run, 4), vd = _mm256_i32gather_ps(sc.d.data(), run, 4);
      }
      const __m256 ab = _mm256_add_ps(va, _mm256_mul_ps(_mm256_sub_ps(vb, va), ux));
      const __m256 cd = _mm256_add_ps(vc, _mm256_mul_ps(_mm256_sub_ps(vd, vc), ux));
      const __m256 v = _mm256_add_ps(ab, _mm256_mul_ps(_mm256_sub_ps(cd, ab), uy));
      const __m256 w = _mm256_loadu_ps(sc.w.data() + j);
      const __m256 sum = _mm256_loadu_ps(out + j);
      const __m256 added = _mm256_add_ps(sum, _mm256_mul_ps(_mm256_mul_ps(vamp, w), v));
      _mm256_storeu_ps(out + j, _mm256_blendv_ps(sum, added, _mm256_cmp_ps(w, zerof, _CMP_GT_OQ)));
    }
    for (std::size_t j = m8; j < m; ++j) {  // the rest one at a time
      if (!(sc.w[j] > 0)) continue;
      const auto r = static_cast<std::size_t>(sc.run[j]);
      const float tx = sc.tx[j], ty = sc.ty[j];
      const float ux = tx * tx * (3.0f - 2.0f * tx), uy = ty * ty * (3.0f - 2.0f * ty);
      const float ab = sc.a[r] + (sc.b[r] - sc.a[r]) * ux, cd = sc.c[r] + (sc.d[r] - sc.c[r]) * ux;
      out[j] += amp * sc.w[j] * (ab + (cd - ab) * uy);
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

void FbmScratch::resize(std::size_t m) {
  for (auto* v : {&fx, &fy}) v->resize(m + 1);
  for (auto* v : {&tx, &ty, &w, &a, &b, &c, &d}) v->resize(m);
  run.resize(m);
  start.resize(m + 4);  // markRuns stores 4 at a time
}

void fbmRow(std::uint64_t salt, const double* xs, const double* ys, const float* footprints, std::size_t m,
            double base_freq, int octaves, float* out, FbmScratch& scratch) {
#ifdef MAPNAV_WORLD_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  if (avx2) {
    fbmRowAvx2(salt, xs, ys, footprints, m, base_freq, octaves, out, scratch);
    return;
  }
#endif
  (void)scratch;
  fbmBatch(salt, xs, ys, footprints, m, base_freq, octaves, out);
}

}  // namespace mapnav::world_detail
