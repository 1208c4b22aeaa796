// The cluster-perceptron's runtime (Jochem & Baluja 1993 §5-6): every pixel classified (the colour
// lookup table, or the reference path), the road certainty summed per block, and the Hough over
// (top-row intercept × angle × curvature step) with its sub-block refinement; then find() hands the
// centre model to the edge refinement (cluster_perceptron_edges.cpp, cluster_perceptron_arc.cpp).
// The hot loops (classifyRow, blockSums, houghSearch) stay in this file with find(). See
// cluster_perceptron.h.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#ifdef __SSE2__
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cluster_perceptron_internal.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav {

namespace {

/// Per-thread scratch of find(): the frame's per-pixel certainty and its block sums, reused from
/// frame to frame so that a frame costs no allocation.
struct Scratch {
  std::vector<std::uint8_t> cert;
  std::vector<std::uint32_t> bsum;
};
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

int threadCount(int option) {
#ifdef _OPENMP
  return option == 0 ? omp_get_num_procs() : option;
#else
  (void)option;
  return 1;
#endif
}


/// Round half away from zero, without libm's call (|x| < 2³¹).
inline std::int32_t roundToInt(double x) {
  return x >= 0 ? static_cast<std::int32_t>(x + 0.5) : -static_cast<std::int32_t>(-x + 0.5);
}

/// Adds each block's certainty sum of one row to `sums` (blocks of `bs` pixels) and returns the
/// row's road pixels (certainty > 127, the byte's top bit). Eight pixels at a time with SSE2's sum
/// of absolute differences where the blocks are whole multiples of 8 pixels.
long long blockSums(const std::uint8_t* c, int width, int bs, std::uint32_t* sums) {
  const int cols = (width + bs - 1) / bs;
  long long road = 0;
  int b = 0;
#ifdef __SSE2__
  if (bs % 8 == 0) {
    const __m128i zero = _mm_setzero_si128(), ones = _mm_set1_epi8(1);
    for (; (b + 1) * bs <= width; ++b) {
      __m128i sum = zero, cnt = zero;
      for (int u = b * bs; u < (b + 1) * bs; u += 8) {
        const __m128i x = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(c + u));
        sum = _mm_add_epi64(sum, _mm_sad_epu8(x, zero));
        cnt = _mm_add_epi64(cnt, _mm_sad_epu8(_mm_and_si128(_mm_srli_epi16(x, 7), ones), zero));
      }
      sums[b] += static_cast<std::uint32_t>(_mm_cvtsi128_si32(sum));
      road += _mm_cvtsi128_si32(cnt);
    }
  }
#endif
  for (; b < cols; ++b) {
    const int u0 = b * bs, u1 = std::min(width, u0 + bs);
    std::uint32_t s = 0;
    for (int u = u0; u < u1; ++u) {
      s += c[u];
      road += c[u] > 127;
    }
    sums[b] += s;
  }
  return road;
}

struct HoughPeak {
  std::int64_t sum = std::numeric_limits<std::int64_t>::min();
  int x = 0, shift = 0, bend = 0;
};

/// The Hough's accumulation (§5): for every bend q and shift s, row i of the kernel sums `S`
/// (`rows` × 3·cols, column c of the image at index cols + c) moved by offsets[(q·shifts + s)·rows + i]
/// blocks and summed column by column; the largest column sum over the columns x_lo[s]..x_hi[s],
/// first in (q, s, x) order (none: sum stays the lowest int64). Exact integer arithmetic; built for
/// AVX2 too where the processor has it.
__attribute__((target_clones("avx2", "default"))) HoughPeak houghSearch(const std::int32_t* S, int rows, int cols,
                                                                         const int* offsets, int shifts, int bends,
                                                                         const int* x_lo, const int* x_hi) {
  HoughPeak best;
  const int ext = 3 * cols;
  std::vector<std::int32_t> acc(static_cast<std::size_t>(cols));
  for (int q = 0; q < bends; ++q)
    for (int s = 0; s < shifts; ++s) {
      if (x_lo[s] > x_hi[s]) continue;
      std::fill(acc.begin(), acc.end(), 0);
      const int* off = offsets + (static_cast<std::size_t>(q) * shifts + s) * rows;
      for (int i = 0; i < rows; ++i) {
        const std::int32_t* __restrict srow = S + static_cast<std::size_t>(i) * ext + cols + off[i];
        const int x0 = std::max(0, -cols - off[i]), x1 = std::min(cols, 2 * cols - off[i]);
        std::int32_t* __restrict a = acc.data();
        for (int x = x0; x < x1; ++x) a[x] += srow[x];
      }
      for (int x = x_lo[s]; x <= x_hi[s]; ++x)
        if (acc[x] > best.sum) best = {acc[x], x, s, q};
    }
  return best;
}

/// The certainty of the pixel at `px` (R, G, B) whose cell is ambiguous: its entry in the cell's exact
/// 8³ table.
inline std::uint8_t exactCertainty(const std::uint8_t* px, const std::uint32_t* sub_offset, const std::uint8_t* sub) {
  const unsigned cell = ((px[0] >> 3u) << 10) | ((px[1] >> 3u) << 5) | (px[2] >> 3u);
  return sub[sub_offset[cell] + (((px[0] & 7u) << 6) | ((px[1] & 7u) << 3) | (px[2] & 7u))];
}

/// The fast path's tables (ClusterPerceptron::buildLut()): the 32³ cells' certainties, and the
/// ambiguous cells' offsets into their exact 8³ tables.
struct LutView {
  const std::uint8_t* lut;
  const std::uint32_t* sub_offset;
  const std::uint8_t* sub;
};

/// The fast path's classification of one row: the colour's cell in the 32³ table, and for the
/// cells that straddle a cluster boundary, the colour's entry in the cell's exact 8³ table. Not
/// inlined: on its own its pointers and tables stay in registers (inlined into the band loop, the
/// table's pointer was reloaded from the stack for every pixel).
__attribute__((noinline)) void classifyRow(const std::uint8_t* __restrict p, std::uint8_t* __restrict c, int width,
                 const std::uint8_t* __restrict lut, const std::uint32_t* __restrict sub_offset,
                 const std::uint8_t* __restrict sub) {
  // The cell index per band from small tables: three loads and two ors instead of six shifts.
  static const auto index = [] {
    std::array<std::array<std::uint16_t, 256>, 3> t{};
    for (int x = 0; x < 256; ++x) {
      t[0][x] = static_cast<std::uint16_t>((x >> 3) << 10);
      t[1][x] = static_cast<std::uint16_t>((x >> 3) << 5);
      t[2][x] = static_cast<std::uint16_t>(x >> 3);
    }
    return t;
  }();
  const std::uint16_t *ir = index[0].data(), *ig = index[1].data(), *ib = index[2].data();
  for (int u = 0; u < width; ++u, p += 3) {
    const unsigned cell = ir[p[0]] | ig[p[1]] | ib[p[2]];
    const std::uint8_t q = lut[cell];
    c[u] = q != kAmbiguous ? q : exactCertainty(p, sub_offset, sub);
  }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define MAPNAV_CP_AVX2 1
/// The cell indices of the 8 pixels at `q` (classifyRowAvx2(); reads 32 bytes).
__attribute__((target("avx2"), always_inline)) inline __m256i cellsAvx2(const std::uint8_t* q) {
  // Bytes 0-11 to the low lane, 12-23 to the high one; then per lane 4 pixels to 4 dwords (R, G, B, 0).
  const __m256i spread = _mm256_setr_epi32(0, 1, 2, 2, 3, 4, 5, 5);
  const __m256i rgb0 = _mm256_setr_epi8(0, 1, 2, -1, 3, 4, 5, -1, 6, 7, 8, -1, 9, 10, 11, -1,  //
                                        0, 1, 2, -1, 3, 4, 5, -1, 6, 7, 8, -1, 9, 10, 11, -1);
  const __m256i five = _mm256_set1_epi8(0x1F);
  const __m256i rg = _mm256_set1_epi32(0x00010120);  // bytes 32, 1, 1, 0: r5·32 + g5 and b5
  const __m256i by32 = _mm256_set1_epi32(0x00010020);  // words 32, 1
  const __m256i x = _mm256_permutevar8x32_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(q)), spread);
  const __m256i b5 = _mm256_and_si256(_mm256_srli_epi16(_mm256_shuffle_epi8(x, rgb0), 3), five);  // r5, g5, b5, 0
  return _mm256_madd_epi16(_mm256_maddubs_epi16(b5, rg), by32);  // (r5·32 + g5)·32 + b5
}

