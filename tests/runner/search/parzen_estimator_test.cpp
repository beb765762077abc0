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

// The joint estimator over a log-uniform, an integer and a categorical axis.
SearchSpace make_mixed_space() {
  SearchSpace space;
  space.axes.push_back({"x", AxisKind::log_uniform, 1e-2, 1e1, 0});
  space.axes.push_back({"k", AxisKind::integer, 1.0, 4.0, 0});
  space.axes.push_back({"c", AxisKind::categorical, 0.0, 0.0, 3});
  return space;
}

TEST(JointParzen, BandwidthsFollowScottsExponentOnAFifthOfEachAxis) {
  const SearchSpace space = make_mixed_space();
  const std::vector<SearchPoint> points = {{std::log(0.1), 2.0, 0.0}, {std::log(3.0), 4.0, 2.0}};
  const JointParzen parzen = make_joint_parzen(space, points, 1.0, 0.2);
  // m = 2, D = 3: h · m^(−1/7) = 0.2 · 2^(−1/7) = 0.181145…; widths ln(1000) and 4 (the cells).
  const double shrink = 0.2 * std::pow(2.0, -1.0 / 7.0);
  EXPECT_NEAR(shrink, 0.18114473, 1e-8);
  EXPECT_DOUBLE_EQ(parzen.bandwidths[0], shrink * std::log(1000.0));
  EXPECT_DOUBLE_EQ(parzen.bandwidths[1], shrink * 4.0);
  EXPECT_DOUBLE_EQ(parzen.bandwidths[2], shrink);
  // 10⁵ points in one dimension at h = 0.05 would narrow to 0.05 · 10⁵^(−1/5) = 0.005 of the
  // axis: clipped to a hundredth of it.
  SearchSpace line;
  line.axes.push_back({"y", AxisKind::uniform, 0.0, 2.0, 0});
  const JointParzen many = make_joint_parzen(line, std::vector<SearchPoint>(100000, SearchPoint{1.0}), 1.0, 0.05);
  EXPECT_DOUBLE_EQ(many.bandwidths[0], 0.02);
  EXPECT_NEAR(make_joint_parzen(line, std::vector<SearchPoint>(32, SearchPoint{1.0}), 1.0, 0.2).bandwidths[0], 0.2, 1e-15);  // 0.2 · 32^(−1/5) · 2
}

TEST(JointParzen, TheMixtureSumsToOneOverTheMixedSpace) {
  // Σ over the integer cells and the choices of ∫ p dx (the trapezoid rule on 4000 cells of ln x).
  const SearchSpace space = make_mixed_space();
  for (const std::vector<SearchPoint>& points :
       {std::vector<SearchPoint>{}, {{std::log(0.02), 1.0, 1.0}}, {{std::log(0.1), 2.0, 0.0}, {std::log(9.0), 4.0, 2.0}, {0.0, 3.0, 0.0}}}) {
    for (const double weight : {1.0, 0.25}) {
      const JointParzen parzen = make_joint_parzen(space, points, weight, 0.2);
      const double a = std::log(1e-2), b = std::log(1e1);
      const int cells = 4000;
      const double h = (b - a) / cells;
      double total = 0.0;
      for (double k = 1.0; k <= 4.0; k += 1.0) {
        for (double c = 0.0; c < 3.0; c += 1.0) {
          double sum = 0.5 * (std::exp(calc_log_density(parzen, {a, k, c})) + std::exp(calc_log_density(parzen, {b, k, c})));
          for (int i = 1; i < cells; ++i) sum += std::exp(calc_log_density(parzen, {a + i * h, k, c}));
          total += sum * h;
        }
      }
      EXPECT_NEAR(total, 1.0, 1e-6) << points.size() << " points, prior weight " << weight;
    }
  }
}

