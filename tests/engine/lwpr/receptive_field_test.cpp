// One receptive field: kernels against closed forms, activation with diagonal and full metrics,
// incremental PLS against batch weighted least squares on a plane.
#include "engine/lwpr/receptive_field.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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

// A 2-D field at the origin with metric I, and scratch sized for it.
ReceptiveField make_unit_field(const LwprParams& params, FieldScratch& scratch) {
  scratch.resize(2, true);
  return make_receptive_field(params, Eigen::Vector2d::Zero(), Eigen::Matrix2d::Identity());
}

TEST(ReceptiveField, PlsLearnsAPlane) {
  // Two projections span the 2-D input, so the local model converges to the plane; forgetting
  // washes out the statistics gathered while the PLS directions were still moving.
  LwprParams params;
  params.update_D = false;
  FieldScratch scratch;
  ReceptiveField rf = make_unit_field(params, scratch);
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

// The sample at which a field with two projections first records a leave-one-out error.
int first_loo_sample(LooStart rule) {
  LwprParams params;
  params.update_D = false;
  params.loo_start = rule;
  FieldScratch scratch;
  ReceptiveField rf = make_unit_field(params, scratch);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int k = 1; k <= 1000; ++k) {
    const Eigen::Vector2d x(uniform(rng), uniform(rng));
    update_receptive_field(params, 4.0, x, x(0) * x(1) + 0.1 * uniform(rng), 1.0, rf, scratch);
    if (rf.sum_e_cv2(0) != 0.0) return k;
  }
  return -1;
}

