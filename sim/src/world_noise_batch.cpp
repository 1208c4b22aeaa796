// The fractal sums of a row of points (fbmRow): fbmBatch's values, with AVX2 where the CPU has it.
// Octave by octave: the lattice coordinates and blend weights of 4 points at a time (doubles), the
// cells' corner values (scalar, the last cell reused), then the blend of 8 points at a time
// (floats). Every lane performs fbm's own operations in its own order, in IEEE single and double
// precision, and no operation is fused (no FMA), so the sums are bit for bit fbm's.
#include <algorithm>
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

/// Octave `o` of fbm at points [j0, m) one at a time (the tails of the vector loops).
void octaveTail(std::uint64_t s, const double* xs, const double* ys, const float* footprints, std::size_t j0,
                std::size_t m, double f, float amp, float* out) {
  NoiseMemo memo;
  for (std::size_t j = j0; j < m; ++j) {
    const float w = filterWeight(f, footprints[j]);
    if (w > 0) out[j] += amp * w * valueNoise(s, xs[j] * f, ys[j] * f, &memo);
  }
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
      _mm256_storeu_pd(sc.fx.data() + j, fx);
      _mm256_storeu_pd(sc.fy.data() + j, fy);
      _mm_storeu_ps(sc.tx.data() + j, _mm256_cvtpd_ps(_mm256_sub_pd(x, fx)));
      _mm_storeu_ps(sc.ty.data() + j, _mm256_cvtpd_ps(_mm256_sub_pd(y, fy)));
      const __m256d fp = _mm256_cvtps_pd(_mm_loadu_ps(footprints + j));
      const __m256d w = _mm256_min_pd(_mm256_max_pd(_mm256_sub_pd(two, _mm256_mul_pd(v4f, fp)), zero), one);
      const __m128 wf = _mm256_cvtpd_ps(w);
      _mm_storeu_ps(sc.w.data() + j, wf);
      shows |= _mm_movemask_ps(_mm_cmpgt_ps(wf, _mm_setzero_ps()));
    }
    for (std::size_t j = m4; j < m && shows == 0; ++j) shows = filterWeight(f, footprints[j]) > 0;
    if (shows == 0) {
      // No point sees this octave, nor a finer one (a weight falls as f doubles): the sums stay,
      // the normalisation counts them.
      for (; o < octaves; ++o) {
        norm += amp;
        amp *= 0.5f;
      }
      break;
    }
    // The cells' corners (the last cell's reused), where the octave shows.
    double cx = std::numeric_limits<double>::quiet_NaN(), cy = cx;
    float a = 0, b = 0, c = 0, d = 0;
    for (std::size_t j = 0; j < m4; ++j) {
      if (sc.w[j] > 0 && (sc.fx[j] != cx || sc.fy[j] != cy)) {
        cx = sc.fx[j];
        cy = sc.fy[j];
        const auto ix = static_cast<std::int64_t>(cx), iy = static_cast<std::int64_t>(cy);
        a = unitSigned(hash2(s, ix, iy)), b = unitSigned(hash2(s, ix + 1, iy));
        c = unitSigned(hash2(s, ix, iy + 1)), d = unitSigned(hash2(s, ix + 1, iy + 1));
      }
      sc.a[j] = a, sc.b[j] = b, sc.c[j] = c, sc.d[j] = d;
    }
    // The blend and the weighted sum, 8 points at a time (where the weight is 0, the sum stays).
    const __m256 three = _mm256_set1_ps(3.0f), twof = _mm256_set1_ps(2.0f), vamp = _mm256_set1_ps(amp);
    const __m256 zerof = _mm256_setzero_ps();
    for (std::size_t j = 0; j < m8; j += 8) {
      const __m256 tx = _mm256_loadu_ps(sc.tx.data() + j), ty = _mm256_loadu_ps(sc.ty.data() + j);
      const __m256 ux = _mm256_mul_ps(_mm256_mul_ps(tx, tx), _mm256_sub_ps(three, _mm256_mul_ps(twof, tx)));
      const __m256 uy = _mm256_mul_ps(_mm256_mul_ps(ty, ty), _mm256_sub_ps(three, _mm256_mul_ps(twof, ty)));
      const __m256 va = _mm256_loadu_ps(sc.a.data() + j), vb = _mm256_loadu_ps(sc.b.data() + j);
      const __m256 vc = _mm256_loadu_ps(sc.c.data() + j), vd = _mm256_loadu_ps(sc.d.data() + j);
      const __m256 ab = _mm256_add_ps(va, _mm256_mul_ps(_mm256_sub_ps(vb, va), ux));
      const __m256 cd = _mm256_add_ps(vc, _mm256_mul_ps(_mm256_sub_ps(vd, vc), ux));
      const __m256 v = _mm256_add_ps(ab, _mm256_mul_ps(_mm256_sub_ps(cd, ab), uy));
      const __m256 w = _mm256_loadu_ps(sc.w.data() + j);
      const __m256 sum = _mm256_loadu_ps(out + j);
      const __m256 added = _mm256_add_ps(sum, _mm256_mul_ps(_mm256_mul_ps(vamp, w), v));
      _mm256_storeu_ps(out + j, _mm256_blendv_ps(sum, added, _mm256_cmp_ps(w, zerof, _CMP_GT_OQ)));
    }
    // Points [m8, m4) have their corners: blend them one at a time; [m4, m) entirely so.
    for (std::size_t j = m8; j < m4; ++j) {
      if (!(sc.w[j] > 0)) continue;
      const float tx = sc.tx[j], ty = sc.ty[j];
      const float ux = tx * tx * (3.0f - 2.0f * tx), uy = ty * ty * (3.0f - 2.0f * ty);
      const float ab = sc.a[j] + (sc.b[j] - sc.a[j]) * ux, cd = sc.c[j] + (sc.d[j] - sc.c[j]) * ux;
      out[j] += amp * sc.w[j] * (ab + (cd - ab) * uy);
    }
    octaveTail(s, xs, ys, footprints, m4, m, f, amp, out);
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

}  // namespace
#endif

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
  for (auto* v : {&fx, &fy}) v->resize(m);
  for (auto* v : {&tx, &ty, &w, &a, &b, &c, &d}) v->resize(m);
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