/// The 16 certainties of the pixels at `p` (48 bytes; reads 56) from the table: the cells' bytes by
/// two 8-lane gathers (4 bytes read from each cell's byte: the table has 3 bytes of padding).
__attribute__((target("avx2"), always_inline)) inline __m128i lookup16Avx2(const std::uint8_t* p, const std::uint8_t* lut) {
  // The gathered dwords' low bytes to dword 0 of each lane (first 8 pixels) or dword 1 (next 8), then
  // the dwords in pixel order.
  const __m256i first = _mm256_setr_epi8(0, 4, 8, 12, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1,  //
                                         0, 4, 8, 12, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1);
  const __m256i second = _mm256_setr_epi8(-1, -1, -1, -1, 0, 4, 8, 12, -1, -1, -1, -1, -1, -1, -1, -1,  //
                                          -1, -1, -1, -1, 0, 4, 8, 12, -1, -1, -1, -1, -1, -1, -1, -1);
  const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 3, 6, 7);
  const int* const table = reinterpret_cast<const int*>(lut);
  const __m256i q0 = _mm256_i32gather_epi32(table, cellsAvx2(p), 1);
  const __m256i q1 = _mm256_i32gather_epi32(table, cellsAvx2(p + 24), 1);
  return _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
      _mm256_or_si256(_mm256_shuffle_epi8(q0, first), _mm256_shuffle_epi8(q1, second)), order));
}