TEST(ReceptiveField, StartRuleDecidesWhenLeaveOneOutStatisticsBegin) {
  // n_data after k samples is Σ_{i<k} λ^i ≈ k − k²/2000 at λ ≈ 0.999. Early: once n_data >
  // 4·(R+1) = 12, i.e. at sample 13 (n_12 ≈ 11.93, n_13 ≈ 12.92). Library: once n_data >
  // 0.1/(1−λ) ≈ 100, which the discounted count passes only after more than 100 samples (about
  // 106 at λ = 0.999; λ anneals upwards, so a little later).
  EXPECT_EQ(first_loo_sample(LooStart::kEarly), 13);
  const int library = first_loo_sample(LooStart::kLibrary);
  EXPECT_GT(library, 105);
  EXPECT_LT(library, 130);
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


// A known three-sample sequence into a 1-D field with one projection: every statistic equals the
// value worked out by hand from the update equations (forgetting-weighted means, sample counts,
// incremental PLS of table 2 of Vijayakumar et al. 2005, the leave-one-out error sum).
TEST(ReceptiveField, StatisticsAfterAKnownSequenceMatchHandComputedValues) {
  LwprParams params;
  params.update_D = false;
  params.init_n_reg = 1;
  params.init_lambda = 0.9;  // λ: 0.9, 0.945, 0.9675 for the three samples
  params.final_lambda = 0.99;
  params.tau_lambda = 0.5;
  ReceptiveField rf = make_receptive_field(params, Eigen::VectorXd::Zero(1), Eigen::MatrixXd::Ones(1, 1));
  FieldScratch scratch;
  scratch.resize(1, true);
  const double xs[3] = {1.0, 3.0, 2.0}, ys[3] = {2.0, 1.0, 4.0}, ws[3] = {0.5, 0.25, 0.1};
  const double lambdas[3] = {0.9, 0.945, 0.9675};
  for (int k = 0; k < 3; ++k) {
    update_receptive_field(params, 2.5, Eigen::VectorXd::Constant(1, xs[k]), ys[k], ws[k], rf, scratch);
    EXPECT_EQ(rf.trustworthy, k == 2) << "sample " << k + 1;  // counts 1, 1.945, 2.88 against 2.5
  }
  // Each sample counts 1 whatever its activation; earlier ones are discounted by the later λ.
  EXPECT_NEAR(rf.n_data(0), 1.0 + 0.9675 + 0.9675 * 0.945, 1e-9);  // 2.8817875; the weights sum to 0.799
  EXPECT_NEAR(rf.sum_w(0), 0.1 + 0.9675 * 0.25 + 0.9675 * 0.945 * 0.5, 1e-9);
  EXPECT_NEAR(rf.lambda, 0.5 * 0.9675 + 0.5 * 0.99, 1e-15);
  // Means: Σλw x / Σλw with the discounted weights 0.45714375, 0.241875, 0.1.
  const double dw[3] = {0.5 * 0.945 * 0.9675, 0.25 * 0.9675, 0.1};
  const double W = dw[0] + dw[1] + dw[2];
  EXPECT_NEAR(rf.mean_x(0), (dw[0] * 1.0 + dw[1] * 3.0 + dw[2] * 2.0) / W, 1e-9);
  EXPECT_NEAR(rf.beta0, (dw[0] * 2.0 + dw[1] * 1.0 + dw[2] * 4.0) / W, 1e-9);

  // PLS in 1-D by hand: u = sign(Σλ_slow w z res), s = u·z, then the regression sums.
  double sw = 1e-10, mx = 0.0, b0 = 0.0, sxy = 0.0, ss2 = params.init_S2, sys = 0.0, sxs = 0.0, e_cv2 = 0.0;
  double n_data = 1e-10;
  for (int k = 0; k < 3; ++k) {
    const double lambda = lambdas[k], w = ws[k];
    const double w_old = lambda * sw;
    sw = w_old + w;
    n_data = lambda * n_data + 1.0;
    mx = (w_old * mx + w * xs[k]) / sw;
    b0 = (w_old * b0 + w * ys[k]) / sw;
    const double z = xs[k] - mx, res = ys[k] - b0;
    sxy = (1.0 - (1.0 - lambda) / 10.0) * sxy + w * z * res;
    const double s = (sxy > 0 ? 1.0 : -1.0) * z;
    ss2 = lambda * ss2 + w * s * s;
    sys = lambda * sys + w * s * res;
    sxs = lambda * sxs + w * z * s;
    const double e = res - sys / ss2 * s;
    const double one_minus_h = std::max(1.0 - w * s * s / ss2, 1e-3);
    // Leave-one-out sums start once the field has more than min(0.1/(1−λ), 4(R+1)) samples (1, 1.8, 3.1).
    if (n_data > std::min(0.1 / (1.0 - lambda), 8.0)) e_cv2 = lambda * e_cv2 + w * (e / one_minus_h) * (e / one_minus_h);
  }
  EXPECT_NEAR(rf.sxy(0, 0), sxy, 1e-12);
  EXPECT_NEAR(rf.ss2(0), ss2, 1e-12);
  EXPECT_NEAR(rf.sys(0), sys, 1e-12);
  EXPECT_NEAR(rf.sxs(0, 0), sxs, 1e-12);
  EXPECT_NEAR(rf.beta(0), sys / ss2, 1e-9);
  EXPECT_NEAR(rf.loadings(0, 0), sxs / ss2, 1e-9);
  EXPECT_NEAR(std::abs(rf.directions(0, 0)), 1.0, 1e-15);
  EXPECT_NEAR(rf.sum_e_cv2(0), e_cv2, 1e-12);
  EXPECT_GT(e_cv2, 0.0);
}

// A narrow field (activation 0.1 for every sample, as in 21-D) adds its third projection as soon
// as the rule passes: mse_2/mse_1 < add_threshold, the last projection has seen 99 % of the
// samples, and n_data·(1 − λ) > 0.5, checked after every sample. With λ = 0.9 the sample count
// first exceeds 5 at sample 7 ((1 − 0.9⁷)/0.1 = 5.22); the summed activations never exceed 1, so
// a count of weights would never pass.
TEST(ReceptiveField, AddsAProjectionWhenTheCriterionPasses) {
  LwprParams params;
  params.update_D = false;
  params.init_lambda = params.final_lambda = 0.9;
  ReceptiveField rf = make_receptive_field(params, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity());
  FieldScratch scratch;
  scratch.resize(3, true);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  int added_at = 0;
  for (int k = 1; k <= 40 && added_at == 0; ++k) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    update_receptive_field(params, 6.0, x, 3.0 * x(0) - 2.0 * x(1) + 1.0 * x(2), 0.1, rf, scratch);
    const double expected_count = (1.0 - std::pow(0.9, k)) / 0.1 + std::pow(0.9, k) * 1e-10;
    EXPECT_NEAR(rf.n_data(0), expected_count, 1e-12);
    EXPECT_NEAR(rf.n_data(1), expected_count, 1e-12);
    EXPECT_LT(rf.sum_w(1) * (1.0 - 0.9), 0.5);
    const double mse_2 = rf.sum_e_cv2(1) / rf.sum_w(1) + 1e-10;
    const double mse_1 = rf.sum_e_cv2(0) / rf.sum_w(0) + 1e-10;
    const bool rule = mse_2 / mse_1 < params.add_threshold && rf.n_data(1) * (1.0 - 0.9) > 0.5;
    EXPECT_EQ(rf.n_reg() == 3, rule) << "sample " << k;
    if (rf.n_reg() == 3) added_at = k;
  }
  EXPECT_GE(added_at, 7);  // the count rule cannot pass earlier
  ASSERT_EQ(rf.n_reg(), 3);
  EXPECT_EQ(rf.n_data(2), 0.0);  // the new projection starts counting from zero
  update_receptive_field(params, 6.0, Eigen::Vector3d(0.1, 0.2, 0.3), 0.1, 0.1, rf, scratch);
  EXPECT_EQ(rf.n_data(2), 1.0);
  EXPECT_NEAR(rf.n_data(0), (1.0 - std::pow(0.9, added_at + 1)) / 0.1, 1e-9);
}

// The field update's AVX2 copy against its SSE2 one: every statistic the same bits after the same
// stream, at input dimensions that fill whole blocks of four lanes and that leave a tail of one to
// three, with and without metric learning, with a projection added on the way.
std::vector<double> flatten_field(const ReceptiveField& rf) {
  std::vector<double> all;
  for (const Eigen::MatrixXd* m : {&rf.metric_factor, &rf.metric, &rf.log_alpha, &rf.meta_trace, &rf.sxy, &rf.sxs,
                                   &rf.directions, &rf.loadings}) {
    all.insert(all.end(), m->data(), m->data() + m->size());
  }
  for (const Eigen::VectorXd* v : {&rf.mean_x, &rf.sum_w, &rf.n_data, &rf.ss2, &rf.sys, &rf.sum_e_cv2, &rf.press_H,
                                   &rf.press_R, &rf.beta}) {
    all.insert(all.end(), v->data(), v->data() + v->size());
  }
  all.insert(all.end(), {rf.lambda, rf.beta0, rf.sum_e2, rf.press_E, rf.trustworthy ? 1.0 : 0.0});
  return all;
}

// Full metrics that adapt quickly: λ from 0.99, projections added readily, a small penalty.
LwprParams make_full_metric_params(bool meta) {
  LwprParams params;
  params.diag_only = false;
  params.update_D = true;
  params.meta = meta;
  params.init_lambda = 0.99;
  params.add_threshold = 0.9;
  params.penalty = 1e-4;
  return params;
}

