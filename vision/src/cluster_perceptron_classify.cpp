// The cluster-perceptron's per-pixel classification (Jochem & Baluja 1993 §6), the first step of
// ClusterPerceptron::find() (cluster_perceptron_runtime.cpp): every pixel's road certainty, from the
// colour lookup table (the fast path: portable, AVX2 or AVX-512 rows, the widest the processor runs
// within setParkSimdCap()'s cap) or from the perceptron itself (the reference path), and each
// block's sum of them, one band of block rows per thread. The hot loops (classifyRow, blockSums,
// the AVX2 and AVX-512 row passes) stay in this file with their band loop. See cluster_perceptron.h.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
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

int threadCount(int option) {
#ifdef _OPENMP
  return option == 0 ? omp_get_num_procs() : option;
#else
  (void)option;
  return 1;
#endif
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

/// The certainty of the pixel at `px` (R, G, B) whose cell is ambiguous: its entry in the cell's exact
/// 8³ table.
inline std::uint8_t exactCertainty(const std::uint8_t* px, const std::uint32_t* sub_offset, const std::uint8_t* sub) {
  const unsigned cell = ((px[0] >> 3u) << 10) | ((px[1] >> 3u) << 5) | (px[2] >> 3u);
  return sub[sub_offset[cell] + (((px[0] & 7u) << 6) | ((px[1] & 7u) << 3) | (px[2] & 7u))];
}

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

}  // namespace

void setParkSimdCap(ParkSimd cap) { simd_cap.store(static_cast<int>(cap), std::memory_order_relaxed); }

long long classifyFrame(const ClusterPerceptron& finder, const LutView& tables, const std::uint8_t* rgb, int width,
                        int height, FrameScratch& scr) {
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

}  // namespace mapnav
