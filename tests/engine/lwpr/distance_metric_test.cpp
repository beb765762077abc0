// Distance-metric gradient against finite differences of the activation and of the penalty.
#include "engine/lwpr/distance_metric.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace armfarm::lwpr {
namespace {

double calc_activation_of_factor(const ReceptiveField& rf, const Eigen::VectorXd& diff) {
  Eigen::MatrixXd D;
  calc_metric_from_factor(rf.metric_factor, D);
  const double q = rf.diagonal() ? D.col(0).dot(diff.cwiseAbs2()) : diff.dot(D * diff);
  return std::exp(-0.5 * q);
}

double calc_penalty(const ReceptiveField& rf) {
  Eigen::MatrixXd D;
  calc_metric_from_factor(rf.metric_factor, D);
  return rf.diagonal() ? D.squaredNorm() : D.squaredNorm();
}

void check_gradient(bool diag_only) {
  LwprParams params;
  params.diag_only = diag_only;
  Eigen::Matrix3d D;
  D << 5, 1, 0.3, 1, 4, -0.5, 0.3, -0.5, 6;
  if (diag_only) D = D.diagonal().asDiagonal();
  ReceptiveField rf = make_receptive_field(params, Eigen::Vector3d::Zero(), D);
  const Eigen::Vector3d diff(0.2, -0.3, 0.25);
  Eigen::VectorXd zero = Eigen::VectorXd::Zero(3), md(3);
  MetricSample sample(zero, zero, zero);
  sample.w = calc_activation_of_factor(rf, diff);
  sample.q = -2.0 * std::log(sample.w);
  sample.W = 1.0;
  Eigen::MatrixXd grad;
  // Activation part only: dJ1/dw = 1, no penalty.
  params.penalty = 0.0;
  calc_metric_gradient(params, rf, diff, sample, 1.0, 0.0, grad, nullptr, md);
  const double h = 1e-7;
  for (Eigen::Index c = 0; c < rf.metric_factor.cols(); ++c) {
    for (Eigen::Index r = 0; r <= (diag_only ? 2 : c); ++r) {
      ReceptiveField plus = rf, minus = rf;
      plus.metric_factor(r, c) += h;
      minus.metric_factor(r, c) -= h;
      const double fd = (calc_activation_of_factor(plus, diff) - calc_activation_of_factor(minus, diff)) / (2 * h);
      EXPECT_NEAR(grad(r, c), fd, 1e-6) << r << "," << c;
    }
  }
  // Penalty part only: (w/W)·(γ/n)·Σ D² with w/W = 1 here.
  params.penalty = 3.0;
  sample.w = 1.0;
  calc_metric_gradient(params, rf, diff, sample, 0.0, 0.0, grad, nullptr, md);
  for (Eigen::Index c = 0; c < rf.metric_factor.cols(); ++c) {
    for (Eigen::Index r = 0; r <= (diag_only ? 2 : c); ++r) {
      ReceptiveField plus = rf, minus = rf;
      plus.metric_factor(r, c) += h;
      minus.metric_factor(r, c) -= h;
      const double fd = (3.0 / 3.0) * (calc_penalty(plus) - calc_penalty(minus)) / (2 * h);
      EXPECT_NEAR(grad(r, c), fd, 1e-4 * std::max(1.0, std::abs(fd))) << r << "," << c;
    }
  }
}

TEST(DistanceMetric, GradientMatchesFiniteDifferencesDiagonal) { check_gradient(true); }
TEST(DistanceMetric, GradientMatchesFiniteDifferencesFull) { check_gradient(false); }

TEST(DistanceMetric, PressDerivativeOfALoneSampleIsItsExcessError) {
  // With empty memory terms, ∂J1/∂w = (e_cv² − E/W)/W.
  LwprParams params;
  ReceptiveField rf = make_receptive_field(params, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity());
  Eigen::VectorXd s = Eigen::Vector2d(0.5, 0.1), e = Eigen::Vector2d(0.3, 0.2), ecv = Eigen::Vector2d(0.4, 0.25);
  MetricSample sample(s, e, ecv);
  sample.W = 10.0;
  sample.E = 0.5;
  EXPECT_NEAR(calc_press_dw(rf, sample), (0.16 + 0.0625 - 0.05) / 10.0, 1e-15);
}

TEST(DistanceMetric, NeverLeavesANonFiniteMetric) {
  LwprParams params;
  ReceptiveField rf = make_receptive_field(params, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity() * 4.0);
  FieldScratch scratch;
  scratch.resize(2, true);
  const Eigen::MatrixXd before = rf.metric;
  Eigen::VectorXd s = Eigen::Vector2d(1e300, 1e300), e = Eigen::Vector2d(1e300, 1e300);
  MetricSample sample(s, e, e);
  sample.w = 0.5;
  sample.q = 1.0;
  sample.W = 1e-300;
  sample.E = 1e300;
  update_distance_metric(params, Eigen::Vector2d(0.5, 0.5), sample, 1.0, rf, scratch);
  EXPECT_TRUE(rf.metric.allFinite());
  EXPECT_EQ(rf.metric, before);
}


// Without meta learning a diagonal step is M − α·transient·∂J/∂M element by element (the gradient
// from calc_metric_gradient), except where the step exceeds 0.1·max|M|: that element keeps its
// value and its rate halves.
TEST(DistanceMetric, DiagonalStepIsTheGradientStepWithTheSafeguard) {
  LwprParams params;
  params.penalty = 1e-2;
  ReceptiveField rf = make_receptive_field(params, Eigen::Vector3d::Zero(), Eigen::Vector3d(4.0, 1.0, 0.25).asDiagonal());
  FieldScratch scratch;
  scratch.resize(3, true);
  const Eigen::Vector3d diff(0.02, 0.3, 2.0);
  Eigen::VectorXd s = Eigen::Vector2d(0.5, 0.1), e = Eigen::Vector2d(0.3, 0.2), ecv = Eigen::Vector2d(0.4, 0.25);
  MetricSample sample(s, e, ecv);
  sample.q = rf.metric.col(0).dot(diff.cwiseAbs2());
  sample.w = std::exp(-0.5 * sample.q);
  sample.W = 5.0;
  sample.E = 0.5;
  const double transient = 0.7;
  Eigen::MatrixXd grad;
  Eigen::VectorXd md(3);
  calc_metric_gradient(params, rf, diff, sample, calc_press_dw(rf, sample), 0.0, grad, nullptr, md);
  const Eigen::VectorXd M0 = rf.metric_factor.col(0);
  const double bound = 0.1 * M0.cwiseAbs().maxCoeff();
  update_distance_metric(params, diff, sample, transient, rf, scratch);
  int skipped = 0, applied = 0;
  for (int i = 0; i < 3; ++i) {
    const double step = params.init_alpha * transient * grad(i, 0);
    if (std::abs(step) > bound) {
      ++skipped;
      EXPECT_EQ(rf.metric_factor(i, 0), M0(i));
      EXPECT_NEAR(rf.log_alpha(i, 0), std::log(params.init_alpha / 2.0), 1e-12);
    } else {
      ++applied;
      EXPECT_NEAR(rf.metric_factor(i, 0), M0(i) - step, 1e-12);
      EXPECT_NEAR(rf.log_alpha(i, 0), std::log(params.init_alpha), 1e-12);
    }
    EXPECT_DOUBLE_EQ(rf.metric(i, 0), rf.metric_factor(i, 0) * rf.metric_factor(i, 0));
  }
  EXPECT_GE(skipped, 1);
  EXPECT_GE(applied, 1);
}

// The full metric's products M·d (any n; loops up to 8 columns, Eigen beyond) and D = MᵀM (loops up
// to 3 columns, Eigen beyond) against Eigen's dense expressions, at random upper triangular M.
TEST(DistanceMetric, FactorProductsMatchEigen) {
  std::srand(5);
  for (int n = 1; n <= 10; ++n) {
    const Eigen::MatrixXd M = Eigen::MatrixXd::Random(n, n).triangularView<Eigen::Upper>();
    const Eigen::VectorXd d = Eigen::VectorXd::Random(n);
    Eigen::VectorXd md;
    calc_factor_product(M, d, md);
    const Eigen::VectorXd md_eigen = M * d;
    ASSERT_EQ(md.size(), n);
    for (int r = 0; r < n; ++r) EXPECT_NEAR(md(r), md_eigen(r), 1e-14 * n) << "n " << n << " row " << r;
    if (n == 1) continue;  // a 1×1 factor is stored as a diagonal
    Eigen::MatrixXd D;
    calc_metric_from_factor(M, D);
    const Eigen::MatrixXd D_eigen = M.transpose() * M;
    ASSERT_EQ(D.rows(), n);
    ASSERT_EQ(D.cols(), n);
    EXPECT_LE((D - D_eigen).cwiseAbs().maxCoeff(), 1e-14 * n) << "n " << n;
    if (n <= 3) {
      EXPECT_EQ(D, D.transpose()) << "n " << n;  // computed once per pair and mirrored
    }
  }
}

// A full metric's step given the caller's M·(x − c) (sample.md, from calc_factor_product as
// update_receptive_field computes q) leaves the same bits as the step that multiplies itself, for
// the unrolled sizes, the loop (n ≤ 8) and Eigen's product (n > 8), with and without meta
// learning; and it does use sample.md (a perturbed one gives another metric).
TEST(DistanceMetric, FullStepGivenTheFactorProductMatchesTheStepThatMultipliesBitForBit) {
  std::srand(11);
  for (const bool meta : {false, true}) {
    for (const int n : {2, 3, 5, 9}) {
      LwprParams params;
      params.penalty = 1e-3;
      params.meta = meta;
      params.diag_only = false;
      const Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n);
      const Eigen::MatrixXd D = A.transpose() * A + 2.0 * Eigen::MatrixXd::Identity(n, n);
      const ReceptiveField start = make_receptive_field(params, Eigen::VectorXd::Zero(n), D);
      ASSERT_FALSE(start.diagonal());
      const Eigen::VectorXd diff = 0.3 * Eigen::VectorXd::Random(n);
      Eigen::VectorXd s = Eigen::Vector2d(0.5, 0.1), e = Eigen::Vector2d(0.3, 0.2), ecv = Eigen::Vector2d(0.4, 0.25);
      FieldScratch scratch;
      scratch.resize(n, false);
      Eigen::VectorXd md;
      calc_factor_product(start.metric_factor, diff, md);
      auto step = [&](const Eigen::VectorXd* given) {
        ReceptiveField rf = start;
        MetricSample sample(s, e, ecv);
        sample.q = md.squaredNorm();
        sample.w = std::exp(-0.5 * sample.q);
        sample.W = 5.0;
        sample.E = 0.5;
        sample.md = given;
        scratch.md.setConstant(n, 7.0);  // stale scratch: the step must not read it
        update_distance_metric(params, diff, sample, 0.7, rf, scratch);
        return rf;
      };
      const ReceptiveField computed = step(nullptr);
      const ReceptiveField given = step(&md);
      ASSERT_NE(computed.metric_factor, start.metric_factor) << "n " << n << " meta " << meta;  // a step was taken
      EXPECT_EQ(std::memcmp(given.metric_factor.data(), computed.metric_factor.data(), sizeof(double) * n * n), 0)
          << "n " << n << " meta " << meta;
      EXPECT_EQ(std::memcmp(given.metric.data(), computed.metric.data(), sizeof(double) * n * n), 0)
          << "n " << n << " meta " << meta;
      EXPECT_EQ(std::memcmp(given.log_alpha.data(), computed.log_alpha.data(), sizeof(double) * n * n), 0);
      EXPECT_EQ(std::memcmp(given.meta_trace.data(), computed.meta_trace.data(), sizeof(double) * n * n), 0);
      const Eigen::VectorXd perturbed = 1.5 * md;
      EXPECT_NE(step(&perturbed).metric_factor, computed.metric_factor) << "n " << n << " meta " << meta;
    }
  }
}

}  // namespace
}  // namespace armfarm::lwpr