TEST(ReceptiveField, Avx2FieldUpdateMatchesSse2BitForBit) {
  if (!has_avx2()) GTEST_SKIP() << "this CPU has no AVX2";
  for (const int n : {4, 5, 7, 8, 21}) {
    for (const bool update_d : {false, true}) {
      LwprParams params;
      params.update_D = update_d;
      params.init_lambda = 0.99;
      params.add_threshold = 0.9;  // add projections readily, so the test covers an added one
      const Eigen::MatrixXd D = 2.0 * Eigen::MatrixXd::Identity(n, n);
      ReceptiveField fields[2] = {make_receptive_field(params, Eigen::VectorXd::Zero(n), D),
                                  make_receptive_field(params, Eigen::VectorXd::Zero(n), D)};
      FieldScratch scratch[2];
      for (int k = 0; k < 2; ++k) {
        scratch[k].resize(n, true);
        scratch[k].use_avx2 = k == 1;
      }
      std::mt19937_64 rng(static_cast<unsigned>(11 * n + update_d));
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      for (int i = 0; i < 2000; ++i) {
        const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.5 * uniform(rng); });
        const double y = std::sin(3.0 * x(0)) + x(1) * x(n - 1) + 0.05 * uniform(rng);
        const double w = 0.05 + 0.95 * std::abs(uniform(rng));
        for (int k = 0; k < 2; ++k) update_receptive_field(params, 2.0 * n, x, y, w, fields[k], scratch[k]);
      }
      EXPECT_GT(fields[0].n_reg(), params.init_n_reg) << "n = " << n << ": no projection was added";
      const std::vector<double> sse2 = flatten_field(fields[0]), avx2 = flatten_field(fields[1]);
      ASSERT_EQ(sse2.size(), avx2.size()) << "n = " << n;
      EXPECT_EQ(std::memcmp(sse2.data(), avx2.data(), sse2.size() * sizeof(double)), 0)
          << "n = " << n << ", update_D " << update_d;
    }
  }
}

// update_receptive_field_pair against two update_receptive_field calls: every statistic the same
// bits, on SSE2 and AVX2, at the fixed sizes (2, 3: sequential) and the run-time ones, with and
// without update_D. The two fields differ in centre, metric and projection count (one adds
// projections, the other may not), so the pair's runs end at different steps.
TEST(ReceptiveField, FieldPairUpdateMatchesTwoSingleUpdatesBitForBit) {
  for (const int n : {2, 3, 4, 5, 7, 8, 21}) {
    for (const bool avx2 : {false, true}) {
      if (avx2 && !has_avx2()) continue;
      for (const bool update_d : {false, true}) {
        LwprParams params;
        params.update_D = update_d;
        params.init_lambda = 0.99;
        params.add_threshold = 0.9;  // add projections readily
        const Eigen::MatrixXd D_a = 2.0 * Eigen::MatrixXd::Identity(n, n);
        const Eigen::MatrixXd D_b = 0.5 * Eigen::MatrixXd::Identity(n, n);
        const Eigen::VectorXd c_b = Eigen::VectorXd::Constant(n, 0.2);
        ReceptiveField single[2] = {make_receptive_field(params, Eigen::VectorXd::Zero(n), D_a),
                                    make_receptive_field(params, c_b, D_b)};
        if (n > params.init_n_reg) add_projection(params, single[1]);  // b starts one projection ahead
        ReceptiveField pair[2] = {single[0], single[1]};
        FieldScratch scratch[3];
        for (FieldScratch& sc : scratch) {
          sc.resize(n, true);
          sc.use_avx2 = avx2;
        }
        std::mt19937_64 rng(static_cast<unsigned>(13 * n + 2 * avx2 + update_d));
        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        int unequal_steps = 0;
        for (int i = 0; i < 1500; ++i) {
          const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.5 * uniform(rng); });
          const double y = std::sin(3.0 * x(0)) + x(1) * x(n - 1) + 0.05 * uniform(rng);
          const double w_a = 0.05 + 0.95 * std::abs(uniform(rng));
          const double w_b = 0.05 + 0.95 * std::abs(uniform(rng));
          if (pair[0].n_reg() != pair[1].n_reg()) ++unequal_steps;
          update_receptive_field(params, 2.0 * n, x, y, w_a, single[0], scratch[0]);
          update_receptive_field(params, 2.0 * n, x, y, w_b, single[1], scratch[0]);
          update_receptive_field_pair(params, 2.0 * n, x, y, w_a, pair[0], scratch[1], w_b, pair[1], scratch[2]);
        }
        if (n > params.init_n_reg) {
          EXPECT_GT(single[0].n_reg(), params.init_n_reg) << "n = " << n << ": no projection was added";
          EXPECT_GT(unequal_steps, 50) << "n = " << n << ": too few steps with unequal projection counts";
        }
        for (int k = 0; k < 2; ++k) {
          const std::vector<double> a = flatten_field(single[k]), b = flatten_field(pair[k]);
          ASSERT_EQ(a.size(), b.size()) << "n = " << n << ", field " << k;
          EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0)
              << "n = " << n << ", field " << k << ", AVX2 " << avx2 << ", update_D " << update_d;
        }
      }
    }
  }
}

