// The Parzen estimators are densities (they integrate to 1 — by the trapezoid rule, a second
// computation) and their draws follow them (a histogram of draws against the density).
#include "runner/search/parzen_estimator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace armfarm::search {
namespace {

double integrate(const NumericParzen& parzen, int cells) {
  const double a = parzen.interval.low;
  const double b = parzen.interval.high;
  const double h = (b - a) / cells;
  double sum = 0.5 * (std::exp(calc_log_density(parzen, a)) + std::exp(calc_log_density(parzen, b)));
  for (int i = 1; i < cells; ++i) sum += std::exp(calc_log_density(parzen, a + i * h));
  return sum * h;
}

TEST(ParzenEstimator, TheNumericMixtureIntegratesToOne) {
  const SearchAxis axis{"x", AxisKind::uniform, -1.0, 4.0, 0};
  for (const std::vector<double>& centres :
       {std::vector<double>{}, {0.2}, {-1.0, 3.9}, {1.0, 1.0, 1.0}, {0.0, 0.1, 0.2, 2.0, 3.5, 4.0}}) {
    const NumericParzen parzen = make_numeric_parzen(axis, centres);
    EXPECT_NEAR(integrate(parzen, 20000), 1.0, 1e-6) << centres.size();
  }
}

TEST(ParzenEstimator, BandwidthsAreTheLargerNeighbourGapClipped) {
  const SearchAxis axis{"x", AxisKind::uniform, 0.0, 10.0, 0};
  const NumericParzen parzen = make_numeric_parzen(axis, {6.0, 1.0, 2.0});
  ASSERT_EQ(parzen.centres, (std::vector<double>{1.0, 2.0, 6.0}));
  // Gaps: 1 → max(1−0, 2−1) = 1; 2 → max(1, 4) = 4; 6 → max(4, 10−6) = 4. Smallest 10/min(100, 4) = 2.5.
  EXPECT_DOUBLE_EQ(parzen.bandwidths[0], 2.5);
  EXPECT_DOUBLE_EQ(parzen.bandwidths[1], 4.0);
  EXPECT_DOUBLE_EQ(parzen.bandwidths[2], 4.0);
}

TEST(ParzenEstimator, IntegerMassesSumToOneAndMatchTheirDraws) {
  const SearchAxis axis{"k", AxisKind::integer, 1.0, 8.0, 0};
  const NumericParzen parzen = make_numeric_parzen(axis, {2.0, 3.0, 7.0});
  double total = 0.0;
  std::vector<double> mass(9, 0.0);
  for (int k = 1; k <= 8; ++k) total += mass[k] = std::exp(calc_log_density(parzen, k));
  EXPECT_NEAR(total, 1.0, 1e-12);
  RandomStream stream(3, "test");
  std::vector<int> counts(9, 0);
  const int n = 40000;
  for (int i = 0; i < n; ++i) {
    const double k = calc_parzen_draw(parzen, stream);
    ASSERT_EQ(k, std::round(k));
    ++counts[static_cast<int>(k)];
  }
  for (int k = 1; k <= 8; ++k) EXPECT_NEAR(counts[k] / static_cast<double>(n), mass[k], 0.01) << k;
}

TEST(ParzenEstimator, NumericDrawsFollowTheDensity) {
  const SearchAxis axis{"x", AxisKind::log_uniform, 1e-3, 1e1, 0};
  std::vector<double> values = {std::log(0.01), std::log(0.02), std::log(5.0)};
  const NumericParzen parzen = make_numeric_parzen(axis, values);
  RandomStream stream(5, "test");
  const int n = 40000;
  const int bins = 8;
  std::vector<int> counts(bins, 0);
  const double a = parzen.interval.low;
  const double width = (parzen.interval.high - a) / bins;
  for (int i = 0; i < n; ++i) {
    const double z = calc_parzen_draw(parzen, stream);
    ASSERT_GE(z, parzen.interval.low);
    ASSERT_LE(z, parzen.interval.high);
    ++counts[std::min(bins - 1, static_cast<int>((z - a) / width))];
  }
  for (int bin = 0; bin < bins; ++bin) {
    // The bin's probability by the midpoint rule on 200 sub-cells.
    double p = 0.0;
    for (int j = 0; j < 200; ++j) p += std::exp(calc_log_density(parzen, a + (bin + (j + 0.5) / 200.0) * width));
    p *= width / 200.0;
    EXPECT_NEAR(counts[bin] / static_cast<double>(n), p, 0.01) << bin;
  }
}

TEST(ParzenEstimator, CategoricalProbabilitiesAreSmoothedCounts) {
  const CategoricalParzen parzen = make_categorical_parzen(4, {1.0, 1.0, 3.0});
  // (n_c + 1/4) / (3 + 1)
  EXPECT_DOUBLE_EQ(parzen.probabilities[0], 0.0625);
  EXPECT_DOUBLE_EQ(parzen.probabilities[1], 0.5625);
  EXPECT_DOUBLE_EQ(parzen.probabilities[2], 0.0625);
  EXPECT_DOUBLE_EQ(parzen.probabilities[3], 0.3125);
  RandomStream stream(9, "test");
  std::vector<int> counts(4, 0);
  for (int i = 0; i < 40000; ++i) ++counts[static_cast<int>(calc_parzen_draw(parzen, stream))];
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(counts[c] / 40000.0, parzen.probabilities[c], 0.01) << c;
}

}  // namespace
}  // namespace armfarm::search