namespace armfarm::lwpr {
namespace {

// The fixed-size step of a full metric with 2 or 3 inputs (update_small_full_metric, SSE2 and AVX2
// copies) against the general one (update_distance_metric) on the same terms, w = exp(−q/2) of the q the general step
// is given: M, D, log α and the trace the same bits, with and without meta learning, for both
// kernels, at random metrics, samples and field memories; and a degenerate sample (a gradient that
// is not finite) leaves both unchanged.
TEST(DistanceMetric, SmallFullStepMatchesTheGeneralStepBitForBit) {
  std::srand(23);
  int steps = 0, skipped = 0;
  for (const Kernel kernel : {Kernel::kGaussian, Kernel::kBisquare}) {
    for (const bool meta : {false, true}) {
      for (const int n : {2, 3}) {
        for (int trial = 0; trial < 200; ++trial) {
          LwprParams params;
          params.kernel = kernel;
          params.penalty = 1e-3;
          params.meta = meta;
          params.diag_only = false;
          const Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n);
          const Eigen::MatrixXd D = 4.0 * (A.transpose() * A) + Eigen::MatrixXd::Identity(n, n);
          params.init_n_reg = 1;
          ReceptiveField start = make_receptive_field(params, Eigen::VectorXd::Zero(n), D);
          const int n_reg = 1 + trial % n;  // R = 1 … n
          while (start.n_reg() < n_reg) add_projection(params, start);
          start.ss2 = Eigen::VectorXd::Random(n_reg).cwiseAbs() + Eigen::VectorXd::Constant(n_reg, 0.1);
          start.press_H = Eigen::VectorXd::Random(n_reg);
          start.press_R = Eigen::VectorXd::Random(n_reg).cwiseAbs();
          start.log_alpha.triangularView<Eigen::Upper>() =
              Eigen::MatrixXd::Random(n, n) + Eigen::MatrixXd::Constant(n, n, std::log(50.0));
          if (meta) start.meta_trace.triangularView<Eigen::Upper>() = 1e-3 * Eigen::MatrixXd::Random(n, n);
          const Eigen::VectorXd diff = (trial % 2 == 0 ? 0.2 : 0.6) * Eigen::VectorXd::Random(n);
          const Eigen::VectorXd s = Eigen::VectorXd::Random(n_reg), e = 0.5 * Eigen::VectorXd::Random(n_reg);
          const Eigen::VectorXd e_cv = 1.2 * e;
          Eigen::VectorXd md;
          calc_factor_product(start.metric_factor, diff, md);
          const double q = md.squaredNorm();
          const double w = calc_kernel(kernel, q);
          if (!(w > 0.0)) continue;
          const double W = 2.0 + 10.0 * std::abs(Eigen::VectorXd::Random(1)(0));
          const double E = W * (0.1 + e_cv.squaredNorm());
          const double transient = trial % 3 == 0 ? 1.0 : 0.3;

          ReceptiveField general = start;
          FieldScratch scratch;
          scratch.resize(n, false);
          MetricSample sample(s, e, e_cv);
          sample.w = w;
          sample.q = q;
          sample.W = W;
          sample.E = E;
          update_distance_metric(params, diff, sample, transient, general, scratch);

          SmallMetricSample terms;
          terms.w = w;
          terms.W = W;
          terms.E = E;
          terms.e_cv2 = e_cv.squaredNorm();
          terms.s = s.data();
          terms.e = e.data();
          terms.e_cv = e_cv.data();
          terms.diff = diff.data();
          for (const bool avx2 : {false, true}) {
            if (avx2 && !has_avx2()) continue;
            ReceptiveField small = start;
            update_small_full_metric(params, terms, transient, small, avx2);
            const std::string where = "n " + std::to_string(n) + " meta " + std::to_string(meta) + " kernel " +
                                      std::to_string(static_cast<int>(kernel)) + " trial " + std::to_string(trial) +
                                      (avx2 ? " AVX2" : " SSE2");
            const auto same = [n](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
              return std::memcmp(a.data(), b.data(), sizeof(double) * n * n) == 0;
            };
            EXPECT_TRUE(same(small.metric_factor, general.metric_factor)) << where;
            EXPECT_TRUE(same(small.metric, general.metric)) << where;
            EXPECT_TRUE(same(small.log_alpha, general.log_alpha)) << where;
            EXPECT_TRUE(same(small.meta_trace, general.meta_trace)) << where;
          }
          steps += general.metric_factor != start.metric_factor ? 1 : 0;
          if (!meta && general.log_alpha != start.log_alpha) ++skipped;  // the safeguard halved a rate
        }
      }
    }
  }
  EXPECT_GT(steps, 1000);   // most samples move the metric
  EXPECT_GT(skipped, 10);   // and some steps were too large (rate halved, element skipped)