// The field update's PLS statistics, means and cached directions against a plain scalar loop written
// here from the algorithm (Vijayakumar et al. 2005, table 2) with the summation order the field update
// documents (element i in partial sum i mod 4, added as (p0 + p1) + (p2 + p3)): the same bits at every
// remainder n mod 4, on both copies (SSE2 pairs, AVX2) and at the fixed sizes 2, 3 and (AVX2) 21.
TEST(ReceptiveField, FieldUpdateMatchesAPlainScalarLoopBitForBit) {
  struct Plain {  // the reference state: n inputs, R projections
    std::vector<double> mean_x, sxy, sxs, u, p, sum_w, ss2, sys, beta;
    double beta0 = 0.0, lambda = 0.0;
  };
  for (const int n : {2, 3, 4, 5, 6, 7, 9, 10, 11, 21}) {
    for (const bool avx2 : {false, true}) {
      if (avx2 && !has_avx2()) continue;
      LwprParams params;
      params.update_D = false;
      params.add_proj = false;
      params.init_lambda = 0.99;
      const int R = params.init_n_reg;
      ReceptiveField rf = make_receptive_field(params, Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n));
      FieldScratch scratch;
      scratch.resize(n, true);
      scratch.use_avx2 = avx2;
      Plain ref;
      ref.mean_x.assign(n, 0.0);
      ref.sxy.assign(n * R, 0.0);
      ref.sxs.assign(n * R, 0.0);
      ref.u.assign(n * R, 0.0);
      ref.p.assign(n * R, 0.0);
      ref.sum_w.assign(R, 1e-10);
      ref.ss2.assign(R, params.init_S2);
      ref.sys.assign(R, 0.0);
      ref.beta.assign(R, 0.0);
      ref.lambda = params.init_lambda;
      std::mt19937_64 rng(static_cast<unsigned>(5 * n + avx2));
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      for (int t = 0; t < 300; ++t) {
        const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); });
        const double y = std::cos(2.0 * x(0)) + x(n - 1) * x(n / 2) + 0.05 * uniform(rng);
        const double w = 0.1 + 0.9 * std::abs(uniform(rng));
        update_receptive_field(params, 2.0 * n, x, y, w, rf, scratch);

        const double lambda = ref.lambda;
        const double lambda_slow = 1.0 - (1.0 - lambda) / 10.0;
        const double w_old = lambda * ref.sum_w[0];
        for (int r = 0; r < R; ++r) ref.sum_w[r] = lambda * ref.sum_w[r] + w;
        const double inv_w = 1.0 / ref.sum_w[0];
        std::vector<double> z(n);
        for (int i = 0; i < n; ++i) {
          ref.mean_x[i] = (w_old * ref.mean_x[i] + w * x(i)) * inv_w;
          z[i] = x(i) - ref.mean_x[i];
        }
        ref.beta0 = (w_old * ref.beta0 + w * y) * inv_w;
        double res = y - ref.beta0;
        for (int r = 0; r < R; ++r) {
          double norm2[4] = {0.0, 0.0, 0.0, 0.0}, dot[4] = {0.0, 0.0, 0.0, 0.0};
          for (int i = 0; i < n; ++i) {
            double& v = ref.sxy[r * n + i];
            v = lambda_slow * v + (w * res) * z[i];
            norm2[i % 4] += v * v;
            dot[i % 4] += v * z[i];
          }
          const double nn = (norm2[0] + norm2[1]) + (norm2[2] + norm2[3]);
          const double inv_norm = nn > 0.0 ? 1.0 / std::sqrt(nn) : 0.0;
          const double s = ((dot[0] + dot[1]) + (dot[2] + dot[3])) * inv_norm;
          ref.ss2[r] = lambda * ref.ss2[r] + (w * s) * s;
          ref.sys[r] = lambda * ref.sys[r] + (w * s) * res;
          const double inv_ss2 = 1.0 / ref.ss2[r];
          ref.beta[r] = ref.sys[r] * inv_ss2;
          for (int i = 0; i < n; ++i) {
            ref.u[r * n + i] = ref.sxy[r * n + i] * inv_norm;
            ref.sxs[r * n + i] = lambda * ref.sxs[r * n + i] + (w * s) * z[i];
            ref.p[r * n + i] = ref.sxs[r * n + i] * inv_ss2;
            z[i] -= s * ref.p[r * n + i];
          }
          res -= ref.beta[r] * s;
        }
        ref.lambda = params.tau_lambda * lambda + (1.0 - params.tau_lambda) * params.final_lambda;
      }
      auto same = [](const double* a, const std::vector<double>& b) {
        return std::memcmp(a, b.data(), b.size() * sizeof(double)) == 0;
      };
      const std::string where = "n = " + std::to_string(n) + (avx2 ? ", AVX2" : ", SSE2");
      ASSERT_EQ(rf.n_reg(), R) << where;
      EXPECT_TRUE(same(rf.mean_x.data(), ref.mean_x)) << where;
      EXPECT_TRUE(same(rf.sxy.data(), ref.sxy)) << where;
      EXPECT_TRUE(same(rf.sxs.data(), ref.sxs)) << where;
      EXPECT_TRUE(same(rf.directions.data(), ref.u)) << where;
      EXPECT_TRUE(same(rf.loadings.data(), ref.p)) << where;
      EXPECT_TRUE(same(rf.sum_w.data(), ref.sum_w)) << where;
      EXPECT_TRUE(same(rf.ss2.data(), ref.ss2)) << where;
      EXPECT_TRUE(same(rf.sys.data(), ref.sys)) << where;
      EXPECT_TRUE(same(rf.beta.data(), ref.beta)) << where;
      EXPECT_EQ(std::memcmp(&rf.beta0, &ref.beta0, sizeof(double)), 0) << where;
      // The field's prediction at a sample against the same plain loop over the cached directions.
      const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); });
      double leverage = 0.0;
      const double y_hat = predict_receptive_field(rf, x, leverage, scratch);
      std::vector<double> z(n);
      for (int i = 0; i < n; ++i) z[i] = x(i) - ref.mean_x[i];
      double y_ref = ref.beta0, leverage_ref = 0.0;
      for (int r = 0; r < R; ++r) {
        double part[4] = {0.0, 0.0, 0.0, 0.0};
        for (int i = 0; i < n; ++i) part[i % 4] += ref.u[r * n + i] * z[i];
        const double s = (part[0] + part[1]) + (part[2] + part[3]);
        y_ref += ref.beta[r] * s;
        leverage_ref += s * s / ref.ss2[r];
        for (int i = 0; i < n; ++i) z[i] -= s * ref.p[r * n + i];
      }
      EXPECT_EQ(std::memcmp(&y_hat, &y_ref, sizeof(double)), 0) << where << ": " << y_hat << " vs " << y_ref;
      EXPECT_EQ(std::memcmp(&leverage, &leverage_ref, sizeof(double)), 0) << where;
    }
  }
}