/// classifyRow() and blockSums() of one row in one pass, 16 pixels at a time with AVX2 (blocks of a
/// multiple of 8 pixels): the certainties from the table (lookup16Avx2()), the ambiguous cells (255)
/// classified one by one as classifyRow() does, then each 8 pixels' sum (sum of absolute differences)
/// added to its block's and the road pixels (the bytes' top bits) counted. The same bytes, sums and
/// count as classifyRow() and blockSums(). `last_row`: the frame's last (nothing to read beyond it).
__attribute__((target("avx2"))) long long classifySumRowAvx2(const std::uint8_t* __restrict p, std::uint8_t* __restrict c,
                                                            int width, const std::uint8_t* __restrict lut,
                                                            const std::uint32_t* __restrict sub_offset,
                                                            const std::uint8_t* __restrict sub, int bs,
                                                            std::uint32_t* __restrict sums, bool last_row) {
  const __m128i ambiguous = _mm_set1_epi8(static_cast<char>(kAmbiguous)), zero = _mm_setzero_si128();
  const int groups = bs / 8;  // 8-pixel groups per block
  int u = 0, block = 0, left = groups;  // the block of pixel u, and its groups from u on
  long long road = 0;
  const auto add = [&](std::uint32_t sum) {
    sums[block] += sum;
    if (--left == 0) {
      ++block;
      left = groups;
    }
  };
  // The loads read 32 bytes from each 8 pixels' first, 8 beyond the 16 pixels: into the next row,
  // but not past the frame's last.
  for (const int end = last_row ? width - 3 : width; u + 16 <= end; u += 16, p += 48) {
    __m128i q = lookup16Avx2(p, lut);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(c + u), q);
    if (const unsigned amb = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(q, ambiguous))); amb != 0) {
      for (unsigned m = amb; m != 0; m &= m - 1) {
        const int k = __builtin_ctz(m);
        c[u + k] = exactCertainty(p + 3 * k, sub_offset, sub);
      }
      q = _mm_loadu_si128(reinterpret_cast<const __m128i*>(c + u));
    }
    road += __builtin_popcount(static_cast<unsigned>(_mm_movemask_epi8(q)));
    const __m128i s = _mm_sad_epu8(q, zero);
    add(static_cast<std::uint32_t>(_mm_cvtsi128_si32(s)));
    add(static_cast<std::uint32_t>(_mm_extract_epi32(s, 2)));
  }
  _mm256_zeroupper();
  if (u < width) classifyRow(p, c + u, width - u, lut, sub_offset, sub);
  for (; u < width; ++u) {
    sums[u / bs] += c[u];
    road += c[u] > 127;
  }
  return road;
}
#endif


#if defined(MAPNAV_CP_AVX2)
#define MAPNAV_CP_AVX512 1
#define MAPNAV_CP_AVX512_TARGET "avx512f,avx512bw,avx512vbmi,gfni"
/// lookup64Avx512()'s byte picks: pixel k of the 16-pixel group g (bytes 48g + 3k.. of the 192) from
/// the 128 bytes v0:v1 (groups 0, 1) or v1:v2 (groups 2, 3), its R, G, B to bytes 4k..4k+2.
constexpr auto kPicks = [] {
  std::array<std::array<std::uint8_t, 64>, 4> t{};
  for (int g = 0; g < 4; ++g)
    for (int k = 0; k < 16; ++k)
      for (int j = 0; j < 4; ++j) t[g][4 * k + j] = static_cast<std::uint8_t>(48 * g - (g < 2 ? 0 : 64) + 3 * k + std::min(j, 2));
  return t;
}();

/// The cell indices of the 16 pixels whose 48 bytes `pick` takes from the 128 bytes (a, b) (bit 6 of
/// a byte of `pick`: from b), pixel k's R, G, B to bytes 4k..4k+2 (byte 4k+3 weighs nothing).
__attribute__((target(MAPNAV_CP_AVX512_TARGET), always_inline)) inline __m512i cells16Avx512(__m512i a, __m512i b,
                                                                                           __m512i pick) {
  const __m512i rgbx = _mm512_permutex2var_epi8(a, pick, b);
  // Every byte shifted right by 3 (the GF(2) affine map whose row for bit i picks bit i + 3).
  const __m512i five = _mm512_gf2p8affine_epi64_epi8(rgbx, _mm512_set1_epi64(0x0810204080000000LL), 0);
  const __m512i rg = _mm512_maddubs_epi16(five, _mm512_set1_epi32(0x00010120));  // words r5·32 + g5, b5
  return _mm512_madd_epi16(rg, _mm512_set1_epi32(0x00010020));                   // (r5·32 + g5)·32 + b5
}

/// The 64 certainties of the 64 pixels (192 bytes) at `p` from the table: four 16-lane gathers (4
/// bytes read from each cell's byte: the table has 3 bytes of padding), their low bytes packed in
/// pixel order. Ambiguous cells stay 255.
__attribute__((target(MAPNAV_CP_AVX512_TARGET), always_inline)) inline __m512i lookup64Avx512(const std::uint8_t* p,
                                                                                            const std::uint8_t* lut) {
  static constexpr auto low_bytes = [] {  // byte j: byte 4j of a (j < 16) or 4(j − 16) of b (j < 32), twice
    std::array<std::uint8_t, 64> t{};
    for (int j = 0; j < 64; ++j) t[j] = static_cast<std::uint8_t>(j % 32 < 16 ? 4 * (j % 32) : 64 + 4 * (j % 32 - 16));
    return t;
  }();
  const __m512i v0 = _mm512_loadu_si512(p), v1 = _mm512_loadu_si512(p + 64), v2 = _mm512_loadu_si512(p + 128);
  // (The masked gather: g++ 12's unmasked one warns of its undefined source.)
  const auto gather = [lut](__m512i cells) __attribute__((target(MAPNAV_CP_AVX512_TARGET))) {
    return _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), 0xFFFF, cells, lut, 1);
  };
  const __m512i q0 = gather(cells16Avx512(v0, v1, _mm512_loadu_si512(kPicks[0].data())));
  const __m512i q1 = gather(cells16Avx512(v0, v1, _mm512_loadu_si512(kPicks[1].data())));
  const __m512i q2 = gather(cells16Avx512(v1, v2, _mm512_loadu_si512(kPicks[2].data())));
  const __m512i q3 = gather(cells16Avx512(v1, v2, _mm512_loadu_si512(kPicks[3].data())));
  const __m512i low = _mm512_loadu_si512(low_bytes.data());
  const __m512i q01 = _mm512_permutex2var_epi8(q0, low, q1), q23 = _mm512_permutex2var_epi8(q2, low, q3);
  return _mm512_mask_shuffle_i64x2(q01, 0xFF, q01, q23, 0x44);  // q01's low 32 bytes, then q23's (masked: see gather)
}

