// The renderer's vector noise against its scalar reference: fbmRow (world_noise_batch.cpp,
// AVX2 where the CPU has it) gives fbmBatch's and fbm's values bit for bit — no tolerance: every lane
// performs fbm's own IEEE operations in fbm's order, without fused multiply-adds. Rows of every
// length the vector loops split differently (multiples of 4 and 8 and the tails), points on and off
// the lattice lines, negative and far coordinates, footprints from sharp (every octave) to wide
// (none), rows of different lengths one after another.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "../../sim/src/world_noise.h"

namespace mapnav::world_detail {
namespace {

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct Row {
  std::vector<double> xs, ys;
  std::vector<float> footprints;
};

// `m` points: runs of neighbours a small step apart (as a pixel row's ground points, so that cells
// repeat and the memo of the last cell matters), with jumps, lattice points and far coordinates mixed in.
Row randomRow(std::size_t m, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> coord(-300.0, 300.0), step(-0.2, 0.2), fp(0.0, 0.6), u(0.0, 1.0);
  Row r;
  double x = coord(rng), y = coord(rng);
  for (std::size_t j = 0; j < m; ++j) {
    const double kind = u(rng);
    if (kind < 0.05) {
      x = coord(rng), y = coord(rng);  // a jump
    } else if (kind < 0.10) {
      x = std::floor(x), y = std::floor(y);  // on the lattice
    } else if (kind < 0.12) {
      x = 1e6 * coord(rng), y = -1e5 * coord(rng);  // far away
    } else {
      x += step(rng), y += step(rng);
    }
    r.xs.push_back(x);
    r.ys.push_back(y);
    // Sharp, blending and wide footprints: octave weights 1, between 0 and 1, and 0.
    const double f = u(rng);
    r.footprints.push_back(static_cast<float>(f < 0.3 ? 0.0 : f < 0.9 ? fp(rng) : 5.0));
  }
  return r;
}

TEST(WorldNoiseVector, FbmRowEqualsTheScalarFbmBitForBit) {
  const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  std::printf("fbmRow's vector path: %s\n", avx2 ? "AVX2 (compared with the scalar fbmBatch and fbm)"
                                                  : "none on this CPU (fbmRow is fbmBatch)");
  std::mt19937_64 rng(31);
  std::size_t points = 0, differing_batch = 0, differing_fbm = 0, nonzero = 0;
  const std::vector<std::size_t> lengths = {0, 1, 2, 3, 4, 5, 7, 8, 9, 11, 12, 15, 16, 17, 31, 33, 100, 512, 1001};
  for (const std::size_t m : lengths) {
    for (int trial = 0; trial < 6; ++trial) {
      const Row r = randomRow(m, rng);
      const std::uint64_t salt = rng();
      const double base_freq = std::vector<double>{0.05, 0.37, 1.0, 3.3}[trial % 4];
      const int octaves = 1 + trial % NoiseCache::kOctaves + trial / 4;
      std::vector<float> row(m + 1, -7.0f), batch(m + 1, -7.0f);  // one past the end: left alone
      fbmRow(salt, r.xs.data(), r.ys.data(), r.footprints.data(), m, base_freq, octaves, row.data());
      fbmBatch(salt, r.xs.data(), r.ys.data(), r.footprints.data(), m, base_freq, octaves, batch.data());
      for (std::size_t j = 0; j < m; ++j) {
        const float one = fbm(salt, Vec2(r.xs[j], r.ys[j]), base_freq, octaves, r.footprints[j]);
        if (!sameBits(row[j], batch[j]) && ++differing_batch <= 5)  // the first few named
          ADD_FAILURE() << "m " << m << ", trial " << trial << ", point " << j << ": " << row[j] << " vs " << batch[j];
        differing_fbm += !sameBits(row[j], one);
        nonzero += row[j] != 0.0f;
      }
      EXPECT_EQ(row[m], -7.0f) << "m " << m << ": wrote past the row";
      points += m;
    }
  }
  std::printf("%zu points: %zu differ from fbmBatch, %zu from fbm; %zu non-zero\n", points, differing_batch,
              differing_fbm, nonzero);
  EXPECT_EQ(differing_batch, 0u);
  EXPECT_EQ(differing_fbm, 0u);
  EXPECT_GT(nonzero, points / 2);  // the noise is there to compare: most points see some octave
}

// The camera's sensor noise a row at a time (sensorNoiseRow, AVX2 64-bit multiplies from 32-bit ones)
// against sensorNoise subpixel by subpixel, bit for bit: row lengths the 4-lane loop splits
// differently, offsets near 0 and where j·φ wraps past 2^64. Its spread is that of a sum of four
// uniforms: mean 0, standard deviation 1/√3, within [−2, 2).
TEST(WorldNoiseVector, SensorNoiseRowEqualsTheScalarNoiseBitForBit) {
  std::mt19937_64 rng(3131);
  std::size_t differing = 0, count = 0;
  double sum = 0, sum2 = 0;
  float lo = 0, hi = 0;
  const std::vector<std::size_t> lengths = {0, 1, 2, 3, 4, 5, 7, 8, 13, 1536, 1537};
  for (const std::size_t n : lengths) {
    for (const std::uint64_t j0 : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{737277}, rng(), ~std::uint64_t{2}}) {
      const std::uint64_t seed = rng();
      std::vector<float> row(n + 1, -7.0f);
      sensorNoiseRow(seed, j0, n, row.data());
      for (std::size_t j = 0; j < n; ++j) {
        if (!sameBits(row[j], sensorNoise(seed, j0 + j)) && ++differing <= 5)
          ADD_FAILURE() << "n " << n << ", j0 " << j0 << ", subpixel " << j << ": " << row[j] << " vs "
                        << sensorNoise(seed, j0 + j);
        sum += row[j];
        sum2 += static_cast<double>(row[j]) * row[j];
        lo = std::min(lo, row[j]);
        hi = std::max(hi, row[j]);
        ++count;
      }
      EXPECT_EQ(row[n], -7.0f) << "n " << n << ": wrote past the row";
    }
  }
  EXPECT_EQ(differing, 0u);
  const double mean = sum / static_cast<double>(count), sd = std::sqrt(sum2 / static_cast<double>(count) - mean * mean);
  std::printf("%zu subpixels: mean %.4f, sd %.4f (1/sqrt(3) = 0.5774), range [%.3f, %.3f]\n", count, mean, sd, lo, hi);
  EXPECT_NEAR(mean, 0.0, 0.02);  // 15 k samples: the mean's sd is 0.005
  EXPECT_NEAR(sd, 0.5774, 0.02);
  EXPECT_GE(lo, -2.0f);
  EXPECT_LT(hi, 2.0f);
}

// The camera's last step (bytesRow, AVX2 where the CPU has it) gives toByte's bytes: values below,
// within and above the range, every half-way fraction (rounded up), at both black levels, rows of
// every length the vector loop splits differently.
TEST(WorldNoiseVector, BytesRowEqualsToByte) {
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<float> value(-40.0f, 300.0f), noise(-2.0f, 2.0f);
  std::size_t differing = 0;
  for (const std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{8}, std::size_t{9}, std::size_t{1536}}) {
    for (const float lo : {0.0f, 37.0f}) {
      for (const float sigma : {0.0f, 3.4641016f}) {
        std::vector<float> v(n), nz(n);
        for (std::size_t j = 0; j < n; ++j) {
          // A third exact halves (x.5 rounds up), a third whole, a third anywhere.
          v[j] = j % 3 == 0 ? std::floor(value(rng)) + 0.5f : j % 3 == 1 ? std::floor(value(rng)) : value(rng);
          nz[j] = j % 3 == 2 ? noise(rng) : 0.0f;
        }
        std::vector<std::uint8_t> out(n + 1, 7);
        bytesRow(v.data(), nz.data(), sigma, n, lo, out.data());
        for (std::size_t j = 0; j < n; ++j)
          if (out[j] != toByte(v[j] + sigma * nz[j], lo) && ++differing <= 5)
            ADD_FAILURE() << "n " << n << ", value " << v[j] << ": " << int(out[j]) << " vs "
                          << int(toByte(v[j] + sigma * nz[j], lo));
        EXPECT_EQ(out[n], 7) << "n " << n << ": wrote past the row";
      }
    }
  }
  EXPECT_EQ(differing, 0u);
  // The rounding itself: half-way up, the clamps at the black level and 255.
  const std::vector<float> v{2.5f, 2.49f, -3.0f, 254.5f, 300.0f, 36.4f, 37.6f, 0.0f, 100.0f};
  const std::vector<float> zero(v.size(), 0.0f);
  std::vector<std::uint8_t> out(v.size());
  bytesRow(v.data(), zero.data(), 1.0f, v.size(), 37.0f, out.data());
  EXPECT_EQ(out, (std::vector<std::uint8_t>{37, 37, 37, 255, 255, 37, 38, 37, 100}));
  bytesRow(v.data(), zero.data(), 1.0f, v.size(), 0.0f, out.data());
  EXPECT_EQ(out, (std::vector<std::uint8_t>{3, 2, 0, 255, 255, 36, 38, 0, 100}));
}