// A field with random statistics: n inputs, R projections, the cached directions and loadings
// filled directly (prediction reads only those, β, β₀, x₀ and Σλws²).
ReceptiveField make_random_field(int n, int R, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  LwprParams params;
  params.init_n_reg = 1;
  ReceptiveField rf = make_receptive_field(params, Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Identity(n, n));
  while (rf.n_reg() < R) add_projection(params, rf);
  auto fill = [&](auto& m) { m = m.NullaryExpr(m.rows(), m.cols(), [&] { return uniform(rng); }); };
  fill(rf.mean_x);
  fill(rf.directions);
  fill(rf.loadings);
  fill(rf.beta);
  rf.ss2 = Eigen::VectorXd::NullaryExpr(R, [&] { return 0.5 + std::abs(uniform(rng)); });
  rf.beta0 = uniform(rng);
  return rf;
}

// The field prediction (with and without the leverage) on every copy, among them AVX2's fixed-size
// one for 21 inputs (z kept in registers), against a plain loop with the documented summation order
// (element i in partial sum i mod 4, added as (p0 + p1) + (p2 + p3)), at 1 to 6 projections.
TEST(ReceptiveField, FieldPredictionMatchesAPlainLoopBitForBitOnEveryCopy) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const int n : {4, 5, 7, 8, 13, 20, 21, 22}) {
    for (int R = 1; R <= 6; ++R) {
      const ReceptiveField rf = make_random_field(n, R, rng);
      for (int t = 0; t < 20; ++t) {
        const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); });
        std::vector<double> z(n);
        for (int i = 0; i < n; ++i) z[i] = x(i) - rf.mean_x(i);
        double y_ref = rf.beta0, leverage_ref = 0.0;
        for (int r = 0; r < R; ++r) {
          double part[4] = {0.0, 0.0, 0.0, 0.0};
          for (int i = 0; i < n; ++i) part[i % 4] += rf.directions(i, r) * z[i];
          const double s = (part[0] + part[1]) + (part[2] + part[3]);
          y_ref += rf.beta(r) * s;
          leverage_ref += s * s / rf.ss2(r);
          for (int i = 0; i < n; ++i) z[i] -= s * rf.loadings(i, r);
        }
        for (const bool avx2 : {false, true}) {
          if (avx2 && !has_avx2()) continue;
          FieldScratch scratch;
          scratch.resize(n, true);
          scratch.use_avx2 = avx2;
          const std::string where = "n = " + std::to_string(n) + ", R = " + std::to_string(R) +
                                    (avx2 ? ", AVX2" : ", SSE2");
          double leverage = 0.0;
          const double y = predict_receptive_field(rf, x, leverage, scratch);
          const double y_value = predict_receptive_field_value(rf, x, scratch);
          EXPECT_EQ(std::memcmp(&y, &y_ref, sizeof(double)), 0) << where << ": " << y << " vs " << y_ref;
          EXPECT_EQ(std::memcmp(&y_value, &y_ref, sizeof(double)), 0) << where;
          EXPECT_EQ(std::memcmp(&leverage, &leverage_ref, sizeof(double)), 0) << where;
        }
      }
    }
  }
}