/// The certainties `q` of the 64 pixels at `p` (lookup64Avx512()) with those of the ambiguous cells
/// (255, lanes `amb`) from their cells' exact 8³ tables, as exactCertainty(): per 16 pixels, the
/// cells' table offsets and then the colours' bytes by masked gathers (the tables have 3 bytes of
/// padding). Not inlined: a vector in six holds such a pixel (the park scene at 1024 x 1024).
__attribute__((target(MAPNAV_CP_AVX512_TARGET), noinline)) __m512i exactAvx512(const std::uint8_t* p, __m512i q,
                                                                             std::uint64_t amb, const LutView& t) {
  const __m512i v[3] = {_mm512_loadu_si512(p), _mm512_loadu_si512(p + 64), _mm512_loadu_si512(p + 128)};
  for (int g = 0; g < 4; ++g) {
    const auto m = static_cast<__mmask16>(amb >> (16 * g));
    if (m == 0) continue;
    const __m512i a = v[g < 2 ? 0 : 1], b = v[g < 2 ? 1 : 2], pick = _mm512_loadu_si512(kPicks[g].data());
    // The colour's place in its cell's table: (R & 7)·64 + (G & 7)·8 + (B & 7).
    const __m512i low3 = _mm512_and_si512(_mm512_permutex2var_epi8(a, pick, b), _mm512_set1_epi8(7));
    const __m512i at = _mm512_madd_epi16(_mm512_maddubs_epi16(low3, _mm512_set1_epi32(0x00010840)),
                                         _mm512_set1_epi32(0x00010001));
    const __m512i zero = _mm512_setzero_si512();
    const __m512i offset = _mm512_mask_i32gather_epi32(zero, m, cells16Avx512(a, b, pick), t.sub_offset, 4);
    const __m512i exact = _mm512_mask_i32gather_epi32(zero, m, _mm512_add_epi32(offset, at), t.sub, 1);
    // The 16 low bytes to every 16-byte lane, kept in group g's lanes where ambiguous.
    const __m512i bytes = _mm512_maskz_broadcast_i32x4(0xFFFF, _mm512_maskz_cvtepi32_epi8(0xFFFF, exact));  // (masked: see gather)
    q = _mm512_mask_mov_epi8(q, static_cast<__mmask64>(m) << (16 * g), bytes);
  }
  return q;
}

/// classifyRow() and blockSums() of one row, 64 pixels at a time with AVX-512 (VBMI, GFNI): the
/// certainties from the table (lookup64Avx512()), the ambiguous cells' (255) from their exact tables
/// (exactAvx512()), each 8 pixels' sum (sum of absolute differences) added to `groups` (per 8
/// pixels of the row, summed over the band's rows; blocks of a multiple of 8 pixels add them up),
/// and the road pixels (the bytes' top bits) counted. Pixels beyond the last 64 go to their block in
/// `sums` directly. The same bytes, sums and count as classifyRow() and blockSums().
__attribute__((target(MAPNAV_CP_AVX512_TARGET))) long long classifySumRowAvx512(
    const std::uint8_t* __restrict p, std::uint8_t* __restrict c, int width, const LutView& t, int bs,
    std::uint64_t* __restrict groups, std::uint32_t* __restrict sums) {
  const __m512i ambiguous = _mm512_set1_epi8(static_cast<char>(kAmbiguous)), zero = _mm512_setzero_si512();
  long long road = 0;
  int u = 0;
  for (; u + 64 <= width; u += 64, p += 192) {
    __m512i q = lookup64Avx512(p, t.lut);
    if (const std::uint64_t amb = _mm512_cmpeq_epi8_mask(q, ambiguous); amb != 0) [[unlikely]]
      q = exactAvx512(p, q, amb, t);
    _mm512_storeu_si512(c + u, q);
    road += __builtin_popcountll(_mm512_movepi8_mask(q));
    std::uint64_t* const g = groups + u / 8;
    _mm512_storeu_si512(g, _mm512_add_epi64(_mm512_loadu_si512(g), _mm512_sad_epu8(q, zero)));
  }
  if (u < width) classifyRow(p, c + u, width - u, t.lut, t.sub_offset, t.sub);
  for (; u < width; ++u) {
    sums[u / bs] += c[u];
    road += c[u] > 127;
  }
  return road;
}
#endif

std::atomic<int> simd_cap{static_cast<int>(ParkSimd::Avx512)};