  // A gradient that is not finite: no step, in both.
  LwprParams params;
  params.diag_only = false;
  params.meta = true;
  const ReceptiveField start = make_receptive_field(params, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity() * 4.0);
  const double big[2] = {1e300, 1e300};
  const double diff[2] = {0.5, 0.5};
  SmallMetricSample terms;
  terms.w = std::exp(-0.5 * 4.0 * 0.5);
  terms.W = 1e-300;
  terms.E = 1e300;
  terms.e_cv2 = std::numeric_limits<double>::infinity();
  terms.s = big;
  terms.e = big;
  terms.e_cv = big;
  terms.diff = diff;
  for (const bool avx2 : {false, true}) {
    if (avx2 && !has_avx2()) continue;
    ReceptiveField small = start;
    update_small_full_metric(params, terms, 1.0, small, avx2);
    EXPECT_EQ(small.metric_factor, start.metric_factor);
    EXPECT_EQ(small.metric, start.metric);
    EXPECT_EQ(small.log_alpha, start.log_alpha);
    EXPECT_EQ(small.meta_trace, start.meta_trace);
  }
}

// update_small_full_field_metrics() on 1–4 fields at once (the AVX2 copy puts field k in vector lane
// k) against update_small_full_field_metric() on each field alone, on the SSE2 copy: every
// statistic the step writes (M, D, log α, trace, sum_e2, press_E, H, R) the same bits, for n = 2
// and 3, R = 1..n, with and without meta learning, both kernels. Some groups hold degenerate
// fields: one whose gradient is not finite (its R memory term is +∞: no step at all) and one whose
// stepped D overflows (M and D kept, the rates and trace stepped), next to ordinary ones.
TEST(DistanceMetric, FieldMetricLanesMatchOneFieldAtATimeBitForBit) {
  if (!has_avx2()) GTEST_SKIP() << "this CPU has no AVX2: the fields' metric steps run one by one";
  std::srand(41);
  int groups = 0, moved = 0, frozen = 0, overflowed = 0;
  for (const Kernel kernel : {Kernel::kGaussian, Kernel::kBisquare}) {
    for (const bool meta : {false, true}) {
      for (const int n : {2, 3}) {
        for (int trial = 0; trial < 60; ++trial) {
          LwprParams params;
          params.kernel = kernel;
          params.penalty = 1e-3;
          params.meta = meta;
          params.diag_only = false;
          params.init_n_reg = 1;
          const int n_reg = 1 + trial % n;
          const int count = 1 + trial % kMetricLanes;
          const bool degenerate = trial % 5 == 4;
          const Eigen::VectorXd x = 0.3 * Eigen::VectorXd::Random(n);
          ReceptiveField start[kMetricLanes];
          FieldScratch scratch[kMetricLanes];
          double w[kMetricLanes];
          for (int k = 0; k < count; ++k) {
            const Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n);
            const Eigen::MatrixXd D = 4.0 * (A.transpose() * A) + Eigen::MatrixXd::Identity(n, n);
            ReceptiveField& rf = start[k];
            rf = make_receptive_field(params, 0.2 * Eigen::VectorXd::Random(n), D);
            while (rf.n_reg() < n_reg) add_projection(params, rf);
            rf.ss2 = Eigen::VectorXd::Random(n_reg).cwiseAbs() + Eigen::VectorXd::Constant(n_reg, 0.1);
            rf.press_H = Eigen::VectorXd::Random(n_reg);
            rf.press_R = Eigen::VectorXd::Random(n_reg).cwiseAbs();
            rf.sum_w = Eigen::VectorXd::Constant(n_reg, 2.0 + 10.0 * std::abs(Eigen::VectorXd::Random(1)(0)));
            rf.sum_e_cv2 = Eigen::VectorXd::Random(n_reg).cwiseAbs() + Eigen::VectorXd::Constant(n_reg, 0.05);
            rf.sum_e2 = 0.5 * rf.sum_e_cv2(n_reg - 1) * (trial % 3 == 0 ? 3.0 : 1.0);
            rf.press_E = 0.3 * rf.sum_w(0);
            rf.lambda = 0.99 + 0.009 * std::abs(Eigen::VectorXd::Random(1)(0));
            rf.log_alpha.triangularView<Eigen::Upper>() =
                Eigen::MatrixXd::Random(n, n) + Eigen::MatrixXd::Constant(n, n, std::log(50.0));
            if (meta) rf.meta_trace.triangularView<Eigen::Upper>() = 1e-3 * Eigen::MatrixXd::Random(n, n);
            if (degenerate && k == 1) rf.press_R(0) = std::numeric_limits<double>::infinity();
            if (degenerate && k == 2) {
              // A factor whose MᵀM overflows (the step's D is refused) with a finite gradient: the D
              // the gradient reads is set apart from it.
              rf.metric_factor = Eigen::MatrixXd::Constant(n, n, 1e154).triangularView<Eigen::Upper>();
              rf.metric = 4.0 * Eigen::MatrixXd::Identity(n, n);
            }
            scratch[k].resize(n, false);
            scratch[k].s.head(n_reg) = Eigen::VectorXd::Random(n_reg);
            scratch[k].residual.head(n_reg) = 0.5 * Eigen::VectorXd::Random(n_reg);
            scratch[k].one_minus_h.head(n_reg) = Eigen::VectorXd::Constant(n_reg, 0.9) +
                                                 0.09 * Eigen::VectorXd::Random(n_reg);
            Eigen::VectorXd md;
            calc_factor_product(rf.metric_factor, x - rf.center, md);
            w[k] = degenerate && k == 2 ? 0.5 : calc_kernel(kernel, md.squaredNorm());
            if (!(w[k] > 0.0)) w[k] = 0.01;  // past the bisquare's support: any activation will do here
          }
          ReceptiveField lanes[kMetricLanes], alone[kMetricLanes];
          const FieldScratch* scratches[kMetricLanes];
          ReceptiveField* fields[kMetricLanes];
          for (int k = 0; k < count; ++k) {
            lanes[k] = start[k];
            alone[k] = start[k];
            scratch[k].use_avx2 = true;
            scratches[k] = &scratch[k];
            fields[k] = &lanes[k];
          }
          update_small_full_field_metrics(params, x, count, w, scratches, fields);
          for (int k = 0; k < count; ++k) {
            FieldScratch one = scratch[k];
            one.use_avx2 = false;
            update_small_full_field_metric(params, x, w[k], one, alone[k]);
          }
          ++groups;
          for (int k = 0; k < count; ++k) {
            const std::string where = "n " + std::to_string(n) + " R " + std::to_string(n_reg) + " meta " +
                                      std::to_string(meta) + " kernel " + std::to_string(static_cast<int>(kernel)) +
                                      " trial " + std::to_string(trial) + " field " + std::to_string(k) + " of " +
                                      std::to_string(count);
            const auto same = [](const auto& a, const auto& b) {
              return a.size() == b.size() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
            };
            EXPECT_TRUE(same(lanes[k].metric_factor, alone[k].metric_factor)) << where;
            EXPECT_TRUE(same(lanes[k].metric, alone[k].metric)) << where;
            EXPECT_TRUE(same(lanes[k].log_alpha, alone[k].log_alpha)) << where;
            EXPECT_TRUE(same(lanes[k].meta_trace, alone[k].meta_trace)) << where;
            EXPECT_TRUE(same(lanes[k].press_H, alone[k].press_H)) << where;
            EXPECT_TRUE(same(lanes[k].press_R, alone[k].press_R)) << where;
            EXPECT_EQ(std::memcmp(&lanes[k].sum_e2, &alone[k].sum_e2, sizeof(double)), 0) << where;
            EXPECT_EQ(std::memcmp(&lanes[k].press_E, &alone[k].press_E, sizeof(double)), 0) << where;
            if (degenerate && k == 1) {
              EXPECT_EQ(lanes[k].metric_factor, start[k].metric_factor) << where;  // no step at all
              EXPECT_EQ(lanes[k].log_alpha, start[k].log_alpha) << where;
              ++frozen;
            } else if (degenerate && k == 2) {
              EXPECT_EQ(lanes[k].metric_factor, start[k].metric_factor) << where;  // the overflowing D refused
              EXPECT_EQ(lanes[k].metric, start[k].metric) << where;
              if (meta) {
                EXPECT_NE(lanes[k].log_alpha, start[k].log_alpha) << where;  // the rates stepped all the same
                ++overflowed;
              }
            } else {
              moved += lanes[k].metric_factor != start[k].metric_factor ? 1 : 0;
            }
          }
        }
      }
    }
  }
  EXPECT_EQ(groups, 480);
  EXPECT_GT(moved, 500);  // most ordinary fields' metrics moved
  EXPECT_GT(frozen, 20);
  EXPECT_GT(overflowed, 5);
}