// The AVX-512 copy of the 21-input field update (single fields and pairs) against AVX2 and SSE2:
// every statistic the same bits after 2 000 samples, with and without update_D, projections added,
// the pair's fields one projection apart. Fails when the copy is allowed FMA contraction.
TEST(ReceptiveField, Avx512FieldUpdateMatchesAvx2AndSse2BitForBit) {
  if (!has_avx512()) GTEST_SKIP() << "this CPU has no AVX-512 (F, VL, DQ): the AVX-512 field update is not tested";
  constexpr int n = 21;
  for (const bool update_d : {false, true}) {
    LwprParams params;
    params.update_D = update_d;
    params.init_lambda = 0.99;
    params.add_threshold = 0.9;  // add projections readily, so the test covers added ones
    const Eigen::MatrixXd D_a = 2.0 * Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd D_b = 0.5 * Eigen::MatrixXd::Identity(n, n);
    const ReceptiveField start_a = make_receptive_field(params, Eigen::VectorXd::Zero(n), D_a);
    ReceptiveField start_b = make_receptive_field(params, Eigen::VectorXd::Constant(n, 0.2), D_b);
    add_projection(params, start_b);  // b one projection ahead
    // Per copy (0 SSE2, 1 AVX2, 2 AVX-512): a single field, and a pair.
    ReceptiveField single[3], pair_a[3], pair_b[3];
    FieldScratch scratch[3][2];
    for (int c = 0; c < 3; ++c) {
      single[c] = start_a;
      pair_a[c] = start_a;
      pair_b[c] = start_b;
      for (FieldScratch& sc : scratch[c]) {
        sc.resize(n, true);
        sc.use_avx2 = c >= 1;
        sc.use_avx512 = c == 2;
      }
    }
    std::mt19937_64 rng(static_cast<unsigned>(512 + update_d));
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
      const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.5 * uniform(rng); });
      const double y = std::sin(3.0 * x(0)) + x(1) * x(n - 1) + 0.05 * uniform(rng);
      const double w_a = 0.05 + 0.95 * std::abs(uniform(rng));
      const double w_b = 0.05 + 0.95 * std::abs(uniform(rng));
      for (int c = 0; c < 3; ++c) {
        update_receptive_field(params, 2.0 * n, x, y, w_a, single[c], scratch[c][0]);
        update_receptive_field_pair(params, 2.0 * n, x, y, w_a, pair_a[c], scratch[c][0], w_b, pair_b[c],
                                    scratch[c][1]);
      }
    }
    EXPECT_GT(single[2].n_reg(), params.init_n_reg) << "no projection was added";
    const char* names[3] = {"SSE2", "AVX2", "AVX-512"};
    for (int c = 0; c < 2; ++c) {
      for (const auto& [field, copies] : {std::pair{"single", single}, std::pair{"pair a", pair_a},
                                         std::pair{"pair b", pair_b}}) {
        const std::vector<double> expected = flatten_field(copies[c]), actual = flatten_field(copies[2]);
        ASSERT_EQ(expected.size(), actual.size()) << field << ", " << names[c];
        EXPECT_EQ(std::memcmp(expected.data(), actual.data(), expected.size() * sizeof(double)), 0)
            << field << ": AVX-512 against " << names[c] << ", update_D " << update_d;
      }
    }
  }
}

}  // namespace
}  // namespace armfarm::lwpr