TEST(JointParzen, LiarsAreComponentsWithAFractionOfTheGoodBandwidthsAndTheMixtureStillSumsToOne) {
  const SearchSpace space = make_mixed_space();
  const JointParzen good = make_joint_parzen(space, {{std::log(0.1), 2.0, 0.0}}, 1.0, 0.2);
  JointParzen bad = make_joint_parzen(space, {{std::log(0.02), 1.0, 1.0}, {std::log(9.0), 4.0, 2.0}}, 1.0, 0.2);
  add_joint_liars(bad, good, {{std::log(0.1), 2.0, 0.0}, {std::log(0.1), 3.0, 0.0}}, 0.7);
  // τ_d = 0.7 · σ^ℓ_d (above a hundredth of the axis), ε^λ = 0.7 · ε^ℓ; σ^ℓ = 0.2 · 1^(−1/7) · width.
  EXPECT_DOUBLE_EQ(bad.liar_bandwidths[0], 0.7 * 0.2 * std::log(1000.0));
  EXPECT_DOUBLE_EQ(bad.liar_bandwidths[1], 0.7 * 0.2 * 4.0);
  EXPECT_DOUBLE_EQ(bad.liar_bandwidths[2], 0.7 * 0.2);
  EXPECT_DOUBLE_EQ(bad.bandwidths[0], 0.2 * std::pow(2.0, -1.0 / 7.0) * std::log(1000.0));  // the points' own, unchanged
  // The density at a liar is the mixture's by hand: (π + k(x|p1) + k(x|p2) + k(x|p3) + k(x|p4)) / (2 + 2 + 1).
  const auto normal_kernel = [](double x, double mu, double sigma, double a, double b) {
    const double z = calc_normal_cdf((b - mu) / sigma) - calc_normal_cdf((a - mu) / sigma);
    return std::exp(-0.5 * (x - mu) * (x - mu) / (sigma * sigma)) / (sigma * std::sqrt(2.0 * M_PI) * z);
  };
  const auto cell = [](double k, double mu, double sigma) {
    // The integer axis 1 … 4 is the internal interval [0.5, 4.5], of width 4.
    const double z = calc_normal_cdf((4.5 - mu) / sigma) - calc_normal_cdf((0.5 - mu) / sigma);
    const double lo = std::max(0.5, k - 0.5), hi = std::min(4.5, k + 0.5);
    return (calc_normal_cdf((hi - mu) / sigma) - calc_normal_cdf((lo - mu) / sigma)) / z;
  };
  const auto choice = [](double c, double mu, double eps) { return (c == mu ? 1.0 - eps : 0.0) + eps / 3.0; };
  const double a = std::log(1e-2), b = std::log(1e1);
  const SearchPoint x = {std::log(0.1), 2.0, 0.0};
  double sum = 1.0 / ((b - a) * 4.0 * 3.0);
  for (const SearchPoint& p : bad.centres) {
    sum += normal_kernel(x[0], p[0], bad.bandwidths[0], a, b) * cell(x[1], p[1], bad.bandwidths[1]) * choice(x[2], p[2], bad.bandwidths[2]);
  }
  for (const SearchPoint& p : bad.liars) {
    sum += normal_kernel(x[0], p[0], bad.liar_bandwidths[0], a, b) * cell(x[1], p[1], bad.liar_bandwidths[1]) *
           choice(x[2], p[2], bad.liar_bandwidths[2]);
  }
  EXPECT_NEAR(calc_log_density(bad, x), std::log(sum / 5.0), 1e-12);
  // Σ over the cells and choices of ∫ g dx: 1 (the trapezoid rule on 4000 cells of ln x).
  const int cells = 4000;
  const double h = (b - a) / cells;
  double total = 0.0;
  for (double k = 1.0; k <= 4.0; k += 1.0) {
    for (double c = 0.0; c < 3.0; c += 1.0) {
      double row = 0.5 * (std::exp(calc_log_density(bad, {a, k, c})) + std::exp(calc_log_density(bad, {b, k, c})));
      for (int i = 1; i < cells; ++i) row += std::exp(calc_log_density(bad, {a + i * h, k, c}));
      total += row * h;
    }
  }
  EXPECT_NEAR(total, 1.0, 1e-6);
}

TEST(JointParzen, DrawsFollowTheDensityAndKeepEachPointsCoordinatesTogether) {
  // Two points far apart on x with different choices: a draw near one point's x takes that
  // point's choice far more often than the other's (the per-axis estimators would mix them).
  SearchSpace space;
  space.axes.push_back({"x", AxisKind::uniform, 0.0, 1.0, 0});
  space.axes.push_back({"c", AxisKind::categorical, 0.0, 0.0, 2});
  const JointParzen parzen = make_joint_parzen(space, {{0.1, 0.0}, {0.9, 1.0}}, 1.0, 0.2);
  RandomStream stream(11, "test");
  const int n = 60000;
  const int bins = 5;
  std::vector<std::vector<int>> counts(bins, std::vector<int>(2, 0));
  for (int i = 0; i < n; ++i) {
    const SearchPoint x = calc_parzen_draw(parzen, stream);
    ASSERT_GE(x[0], 0.0);
    ASSERT_LE(x[0], 1.0);
    ++counts[std::min(bins - 1, static_cast<int>(x[0] * bins))][static_cast<int>(x[1])];
  }
  for (int bin = 0; bin < bins; ++bin) {
    for (int c = 0; c < 2; ++c) {
      double p = 0.0;  // the cell's probability by the midpoint rule on 200 sub-cells
      for (int j = 0; j < 200; ++j) p += std::exp(calc_log_density(parzen, {(bin + (j + 0.5) / 200.0) / bins, double(c)}));
      p /= 200.0 * bins;
      EXPECT_NEAR(counts[bin][c] / static_cast<double>(n), p, 0.006) << bin << ", " << c;
    }
  }
  // Near x = 0.1 the choice is mostly point 1's (its kernel keeps the choice with 1 − ε/2 = 0.91,
  // ε = 0.2 · 2^(−1/6); the prior splits evenly): about 0.21 against 0.05 of all draws. Per-axis
  // estimators would give both choices 1/2 everywhere.
  EXPECT_GT(counts[0][0], 3 * counts[0][1]);
  EXPECT_GT(counts[4][1], 3 * counts[4][0]);
}

}  // namespace
}  // namespace armfarm::search