/// The widest vector code this processor runs, at most the cap (setParkSimdCap()).
ParkSimd parkSimd() {
#ifdef MAPNAV_CP_AVX2
  static const ParkSimd cpu = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                                      __builtin_cpu_supports("avx512vbmi") && __builtin_cpu_supports("gfni")
                                  ? ParkSimd::Avx512
                              : __builtin_cpu_supports("avx2") ? ParkSimd::Avx2
                                                               : ParkSimd::Portable;
#else
  constexpr ParkSimd cpu = ParkSimd::Portable;
#endif
  return static_cast<ParkSimd>(std::min(static_cast<int>(cpu), simd_cap.load(std::memory_order_relaxed)));
}

/// One band of block rows (the bs rows from v0, block row `sums`) of classifyFrame() on the fast path,
/// with the widest vector code `simd` allows. Returns the band's road pixels.
long long classifyBandFast(const LutView& t, const std::uint8_t* rgb, std::uint8_t* cimg, int width, int height, int v0,
                           int bs, std::uint32_t* sums, ParkSimd simd) {
  const int v1 = std::min(height, v0 + bs);
  long long road = 0;
#ifdef MAPNAV_CP_AVX512
  if (simd == ParkSimd::Avx512 && bs % 8 == 0) {
    // Per 8 pixels of the row, summed over the band; each block then adds up its bs / 8.
    thread_local std::vector<std::uint64_t> groups;
    groups.assign(static_cast<std::size_t>(width / 64 * 8), 0);
    for (int v = v0; v < v1; ++v)
      road += classifySumRowAvx512(rgb + static_cast<std::size_t>(v) * width * 3, cimg + static_cast<std::size_t>(v) * width,
                                   width, t, bs, groups.data(), sums);
    // Group g in block g / (bs / 8): a shift where bs / 8 is a power of two (a division per group cost
    // as much as 3 % of find() at 1024 x 1024).
    const unsigned per_block = static_cast<unsigned>(bs / 8);
    if ((per_block & (per_block - 1)) == 0) {
      const int shift = std::countr_zero(per_block);
      for (std::size_t g = 0; g < groups.size(); ++g) sums[g >> shift] += static_cast<std::uint32_t>(groups[g]);
    } else {
      for (std::size_t g = 0; g < groups.size(); ++g) sums[g / per_block] += static_cast<std::uint32_t>(groups[g]);
    }
    return road;
  }
#endif
  for (int v = v0; v < v1; ++v) {
    const std::uint8_t* p = rgb + static_cast<std::size_t>(v) * width * 3;
    std::uint8_t* c = cimg + static_cast<std::size_t>(v) * width;
#ifdef MAPNAV_CP_AVX2
    if (simd >= ParkSimd::Avx2 && bs % 8 == 0) {
      road += classifySumRowAvx2(p, c, width, t.lut, t.sub_offset, t.sub, bs, sums, v == height - 1);
      continue;
    }
#endif
    classifyRow(p, c, width, t.lut, t.sub_offset, t.sub);
    road += blockSums(c, width, bs, sums);
  }
  return road;
}

/// §6: every pixel's road certainty (into scr.cert) and each block's sum of them (scr.bsum), one band
/// of block rows per task: the bands write disjoint rows of both, so threads do not change the answer.
/// The fast path reads the lookup table; the reference path classifies every pixel by
/// finder.outputReference(). Returns the frame's road pixels.
long long classifyFrame(const ClusterPerceptron& finder, const LutView& tables, const std::uint8_t* rgb, int width,
                        int height, Scratch& scr) {
  const ClusterPerceptronOptions& opt = finder.options();
  const int bs = opt.block_size;
  const int cols = (width + bs - 1) / bs, rows = (height + bs - 1) / bs;
  scr.cert.resize(static_cast<std::size_t>(width) * height);
  scr.bsum.assign(static_cast<std::size_t>(cols) * rows, 0);
  std::uint8_t* const cimg = scr.cert.data();
  std::uint32_t* const bsum = scr.bsum.data();
  const bool fast = opt.fast;
  const ParkSimd simd = parkSimd();
  long long road_px = 0;
  const int nt = std::min(threadCount(opt.threads), rows);
#pragma omp parallel for num_threads(nt) if (nt > 1) schedule(static) reduction(+ : road_px)
  for (int r = 0; r < rows; ++r) {
    const int v0 = r * bs, v1 = std::min(height, (r + 1) * bs);
    std::uint32_t* const sums = bsum + static_cast<std::size_t>(r) * cols;
    if (fast) {
      road_px += classifyBandFast(tables, rgb, cimg, width, height, v0, bs, sums, simd);
      continue;
    }
    for (int v = v0; v < v1; ++v) {
      const std::uint8_t* p = rgb + static_cast<std::size_t>(v) * width * 3;
      std::uint8_t* c = cimg + static_cast<std::size_t>(v) * width;
      for (int u = 0; u < width; ++u, p += 3) c[u] = certaintyOf(finder.outputReference(p[0], p[1], p[2]));
      road_px += blockSums(c, width, bs, sums);
    }
  }
  return road_px;
}

/// The road mask of the certainties: 255 where the certainty is above 127.
Image roadMask(const std::vector<std::uint8_t>& cert, int width, int height) {
  Image mask(width, height, 1);
  for (std::size_t i = 0; i < cert.size(); ++i) mask.data[i] = cert[i] > 127 ? 255 : 0;
  return mask;
}