// calc_rate_exp() against long double's expl (64-bit significand, so expl rounded to double is
// within a hair of the correctly rounded value): within 0.7 ulp everywhere on [−40, 12] (the
// meta-learning rates' range is [−10, 10]), correctly rounded at ≥ 98 %; exact where exp is
// exact (0 → 1) and the edges of double's range (overflow to +∞, the subnormals, underflow to 0,
// ±∞, NaN) as the C library gives them.
TEST(DistanceMetric, RateExpIsWithinAnUlpOfTheExactValue) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(-40.0, 12.0);
  double worst = 0.0;
  int rounded = 0;
  constexpr int kPoints = 200000;
  for (int i = 0; i < kPoints; ++i) {
    const double x = uniform(rng);
    const long double exact = expl(static_cast<long double>(x));
    const double nearest = static_cast<double>(exact);
    const double ulp = std::nextafter(nearest, std::numeric_limits<double>::infinity()) - nearest;
    const double ours = calc_rate_exp(x);
    worst = std::max(worst, static_cast<double>(std::fabs((static_cast<long double>(ours) - exact) / ulp)));
    rounded += ours == nearest ? 1 : 0;
  }
  EXPECT_LT(worst, 0.7);
  EXPECT_GT(rounded, kPoints * 98 / 100);
  EXPECT_EQ(calc_rate_exp(0.0), 1.0);
  EXPECT_EQ(calc_rate_exp(-0.0), 1.0);
  for (const double x : {709.7, 709.78, -700.0, -708.5, -720.0, -744.0, -745.1}) {
    EXPECT_EQ(calc_rate_exp(x), std::exp(x)) << "x = " << x;  // near overflow, subnormal results
  }
  EXPECT_EQ(calc_rate_exp(709.8), std::numeric_limits<double>::infinity());
  EXPECT_EQ(calc_rate_exp(1e300), std::numeric_limits<double>::infinity());
  EXPECT_EQ(calc_rate_exp(std::numeric_limits<double>::infinity()), std::numeric_limits<double>::infinity());
  EXPECT_EQ(calc_rate_exp(-745.2), 0.0);
  EXPECT_EQ(calc_rate_exp(-1e300), 0.0);
  EXPECT_EQ(calc_rate_exp(-std::numeric_limits<double>::infinity()), 0.0);
  EXPECT_TRUE(std::isnan(calc_rate_exp(std::numeric_limits<double>::quiet_NaN())));
}

