// One receptive field: kernels against closed forms, activation with diagonal and full metrics,
// incremental PLS against batch weighted least squares on a plane.
#include "engine/lwpr/receptive_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace armfarm::lwpr {
namespace {

TEST(ReceptiveField, KernelsAndDerivativesMatchClosedFormAndFiniteDifferences) {
  EXPECT_DOUBLE_EQ(calc_kernel(Kernel::kGaussian, 2.0), std::exp(-1.0));
  EXPECT_DOUBLE_EQ(calc_kernel(Kernel::kBisquare, 2.0), 0.25);
  EXPECT_EQ(calc_kernel(Kernel::kBisquare, 5.0), 0.0);
  for (Kernel k : {Kernel::kGaussian, Kernel::kBisquare}) {
    const double q = 1.3, h = 1e-6;
    EXPECT_NEAR(calc_kernel_dq(k, q), (calc_kernel(k, q + h) - calc_kernel(k, q - h)) / (2 * h), 1e-8);
    EXPECT_NEAR(calc_kernel_dq2(k, q), (calc_kernel_dq(k, q + h) - calc_kernel_dq(k, q - h)) / (2 * h), 1e-6);
  }
}

TEST(ReceptiveField, ActivationAgreesForDiagonalAndFullMetrics) {
  LwprParams diag;
  LwprParams full;
  full.diag_only = false;
  Eigen::Matrix3d D = Eigen::Vector3d(4.0, 9.0, 1.0).asDiagonal();
  const Eigen::Vector3d c(0.1, 0.2, 0.3), x(0.3, 0.1, -0.2);
  ReceptiveField a = make_receptive_field(diag, c, D);
  ReceptiveField b = make_receptive_field(full, c, D);
  FieldScratch sa, sb;
  sa.resize(3, true);
  sb.resize(3, false);
  const Eigen::Vector3d d = x - c;
  const double expected = std::exp(-0.5 * d.dot(D * d));
  EXPECT_NEAR(calc_activation(a, Kernel::kGaussian, x, 0.0, sa), expected, 1e-14);
  EXPECT_NEAR(calc_activation(b, Kernel::kGaussian, x, 0.0, sb), expected, 1e-14);
  EXPECT_EQ(calc_activation(a, Kernel::kGaussian, x, 0.9, sa), 0.0);  // below the cutoff
  // A full metric with correlation: q = dᵀDd through the Cholesky factor.
  Eigen::Matrix3d Dfull;
  Dfull << 4, 1, 0.5, 1, 3, 0.2, 0.5, 0.2, 2;
  ReceptiveField f = make_receptive_field(full, c, Dfull);
  EXPECT_TRUE(f.metric.isApprox(Dfull, 1e-12));
  EXPECT_NEAR(calc_activation(f, Kernel::kGaussian, x, 0.0, sb), std::exp(-0.5 * d.dot(Dfull * d)), 1e-14);
}

TEST(ReceptiveField, PlsLearnsAPlane) {
  // Two projections span the 2-D input, so the local model converges to the plane; forgetting
  // washes out the statistics gathered while the PLS directions were still moving.
  LwprParams params;
  params.update_D = false;
  ReceptiveField rf = make_receptive_field(params, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity());
  FieldScratch scratch;
  scratch.resize(2, true);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector2d x(uniform(rng), uniform(rng));
    update_receptive_field(params, 4.0, x, 0.5 + 2.0 * x(0) - 1.0 * x(1), 1.0, rf, scratch);
  }
  EXPECT_TRUE(rf.trustworthy);
  double leverage = 0.0;
  EXPECT_NEAR(predict_receptive_field(rf, Eigen::Vector2d(0.3, 0.4), leverage, scratch), 0.5 + 0.6 - 0.4, 5e-3);
  EXPECT_GE(leverage, 0.0);
  EXPECT_LT(calc_field_noise_variance(rf), 1e-4);
}

TEST(ReceptiveField, AddProjectionGrowsEveryStatistic) {
  LwprParams params;
  params.init_n_reg = 1;
  ReceptiveField rf = make_receptive_field(params, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
  EXPECT_EQ(rf.n_reg(), 1);
  add_projection(params, rf);
  EXPECT_EQ(rf.n_reg(), 2);
  EXPECT_EQ(rf.sxy.cols(), 2);
  EXPECT_EQ(rf.ss2(1), params.init_S2);
}

}  // namespace
}  // namespace armfarm::lwpr