/// One frame's Hough problem (§5) on the grid of blocks (`bs` pixels square, `cols` × `rows`).
struct HoughGrid {
  int bs = 0, cols = 0, rows = 0;
  std::vector<double> sc;  // per block: signed certainty, -127.5..+127.5
  std::vector<double> wb;  // per block row: the bootstrap's road width, blocks
  std::vector<int> rr;     // the road block rows (at least a block wide), top to bottom
  std::vector<double> tr;  // per road row: t, from 0 on the top road row to 1 on the bottom one
  std::vector<double> gb;  // per road row: the arc's offset per curvature step, blocks (0: the line)
};

/// The grid of a frame's block sums: signed certainties, and the road rows with their widths.
HoughGrid houghGrid(const std::vector<std::uint32_t>& bsum, const std::vector<double>& row_widths, int width,
                    int height, int bs) {
  HoughGrid g;
  g.bs = bs;
  const int cols = g.cols = (width + bs - 1) / bs, rows = g.rows = (height + bs - 1) / bs;
  // Signed certainty per block: -127.5..+127.5.
  g.sc.assign(bsum.size(), 0.0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int npx = (std::min(width, (c + 1) * bs) - c * bs) * (std::min(height, (r + 1) * bs) - r * bs);
      g.sc[static_cast<std::size_t>(r) * cols + c] =
          static_cast<double>(bsum[static_cast<std::size_t>(r) * cols + c]) / (npx * static_cast<double>(kCertaintyMax)) * 255.0 - 127.5;
    }
  // Road rows and their widths in blocks.
  g.wb.assign(rows, 0.0);
  for (int r = 0; r < rows; ++r) {
    const int vc = std::min(height - 1, r * bs + bs / 2);
    g.wb[r] = row_widths[vc] / bs;
    if (g.wb[r] >= 1.0) g.rr.push_back(r);
  }
  if (g.rr.size() < 2) return g;
  const int r0 = g.rr.front(), rl = g.rr.back();
  const double span = std::max(1, rl - r0);
  g.tr.resize(g.rr.size());
  for (std::size_t i = 0; i < g.rr.size(); ++i) g.tr[i] = (g.rr[i] - r0) / span;
  g.gb.assign(g.rr.size(), 0.0);
  return g;
}

/// Per-row horizontal summation kernel over an extended column range [-cols, 2 cols), in fixed
/// point (1/1024) so that the Hough's sums are exact integers, in any order, and vectorise; and the
/// largest sum a centre line can reach (`max_possible`).
std::vector<std::int32_t> kernelSums(const HoughGrid& g, double& max_possible) {
  const int cols = g.cols, ext = 3 * cols;
  std::vector<std::int32_t> S(g.rr.size() * ext, 0);
  std::vector<double> prefix(static_cast<std::size_t>(cols) + 1);
  max_possible = 0;
  for (std::size_t i = 0; i < g.rr.size(); ++i) {
    const int r = g.rr[i];
    prefix[0] = 0;
    for (int c = 0; c < cols; ++c) prefix[c + 1] = prefix[c] + g.sc[static_cast<std::size_t>(r) * cols + c];
    const int k = std::max(1, static_cast<int>(std::lround(g.wb[r])));
    max_possible += 127.5 * std::min(k, cols) / k;
    for (int x = 0; x < ext; ++x) {
      const int centre = x - cols;
      const int lo = std::clamp(centre - k / 2, 0, cols), hi = std::clamp(centre - k / 2 + k, 0, cols);
      // Rows weigh the same. A kernel wholly off the image sums 0 (two thirds of the range): no division.
      S[i * ext + x] = lo == hi ? 0 : roundToInt((prefix[hi] - prefix[lo]) / k * 1024.0);
    }
  }
  return S;
}

/// The arc model's basis on the model's rows (its offset per unit curvature) and the road rows' offset
/// per curvature step `dk` (1/m); the reason when the camera does not fit the frame, else nothing.
const char* setArcBasis(HoughGrid& g, CentreModel& model, const std::vector<double>& row_x,
                        const std::vector<double>& row_b, int height, double dk) {
  if (static_cast<int>(row_x.size()) != height) return "the arc model needs the camera (setCamera) of the frame's size";
  const int bs = g.bs;
  model.arc = ArcBasis(row_x, row_b, model.v0, model.v1);
  for (std::size_t i = 0; i < g.rr.size(); ++i) g.gb[i] = dk * model.arc(g.rr[i] * bs + (bs - 1) / 2.0) / bs;
  for (int v = g.rr.front() * bs; v < height; ++v)
    if (!std::isfinite(row_x[v]) || !std::isfinite(row_b[v])) return "arc model: the road rows reach the horizon";
  return nullptr;
}

/// The prior's window (ClusterPerceptronOptions::prior_px): the centre line's columns on the top and
/// the bottom road rows (v0, v1; the arc's offset vanishes on both, so bends do not move them) within
/// prior_px of the prior's. Without a prior (or with prior_px 0) every centre line is in it.
struct PriorWindow {
  bool windowed = false;
  double top = 0, bottom = 0, px = 0;
  bool admits(double u_top, double u_bottom) const {
    return !windowed || (std::abs(u_top - top) <= px && std::abs(u_bottom - bottom) <= px);
  }
};

PriorWindow priorWindow(const std::optional<Segment2>& prior, double prior_px, const CentreModel& model) {
  PriorWindow w;
  w.windowed = prior && prior_px > 0 && std::abs(prior->b.y() - prior->a.y()) > 1e-6;
  w.px = prior_px;
  if (w.windowed) {
    const auto at = [&](double v) {
      return prior->a.x() + (prior->b.x() - prior->a.x()) * (v - prior->a.y()) / (prior->b.y() - prior->a.y());
    };
    w.top = at(model.v0);
    w.bottom = at(model.v1);
  }
  return w;
}