// The diagonal step with meta learning takes its rate from calc_rate_exp(): one step from a known
// state gives M_i − α·g_i with α = calc_rate_exp(log α) after the IDBD change, element by element
// (the gradient from calc_metric_gradient, the same inputs).
TEST(DistanceMetric, DiagonalMetaStepUsesTheRateExp) {
  LwprParams params;
  params.meta = true;
  params.penalty = 1e-3;
  const int n = 3;
  ReceptiveField rf = make_receptive_field(params, Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n) * 2.0);
  // Log-rates where calc_rate_exp() and the C library's exp differ (ours is correctly rounded at
  // about 98.6 % of points, glibc's at 99.9 %), and a zero trace, so that the IDBD change is 0
  // and the rates are exactly those.
  int found = 0;
  for (double x = 0.3; found < n && x < 3.0; x += 1e-3) {
    if (calc_rate_exp(x) != std::exp(x)) rf.log_alpha(found++) = x;
  }
  ASSERT_EQ(found, n);
  rf.meta_trace.setZero();
  const Eigen::VectorXd diff = Eigen::Vector3d(0.1, -0.2, 0.15);
  const Eigen::VectorXd s = Eigen::VectorXd::Constant(rf.n_reg(), 0.4);
  const Eigen::VectorXd e = Eigen::VectorXd::Constant(rf.n_reg(), 0.2);
  const Eigen::VectorXd e_cv = 1.1 * e;
  MetricSample sample(s, e, e_cv);
  sample.q = rf.metric.col(0).dot(diff.cwiseAbs2());
  sample.w = std::exp(-0.5 * sample.q);
  sample.W = 5.0;
  sample.E = 0.5;
  const double dJ1_dw = calc_press_dw(rf, sample);
  Eigen::MatrixXd grad, curvature;
  Eigen::VectorXd md;
  const double d2J1_dw2 = 2.0 * e_cv.squaredNorm() / (sample.W * sample.W);
  calc_metric_gradient(params, rf, diff, sample, dJ1_dw, d2J1_dw2, grad, &curvature, md);
  ReceptiveField stepped = rf;
  FieldScratch scratch;
  scratch.resize(n, true);
  update_distance_metric(params, diff, sample, 1e-3, stepped, scratch);
  for (int i = 0; i < n; ++i) {
    const double change = std::clamp(-params.meta_rate * grad(i) * rf.meta_trace(i), -0.1, 0.1);
    const double log_alpha = std::clamp(rf.log_alpha(i) + change, -10.0, 10.0);
    EXPECT_EQ(stepped.log_alpha(i), log_alpha) << i;
    const double step = calc_rate_exp(log_alpha) * 1e-3 * grad(i);
    EXPECT_EQ(stepped.metric_factor(i), rf.metric_factor(i) - step) << i;
    // The trace from 0 takes the applied step −α·transient·g exactly: it tells the rates apart.
    EXPECT_EQ(stepped.meta_trace(i), -step) << i;
    EXPECT_NE(step, std::exp(log_alpha) * 1e-3 * grad(i)) << i;
  }
}

}  // namespace
}  // namespace armfarm::lwpr