namespace armfarm::lwpr {
namespace {

// A full metric's leave-one-out sums and metric step with 2 or 3 inputs on fixed-size arrays
// (FieldScratch::small_full_metric, the default) against the general code (the flag cleared):
// every statistic the same bits after the same stream, single and pair updates, with and without
// meta learning, for both kernels, the SSE2 and AVX2 copies, with w the field's own activation (calc_activation(), which
// sums q as the model's scan does; the fixed-size step takes the Gaussian's exp(−q/2) from w).
// At n = 3 a projection is added on the way.
TEST(ReceptiveField, SmallFullMetricUpdateMatchesTheGeneralUpdateBitForBit) {
  for (const int n : {2, 3}) {
    for (const bool meta : {false, true}) {
      for (const Kernel kernel : {Kernel::kGaussian, Kernel::kBisquare}) {
        for (const bool avx2 : {false, true}) {
          if (avx2 && !has_avx2()) continue;
          LwprParams params = make_full_metric_params(meta);
          params.kernel = kernel;
          std::mt19937_64 rng(static_cast<unsigned>(31 * n + 2 * meta + static_cast<int>(kernel)));
          std::uniform_real_distribution<double> uniform(-1.0, 1.0);
          Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return uniform(rng); });
          const Eigen::MatrixXd D = 3.0 * Eigen::MatrixXd::Identity(n, n) + A.transpose() * A;
          const Eigen::VectorXd c_b = Eigen::VectorXd::Constant(n, 0.1);
          const ReceptiveField start[2] = {make_receptive_field(params, Eigen::VectorXd::Zero(n), D),
                                           make_receptive_field(params, c_b, 0.5 * D)};
          ReceptiveField general[2] = {start[0], start[1]}, small[2] = {start[0], start[1]};
          ReceptiveField general_pair[2] = {start[0], start[1]}, small_pair[2] = {start[0], start[1]};
          FieldScratch scratch[4];
          for (int k = 0; k < 4; ++k) {
            scratch[k].resize(n, false);
            scratch[k].small_full_metric = k >= 2;  // 0, 1 general; 2, 3 fixed-size
            scratch[k].use_avx2 = avx2;
          }
          int updates = 0;
          for (int i = 0; i < 3000; ++i) {
            const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.4 * uniform(rng); });
            const double y = std::sin(3.0 * x(0)) + x(1) * x(n - 1) + 0.05 * uniform(rng);
            for (int k = 0; k < 2; ++k) {
              const double w_general = calc_activation(general[k], kernel, x, 0.0, scratch[0]);
              const double w_small = calc_activation(small[k], kernel, x, 0.0, scratch[2]);
              if (w_general > 0.0) update_receptive_field(params, 2.0 * n, x, y, w_general, general[k], scratch[0]);
              if (w_small > 0.0) update_receptive_field(params, 2.0 * n, x, y, w_small, small[k], scratch[2]);
              updates += w_general > 0.0 ? 1 : 0;
            }
            const double wg[2] = {calc_activation(general_pair[0], kernel, x, 0.0, scratch[0]),
                                  calc_activation(general_pair[1], kernel, x, 0.0, scratch[0])};
            const double ws[2] = {calc_activation(small_pair[0], kernel, x, 0.0, scratch[2]),
                                  calc_activation(small_pair[1], kernel, x, 0.0, scratch[2])};
            if (wg[0] > 0.0 && wg[1] > 0.0) {
              update_receptive_field_pair(params, 2.0 * n, x, y, wg[0], general_pair[0], scratch[0], wg[1],
                                          general_pair[1], scratch[1]);
            }
            if (ws[0] > 0.0 && ws[1] > 0.0) {
              update_receptive_field_pair(params, 2.0 * n, x, y, ws[0], small_pair[0], scratch[2], ws[1], small_pair[1],
                                          scratch[3]);
            }
          }
          const std::string where = "n = " + std::to_string(n) + ", meta " + std::to_string(meta) + ", kernel " +
                                    std::to_string(static_cast<int>(kernel)) + (avx2 ? ", AVX2" : ", SSE2");
          EXPECT_GT(updates, 3000) << where;
          if (n == 3) {
            EXPECT_GT(general[0].n_reg(), params.init_n_reg) << where << ": no projection was added";
          }
          for (int k = 0; k < 2; ++k) {
            EXPECT_NE(general[k].metric_factor, start[k].metric_factor) << where << ": the metric never moved";
            const std::pair<const ReceptiveField*, const ReceptiveField*> compared[2] = {
                {&general[k], &small[k]}, {&general_pair[k], &small_pair[k]}};
            for (const auto& [a, b] : compared) {
              const std::vector<double> fa = flatten_field(*a), fb = flatten_field(*b);
              ASSERT_EQ(fa.size(), fb.size()) << where << ", field " << k;
              EXPECT_EQ(std::memcmp(fa.data(), fb.data(), fa.size() * sizeof(double)), 0) << where << ", field " << k;
            }
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace armfarm::lwpr

namespace armfarm::lwpr {
namespace {

// The statistics of a field of 2 or 3 inputs on local values (FieldScratch::small_statistics, the
// default) against the general code (the flag cleared): after every update, every statistic and the
// s_r, residuals and 1 − h_r the rest of the update reads are the same bits. Single updates and
// update_receptive_field_pair with every pair of projection counts 1..n (fields that start with 1, 2
// and n projections; at n = 3 the second adds its third on the way), SSE2 and AVX2, with and
// without update_D.
TEST(ReceptiveField, SmallStatisticsMatchTheGeneralStatisticsBitForBit) {
  auto state = [](const ReceptiveField& rf, const FieldScratch& scratch) {
    std::vector<double> all = flatten_field(rf);
    for (const Eigen::VectorXd* v : {&scratch.s, &scratch.residual, &scratch.one_minus_h}) {
      all.insert(all.end(), v->data(), v->data() + rf.n_reg());
    }
    return all;
  };
  auto same_bits = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
  };
  for (const int n : {2, 3}) {
    for (const bool avx2 : {false, true}) {
      if (avx2 && !has_avx2()) continue;
      for (const bool update_d : {false, true}) {
        const std::string where =
            "n = " + std::to_string(n) + (avx2 ? ", AVX2" : ", SSE2") + ", update_D " + std::to_string(update_d);
        constexpr int kKinds = 3;  // fields starting with 1, 2 and n projections
        const int start_reg[kKinds] = {1, 2, n};
        ReceptiveField start[kKinds];
        for (int k = 0; k < kKinds; ++k) {
          LwprParams params;
          params.init_n_reg = start_reg[k];
          params.init_lambda = 0.99;
          const Eigen::MatrixXd D = (1.0 + k) * Eigen::MatrixXd::Identity(n, n);
          start[k] = make_receptive_field(params, Eigen::VectorXd::Constant(n, 0.1 * k), D);
        }
        LwprParams params;
        params.update_D = update_d;
        params.add_threshold = 0.9;  // add projections readily
        FieldScratch scratch[4];
        for (int k = 0; k < 4; ++k) {
          scratch[k].resize(n, true);
          scratch[k].small_statistics = k >= 2;  // 0, 1 general; 2, 3 on locals
          scratch[k].use_avx2 = avx2;
        }
        ReceptiveField general[kKinds], small[kKinds];
        ReceptiveField general_pair[kKinds][kKinds][2], small_pair[kKinds][kKinds][2];
        for (int a = 0; a < kKinds; ++a) {
          general[a] = small[a] = start[a];
          for (int b = 0; b < kKinds; ++b) {
            general_pair[a][b][0] = small_pair[a][b][0] = start[a];
            general_pair[a][b][1] = small_pair[a][b][1] = start[b];
          }
        }
        std::mt19937_64 rng(static_cast<unsigned>(17 * n + 2 * avx2 + update_d));
        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        std::vector<int> pair_steps(16, 0);  // by (R_a − 1)·4 + R_b − 1
        std::vector<int> single_steps(4, 0);
        bool diverged = false;
        for (int i = 0; i < 1500 && !diverged; ++i) {
          const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.5 * uniform(rng); });
          const double y = std::sin(3.0 * x(0)) + x(1) * x(n - 1) + 0.05 * uniform(rng);
          double w[kKinds][2];
          for (auto& wk : w) {
            for (double& v : wk) v = 0.05 + 0.95 * std::abs(uniform(rng));
          }
          for (int a = 0; a < kKinds && !diverged; ++a) {
            ++single_steps[general[a].n_reg() - 1];
            update_receptive_field(params, 2.0 * n, x, y, w[a][0], general[a], scratch[0]);
            update_receptive_field(params, 2.0 * n, x, y, w[a][0], small[a], scratch[2]);
            if (!same_bits(state(general[a], scratch[0]), state(small[a], scratch[2]))) {
              ADD_FAILURE() << where << ": single update, field kind " << a << ", sample " << i;
              diverged = true;
            }
            for (int b = 0; b < kKinds && !diverged; ++b) {
              ReceptiveField(&g)[2] = general_pair[a][b];
              ReceptiveField(&s)[2] = small_pair[a][b];
              ++pair_steps[(g[0].n_reg() - 1) * 4 + g[1].n_reg() - 1];
              update_receptive_field_pair(params, 2.0 * n, x, y, w[a][0], g[0], scratch[0], w[b][1], g[1], scratch[1]);
              update_receptive_field_pair(params, 2.0 * n, x, y, w[a][0], s[0], scratch[2], w[b][1], s[1], scratch[3]);
              for (int f = 0; f < 2 && !diverged; ++f) {
                if (!same_bits(state(g[f], scratch[f]), state(s[f], scratch[2 + f]))) {
                  ADD_FAILURE() << where << ": pair update (kinds " << a << ", " << b << "), field " << f
                                << ", sample " << i;
                  diverged = true;
                }
              }
            }
          }
        }
        if (diverged) continue;  // the stream stopped there
        // Every projection count, single and in every pair, and (n = 3) the added projection.
        for (int r = 1; r <= n; ++r) {
          EXPECT_GT(single_steps[r - 1], 0) << where << ": no single update with R = " << r;
          for (int rb = 1; rb <= n; ++rb) {
            EXPECT_GT(pair_steps[(r - 1) * 4 + rb - 1], 0) << where << ": no pair update with R = " << r << ", " << rb;
          }
        }
        if (n == 3) {
          EXPECT_EQ(general[1].n_reg(), 3) << where << ": the field of 2 projections added none";
        }
      }
    }
  }
}

}  // namespace
}  // namespace armfarm::lwpr

namespace armfarm::lwpr {
namespace {

// update_receptive_fields() on groups of 1–4 fields against update_receptive_field() on each:
// every statistic the same bits after the same stream, for n = 2 and 3 with full metrics, fields
// of different projection counts in one group (so a group's metric steps split by R, and at n = 3
// projections are added on the way) and of one projection count (four such fields' statistics run
// as two pairs in lockstep), with and without meta learning, on SSE2 (the metric steps one by one)
// and on AVX2 (in vector lanes).
TEST(ReceptiveField, FieldGroupUpdateMatchesSingleUpdatesBitForBit) {
  for (const int n : {2, 3}) {
    for (const int mode : {0, 1, 2, 3}) {
      const bool meta = (mode & 1) != 0;
      const bool one_r = (mode & 2) != 0;
      for (const bool avx2 : {false, true}) {
        if (avx2 && !has_avx2()) continue;
        LwprParams params = make_full_metric_params(meta);
        params.init_n_reg = 1;
        std::mt19937_64 rng(static_cast<unsigned>(17 * n + 2 * mode + avx2));
        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        ReceptiveField start[kFieldGroup];
        for (int k = 0; k < kFieldGroup; ++k) {
          Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return uniform(rng); });
          const Eigen::MatrixXd D = 2.0 * Eigen::MatrixXd::Identity(n, n) + A.transpose() * A;
          start[k] = make_receptive_field(params, Eigen::VectorXd::Constant(n, 0.05 * k), D);
          const int n_reg = one_r ? 2 : 1 + k % n;  // R = 2, 2, 2, 2 or 1, 2, (3,) 1, …
          while (start[k].n_reg() < n_reg) add_projection(params, start[k]);
        }
        for (int count = 1; count <= kFieldGroup; ++count) {
          ReceptiveField group[kFieldGroup], alone[kFieldGroup];
          FieldScratch scratch[kFieldGroup], single;
          single.resize(n, false);
          single.use_avx2 = false;
          ReceptiveField* fields[kFieldGroup];
          FieldScratch* scratches[kFieldGroup];
          for (int k = 0; k < count; ++k) {
            group[k] = start[k];
            alone[k] = start[k];
            scratch[k].resize(n, false);
            scratch[k].use_avx2 = avx2;
            fields[k] = &group[k];
            scratches[k] = &scratch[k];
          }
          int stepped = 0;
          for (int i = 0; i < 1500; ++i) {
            const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.3 * uniform(rng); });
            const double y = std::sin(3.0 * x(0)) + x(1) * x(n - 1) + 0.05 * uniform(rng);
            double w[kFieldGroup];
            for (int k = 0; k < count; ++k) {
              w[k] = calc_activation(group[k], Kernel::kGaussian, x, 0.0, single);
              const double w_alone = calc_activation(alone[k], Kernel::kGaussian, x, 0.0, single);
              update_receptive_field(params, 2.0 * n, x, y, w_alone, alone[k], single);
            }
            update_receptive_fields(params, 2.0 * n, x, y, count, w, fields, scratches);
          }
          const std::string where = "n = " + std::to_string(n) + ", meta " + std::to_string(meta) +
                                    (one_r ? ", one R, " : ", mixed R, ") +
                                    std::to_string(count) + " fields" + (avx2 ? ", AVX2" : ", SSE2");
          for (int k = 0; k < count; ++k) {
            stepped += group[k].metric_factor != start[k].metric_factor ? 1 : 0;
            const std::vector<double> a = flatten_field(group[k]), b = flatten_field(alone[k]);
            ASSERT_EQ(a.size(), b.size()) << where << ", field " << k;
            EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0) << where << ", field " << k;
          }
          EXPECT_EQ(stepped, count) << where << ": every field's metric moved";
          if (n == 3 && count >= 2) {  // field 1 starts with 2 of 3 projections (the rule needs 2)
            EXPECT_GT(group[1].n_reg(), start[1].n_reg()) << where << ": no projection was added";
          }
        }
      }
    }
  }
  EXPECT_THROW(update_receptive_fields(LwprParams{}, 4.0, Eigen::VectorXd::Zero(2), 0.0, kFieldGroup + 1, nullptr,
                                       nullptr, nullptr),
               std::invalid_argument);
}

}  // namespace
}  // namespace armfarm::lwpr