/// The coarse Hough (§5): road row i (t_i from 0 at the top road row to 1 at the bottom one) is
/// shifted by round(s·t_i + q·g_i) blocks and the columns summed: s in [−M, M] the bottom row's shift
/// (the line's angle), q in [−Q, Q] the curvature's step (the arc model, g_i the row's arc offset per
/// step; Q = 0 for the paper's straight trapezoid). Only lines in the prior's window count.
HoughPeak coarseHough(const HoughGrid& g, const std::vector<std::int32_t>& S, int M, int Q, const PriorWindow& window) {
  const int cols = g.cols, bs = g.bs;
  std::vector<int> offsets(g.rr.size() * static_cast<std::size_t>(2 * M + 1) * (2 * Q + 1));
  for (int q = -Q, j = 0; q <= Q; ++q)
    for (int s = -M; s <= M; ++s)
      for (std::size_t i = 0; i < g.rr.size(); ++i, ++j)
        offsets[j] = roundToInt(s * g.tr[i] + q * g.gb[i]);
  // Block coordinate X (continuous) ↔ column X · bs − 0.5; the coarse Hough's line has X = x + 0.5 on
  // the top road row and x + 0.5 + s on the bottom one.
  std::vector<int> x_lo(2 * M + 1, 0), x_hi(2 * M + 1, cols - 1);
  if (window.windowed) {
    const double reach = window.px / bs, top = (window.top + 0.5) / bs - 0.5, bottom = (window.bottom + 0.5) / bs - 0.5;
    for (int s = -M; s <= M; ++s) {
      x_lo[s + M] = std::max({0, static_cast<int>(std::ceil(top - reach)), static_cast<int>(std::ceil(bottom - s - reach))});
      x_hi[s + M] = std::min({cols - 1, static_cast<int>(std::floor(top + reach)), static_cast<int>(std::floor(bottom - s + reach))});
    }
  }
  return houghSearch(S.data(), static_cast<int>(g.rr.size()), cols, offsets.data(), 2 * M + 1, 2 * Q + 1, x_lo.data(),
                     x_hi.data());
}

/// Sub-block refinement: the same Hough sum, with each block's certainty spread evenly over its width
/// and the kernel exactly the row's road width, evaluated at fractional intercepts, shifts (and, with
/// `bends`, curvature steps) around the coarse maximum `f` (X, shift, step), coarse to fine. The
/// continuous kernel sum is P(x + W/2) − P(x − W/2), P the running integral of the row.
Vec3 refineSubBlock(const HoughGrid& grid, Vec3 f, bool bends, const PriorWindow& window) {
  const int cols = grid.cols, bs = grid.bs;
  const std::vector<int>& rr = grid.rr;
  std::vector<double> P(rr.size() * (static_cast<std::size_t>(cols) + 1), 0.0);
  for (std::size_t i = 0; i < rr.size(); ++i) {
    const double* row = grid.sc.data() + static_cast<std::size_t>(rr[i]) * cols;
    double* pr = P.data() + i * (cols + 1);
    for (int c = 0; c < cols; ++c) pr[c + 1] = pr[c] + row[c];
  }
  auto integral = [&](std::size_t i, double x) {
    const double* pr = P.data() + i * (cols + 1);
    if (x <= 0) return 0.0;
    if (x >= cols) return pr[cols];
    const int c = static_cast<int>(x);
    return pr[c] + (x - c) * (pr[c + 1] - pr[c]);
  };
  auto score = [&](double X, double sft, double bend) {
    double total = 0;
    for (std::size_t i = 0; i < rr.size(); ++i) {
      const double x = X + sft * grid.tr[i] + bend * grid.gb[i], hw = 0.5 * grid.wb[rr[i]];
      total += (integral(i, x + hw) - integral(i, x - hw)) / (2.0 * hw);
    }
    return total;
  };
  // Pattern search: move to the best of the ± step neighbours in each parameter until none is
  // better, then halve the step (0.5 → 0.25 → 0.125 blocks).
  double fbest = score(f[0], f[1], f[2]);
  for (double step = 0.5; step >= 0.125; step /= 2) {
    for (int moves = 0; moves < 32; ++moves) {
      Vec3 next = f;
      for (int d = 0; d < (bends ? 3 : 2); ++d)
        for (const double sign : {-1.0, 1.0}) {
          Vec3 g = f;
          g[d] += sign * step;
          if (!window.admits(g[0] * bs - 0.5, (g[0] + g[1]) * bs - 0.5)) continue;
          const double val = score(g[0], g[1], g[2]);
          if (val > fbest) {
            fbest = val;
            next = g;
          }
        }
      if (next == f) break;
      f = next;
    }
  }
  return f;
}

/// The centre line sampled every block row from v_top down to the bottom row: the image model's, or
/// the arc model's ground circle taken to the image where it has not turned back.
std::vector<Vec2> centreCurve(const CentreModel& model, const std::optional<GroundArc>& ground, const RowGeometry& rows,
                              int v_top, int height, int bs) {
  std::vector<Vec2> curve;
  for (int v = v_top;; v = std::min(height - 1, v + bs)) {
    if (!ground) {
      curve.emplace_back(model.u(v), v);
    } else if (const double y = ground->at(rows.x[v]); std::isfinite(y)) {
      curve.emplace_back(rows.a[v] + rows.b[v] * y, v);
    }
    if (v >= height - 1) break;
  }
  return curve;
}

