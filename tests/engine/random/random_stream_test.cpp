// The portable generator against published reference outputs, pinned draws (so a change of
// algorithm, compiler or standard library that alters a job's numbers fails here), and the
// moments of its distributions.
#include "engine/random/random_stream.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace armfarm {
namespace {

TEST(RandomStream, SplitMix64MatchesTheReferenceImplementation) {
  // Outputs of Vigna's splitmix64.c started from x = 0.
  std::uint64_t state = 0;
  EXPECT_EQ(calc_splitmix64(state), 0xE220A8397B1DCDAFULL);
  EXPECT_EQ(calc_splitmix64(state), 0x6E789E6AA1B965F4ULL);
  EXPECT_EQ(calc_splitmix64(state), 0x06C45D188009454FULL);
}

TEST(RandomStream, Xoshiro256StarStarMatchesTheReferenceImplementation) {
  // xoshiro256** from the state {1, 2, 3, 4}: the first outputs of the authors' C code.
  RandomStream stream = RandomStream::from_state(1, 2, 3, 4);
  EXPECT_EQ(stream.next_u64(), 11520ULL);
  EXPECT_EQ(stream.next_u64(), 0ULL);
  EXPECT_EQ(stream.next_u64(), 1509978240ULL);
  EXPECT_EQ(stream.next_u64(), 1215971899390074240ULL);
}

TEST(RandomStream, PinnedDrawsDoNotChange) {
  RandomStream stream(42, "pinned");
  EXPECT_EQ(stream.next_u64(), 0x218C23D9D3EEAD06ULL);
  EXPECT_DOUBLE_EQ(stream.uniform(), 0.27704822453006062);
  EXPECT_EQ(stream.uniform_index(1000), 277u);
  EXPECT_DOUBLE_EQ(stream.normal(), 0.26456014959698104);
  std::vector<int> order(8);
  std::iota(order.begin(), order.end(), 0);
  stream.shuffle(order.begin(), order.end());
  EXPECT_EQ(order, (std::vector<int>{3, 2, 7, 6, 5, 1, 4, 0}));
}

TEST(RandomStream, PurposesGiveUnrelatedStreamsAndSeedsMatter) {
  RandomStream a(7, "reaching.targets"), b(7, "batch.shuffle"), c(8, "reaching.targets"), d(7, "reaching.targets");
  const std::uint64_t first = a.next_u64();
  EXPECT_NE(first, b.next_u64());
  EXPECT_NE(first, c.next_u64());
  EXPECT_EQ(first, d.next_u64());
}

TEST(RandomStream, UniformAndNormalHaveTheirMoments) {
  RandomStream stream(1, "moments");
  const int n = 200000;
  double sum_u = 0.0, sum_u2 = 0.0, sum_n = 0.0, sum_n2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double u = stream.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    sum_u += u;
    sum_u2 += u * u;
    const double z = stream.normal();
    sum_n += z;
    sum_n2 += z * z;
  }
  // Standard errors: uniform mean 0.00065, normal mean 0.0022, normal variance 0.0032.
  EXPECT_NEAR(sum_u / n, 0.5, 0.004);
  EXPECT_NEAR(sum_u2 / n - (sum_u / n) * (sum_u / n), 1.0 / 12.0, 0.002);
  EXPECT_NEAR(sum_n / n, 0.0, 0.012);
  EXPECT_NEAR(sum_n2 / n, 1.0, 0.02);
}

TEST(RandomStream, UniformIndexIsUnbiasedAndShuffleIsAPermutation) {
  RandomStream stream(3, "index");
  std::vector<int> counts(6, 0);
  for (int i = 0; i < 60000; ++i) ++counts[stream.uniform_index(6)];
  for (int count : counts) EXPECT_NEAR(count, 10000, 500);  // 5 standard deviations
  std::vector<int> values(100);
  std::iota(values.begin(), values.end(), 0);
  std::vector<int> shuffled = values;
  stream.shuffle(shuffled.begin(), shuffled.end());
  EXPECT_NE(shuffled, values);
  std::sort(shuffled.begin(), shuffled.end());
  EXPECT_EQ(shuffled, values);
}

}  // namespace
}  // namespace armfarm