// The inline floor and distance to the nearest whole number (the slabs' and the leaves' cells)
// give std::floor's and |x − std::round(x)|'s values bit for bit: around every whole number and
// half (just below, on, just above), negative and positive, tiny, large and beyond 2^52.
TEST(WorldNoiseInline, FloorAndDistanceToWholeEqualTheLibrarysBitForBit) {
  std::vector<double> xs{0.0, -0.0, 0.5, -0.5, 1.5, -1.5, 2.5, -2.5, 0.49999999999999994, -0.49999999999999994,
                         1e-300, -1e-300, 4503599627370495.5, -4503599627370495.5, 0x1p52, -0x1p52, 0x1p53 + 2,
                         -0x1p60, 1e300, -1e300};
  for (int k = -50; k <= 50; ++k)
    for (const double f : {0.0, 0.5, 1.0})
      for (const double d : {-1e-12, 0.0, 1e-12}) xs.push_back(k + f + d);
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> wide(-1e7, 1e7), near(-3.0, 3.0);
  for (int i = 0; i < 100000; ++i) xs.push_back(i % 2 == 0 ? wide(rng) : near(rng));
  const auto bits = [](double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
  };
  int differing = 0;
  for (const double x : xs) {
    // The floor's sign of a zero may differ (−0 below zero): every use takes it to an integer.
    if (floorInline(x) != std::floor(x) && ++differing <= 5) ADD_FAILURE() << "floor of " << x;
    const double expected = std::abs(x - std::round(x));
    if (bits(distanceToWhole(x)) != bits(expected) && ++differing <= 5)
      ADD_FAILURE() << "distance of " << x << ": " << distanceToWhole(x) << " vs " << expected;
  }
  EXPECT_EQ(differing, 0);
}

}  // namespace
}  // namespace mapnav::world_detail