RoadFinding failed(RoadFinding res, const char* reason) {
  res.reason = reason;
  return res;
}

}  // namespace

void setParkSimdCap(ParkSimd cap) { simd_cap.store(static_cast<int>(cap), std::memory_order_relaxed); }

RoadFinding ClusterPerceptron::find(const std::uint8_t* rgb, int width, int height, bool want_mask,
                                    const std::optional<Segment2>& prior) const {
  RoadFinding res;
  if (!trained_) return failed(std::move(res), "not trained");
  if (static_cast<int>(row_widths_.size()) != height)
    return failed(std::move(res), "frame height differs from the bootstrap frame's");
  // §6: every pixel's road certainty, summed per block.
  Scratch& scr = scratch();
  const long long road_px =
      classifyFrame(*this, LutView{lut_.data(), sub_offset_.data(), sub_.data()}, rgb, width, height, scr);
  if (want_mask) {
    res.mask = roadMask(scr.cert, width, height);
    res.certainty = Image(width, height, 1);
    std::copy(scr.cert.begin(), scr.cert.end(), res.certainty.data.begin());
  }
  if (static_cast<double>(road_px) < opt_.min_road_fraction * width * height)
    return failed(std::move(res), "no road-coloured pixels");
  // §5: the Hough over the road block rows.
  const int bs = opt_.block_size;
  HoughGrid grid = houghGrid(scr.bsum, row_widths_, width, height, bs);
  if (grid.rr.size() < 2) return failed(std::move(res), "the bootstrap road outline has fewer than 2 block rows");
  double max_possible = 0;
  const std::vector<std::int32_t> S = kernelSums(grid, max_possible);
  // Continuous block coordinate X ↔ pixel u = X · bs − 0.5; rows at their block centres.
  CentreModel model;
  model.v0 = grid.rr.front() * bs + (bs - 1) / 2.0;
  model.v1 = std::max(model.v0 + 1.0, grid.rr.back() * bs + (bs - 1) / 2.0);
  const bool arc = opt_.road_model == RoadModel::Arc;
  const int Q = arc ? opt_.curvature_steps : 0;
  const double dk = opt_.max_curvature / opt_.curvature_steps;  // curvature per step, 1/m
  if (arc) {
    if (const char* why = setArcBasis(grid, model, row_x_, row_b_, height, dk)) return failed(std::move(res), why);
  }
  const PriorWindow window = priorWindow(prior, opt_.prior_px, model);
  const int M = std::min(opt_.max_shift_blocks, 2 * grid.cols);
  const HoughPeak peak = coarseHough(grid, S, M, Q, window);
  if (peak.sum == std::numeric_limits<std::int64_t>::min())
    return failed(std::move(res), "no centre line within prior_px of the prior");
  res.intercept_col = peak.x;
  res.shift = peak.shift - M;
  const Vec3 f = refineSubBlock(grid, Vec3(peak.x + 0.5, peak.shift - M, peak.bend - Q), Q > 0, window);
  model.p = Vec3(f[0] * bs - 0.5, f[1] * bs, arc ? f[2] * dk : 0.0);
  res.confidence = std::clamp(static_cast<double>(peak.sum) / 1024.0 / std::max(1.0, max_possible), 0.0, 1.0);

  // Beyond the paper: the Hough answer is good to about a block; the road's edges put it to the pixel
  // (the image model, or the arc model's circle on the ground).
  const int v_top = grid.rr.front() * bs;
  const RowGeometry geo{row_x_, row_a_, row_b_};
  std::optional<GroundArc> ground;
  if (opt_.refine_edges) {
    const int degree = Q > 0 ? 2 : 1;
    model = edgeConsensusModel(scr.cert.data(), width, height, v_top, row_widths_, model, degree, opt_,
                               [&](const CentreModel& m) { return window.admits(m.u(m.v0), m.u(m.v1)); });
    if (arc) ground = refineOnGround(scr.cert.data(), rgb, width, height, v_top, model, geo, row_widths_, opt_, carried_, res);
    if (!ground) fitModelToEdges(scr.cert.data(), width, height, v_top, row_widths_, degree, opt_.max_curvature, model, res);
  }
  // No ground fit: the image fit stands, unless its centre line, taken to the ground, leaves the
  // vehicle off the road: then the road-coloured area holds no road the vehicle could be on
  // (shoulders classed as road, no edge of the road in view), and the frame fails rather than steer by it.
  if (arc && !ground && leavesTheVehicleOffRoad(model, geo, row_widths_, v_top, height, opt_.max_curvature))
    return failed(std::move(res), "arc model: no centre line within half the road's width of the vehicle");
  res.centerline_curve = centreCurve(model, ground, geo, v_top, height, bs);
  if (res.centerline_curve.size() < 2) return failed(std::move(res), "arc model: the circle turns back above the bottom rows");
  res.centerline_image = Segment2{res.centerline_curve.front(), res.centerline_curve.back()};
  res.curvature = ground ? ground->k : arc ? model.p[2] : 0.0;
  res.ok = true;
  return res;
}

}  // namespace mapnav
