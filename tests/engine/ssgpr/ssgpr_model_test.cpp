// SSGPR: incremental posterior = batch Bayesian linear regression on the same features; large D
// approaches the exact GP; determinism, forgetting, trust, NaN rejection, concurrent predict.
#include "engine/ssgpr/ssgpr_model.hpp"

#include "engine/random/random_stream.hpp"
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

namespace armfarm::ssgpr {
namespace {

double target(double x) { return std::sin(2.0 * x) + 0.3 * x; }

struct Sample1D {
  std::vector<double> x, y;
};

Sample1D make_samples(int n, std::uint64_t seed) {
  RandomStream stream(seed, "test.samples");
  Sample1D s;
  for (int i = 0; i < n; ++i) {
    const double x = stream.uniform(-3.0, 3.0);
    s.x.push_back(x);
    s.y.push_back(target(x) + 0.1 * stream.normal());
  }
  return s;
}

Eigen::VectorXd vec1(double v) { return Eigen::VectorXd::Constant(1, v); }

std::string save(const SsgprModel& model) {
  std::ostringstream out(std::ios::binary);
  write_ssgpr_model(model, out);
  return out.str();
}

SsgprParams params_1d(int features) {
  SsgprParams p;
  p.features = features;
  p.lengthscales = vec1(0.7);
  p.signal_variance = 1.3;
  p.noise_variance = 0.02;
  p.trust_min_samples = 5;
  return p;
}

// Closed-form batch posterior with weights λ^(N−i) on sample i and prior λ^N σ_n² I.
void check_against_batch(const SsgprParams& params, int n) {
  const Sample1D data = make_samples(n, 5);
  SsgprModel model(1, 1, params);
  for (int i = 0; i < n; ++i) model.update(vec1(data.x[i]), vec1(data.y[i]));
  const int F = 2 * params.features;
  const double lambda = params.forgetting;
  Eigen::MatrixXd A = std::pow(lambda, n) * params.noise_variance * Eigen::MatrixXd::Identity(F, F);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(F);
  Eigen::VectorXd phi(F);
  for (int i = 0; i < n; ++i) {
    model.calc_features(vec1(data.x[i]), phi);
    const double weight = std::pow(lambda, n - 1 - i);
    A += weight * phi * phi.transpose();
    b += weight * phi * data.y[i];
  }
  const Eigen::LDLT<Eigen::MatrixXd> solver(A);
  const Eigen::VectorXd w = solver.solve(b);
  auto ws = model.make_workspace();
  for (double x = -3.5; x <= 3.5; x += 0.25) {
    model.calc_features(vec1(x), phi);
    const double mean = phi.dot(w);
    const double variance = params.noise_variance * (1.0 + phi.dot(solver.solve(phi)));
    SsgprPredictionDetail detail;
    const Prediction p = model.predict(vec1(x), *ws, detail);
    EXPECT_NEAR(detail.mean(0), mean, 1e-9) << "x = " << x;
    EXPECT_NEAR(detail.predictive_variance(0), variance, 1e-9) << "x = " << x;
    EXPECT_NEAR(detail.latent_variance(0), variance - params.noise_variance, 1e-9) << "x = " << x;
    ASSERT_TRUE(p.output_trusted[0]);  // near the data, variance_fraction ≪ 0.5
    EXPECT_EQ(p.value(0), detail.mean(0));
    EXPECT_DOUBLE_EQ(p.confidence(0), std::sqrt(detail.predictive_variance(0)));
  }
}

TEST(SsgprModel, IncrementalPosteriorEqualsBatchBayesianLinearRegression) {
  SsgprParams p = params_1d(25);
  p.resolve_interval = 0;  // the gain update alone
  check_against_batch(p, 300);
  p.resolve_interval = 7;  // mixed with re-solves
  check_against_batch(p, 300);
}

TEST(SsgprModel, IncrementalPosteriorWithForgettingEqualsWeightedBatch) {
  SsgprParams p = params_1d(25);
  p.forgetting = 0.995;
  check_against_batch(p, 300);
}

TEST(SsgprModel, LargeFeatureCountApproachesExactGp) {
  const Sample1D data = make_samples(30, 9);
  const SsgprParams base = params_1d(1);
  const double sf2 = base.signal_variance, sn2 = base.noise_variance, ell = base.lengthscales(0);
  auto kernel = [&](double a, double b) { return sf2 * std::exp(-0.5 * (a - b) * (a - b) / (ell * ell)); };
  const int N = static_cast<int>(data.x.size());
  Eigen::MatrixXd K(N, N);
  Eigen::VectorXd y(N);
  for (int i = 0; i < N; ++i) {
    y(i) = data.y[i];
    for (int j = 0; j < N; ++j) K(i, j) = kernel(data.x[i], data.x[j]) + (i == j ? sn2 : 0.0);
  }
  const Eigen::VectorXd alpha = K.llt().solve(y);
  // Root-mean-square difference of the posterior means on a grid, averaged over 5 seeds (the
  // feature approximation's error shrinks like 1/√D).
  auto calc_rms_error = [&](int features) {
    double total = 0.0;
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      SsgprParams p = base;
      p.features = features;
      p.seed = seed;
      SsgprModel model(1, 1, p);
      for (int i = 0; i < N; ++i) model.update(vec1(data.x[i]), vec1(data.y[i]));
      Eigen::VectorXd phi(2 * features);
      double sum2 = 0.0;
      int count = 0;
      for (double x = -3.0; x <= 3.0; x += 0.1, ++count) {
        double gp = 0.0;
        for (int i = 0; i < N; ++i) gp += kernel(x, data.x[i]) * alpha(i);
        model.calc_features(vec1(x), phi);
        const double mean = phi.dot(model.state().weights.col(0));
        sum2 += (mean - gp) * (mean - gp);
      }
      total += std::sqrt(sum2 / count) / 5.0;
    }
    return total;
  };
  const double e_small = calc_rms_error(10), e_large = calc_rms_error(1000);
  // Measured: 0.059 at D = 10, 0.034 at D = 100, 0.0073 at D = 1000.
  EXPECT_LT(e_large, 0.02) << "D = 1000";  // on a function of amplitude ~1.5
  EXPECT_LT(e_large, 0.3 * e_small) << "D = 10: " << e_small;
}

TEST(SsgprModel, SameSeedSameModelOtherSeedOtherModel) {
  const Sample1D data = make_samples(100, 4);
  auto train = [&](std::uint64_t seed) {
    SsgprParams p = params_1d(30);
    p.seed = seed;
    SsgprModel model(1, 1, p);
    for (int i = 0; i < 100; ++i) model.update(vec1(data.x[i]), vec1(data.y[i]));
    return save(model);
  };
  EXPECT_EQ(train(7), train(7));
  EXPECT_NE(train(7), train(8));
  // Frequencies are RandomStream(seed, "ssgpr.features") normals over the lengthscale, row by row.
  SsgprParams p = params_1d(3);
  p.lengthscales = Eigen::Vector2d(0.5, 2.0);
  const SsgprModel model(2, 1, p);
  RandomStream stream(p.seed, "ssgpr.features");
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(model.state().frequencies(i, 0), stream.normal() / 0.5);
    EXPECT_EQ(model.state().frequencies(i, 1), stream.normal() / 2.0);
  }
}

TEST(SsgprModel, ForgettingWeighsRecentDataMore) {
  // 1000 samples of y = +1, then 100 of y = −1 at the same inputs. With λ = 0.97 the old data
  // weigh 0.97^100 ≈ 0.05 against the new: the prediction is within 0.15 of −1. Without
  // forgetting it stays nearer the old mean (≈ (1000 − 100)/1100 ≈ +0.8).
  auto predict_after = [](double forgetting) {
    SsgprParams p = params_1d(20);
    p.forgetting = forgetting;
    SsgprModel model(1, 1, p);
    RandomStream stream(2, "test.forgetting");
    for (int i = 0; i < 1000; ++i) model.update(vec1(stream.uniform(-1.0, 1.0)), vec1(1.0));
    for (int i = 0; i < 100; ++i) model.update(vec1(stream.uniform(-1.0, 1.0)), vec1(-1.0));
    auto ws = model.make_workspace();
    double mean = 0.0;
    for (double x = -0.8; x <= 0.8; x += 0.2) mean += model.predict(vec1(x), *ws).value(0) / 9.0;
    return mean;
  };
  EXPECT_NEAR(predict_after(0.97), -1.0, 0.15);
  EXPECT_GT(predict_after(1.0), 0.5);
}

TEST(SsgprModel, NonFiniteOrMissizedSampleIsRejectedAndModelUnchanged) {
  SsgprModel model(2, 2, params_1d(10));
  model.update(Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(1.0, 2.0));
  const std::string before = save(model);
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(model.update(Eigen::Vector2d(nan, 0.2), Eigen::Vector2d(1.0, 2.0)), std::invalid_argument);
  EXPECT_THROW(model.update(Eigen::Vector2d(0.1, inf), Eigen::Vector2d(1.0, 2.0)), std::invalid_argument);
  EXPECT_THROW(model.update(Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(nan, 2.0)), std::invalid_argument);
  EXPECT_THROW(model.update(Eigen::Vector2d(0.1, 0.2), Eigen::Vector2d(1.0, -inf)), std::invalid_argument);
  EXPECT_THROW(model.update(Eigen::Vector2d(1e308, 1e308), Eigen::Vector2d(1.0, 2.0)), std::invalid_argument);
  EXPECT_THROW(model.update(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector2d(1.0, 2.0)), std::invalid_argument);
  EXPECT_EQ(save(model), before);
  auto ws = model.make_workspace();
  EXPECT_THROW(model.predict(Eigen::Vector2d(nan, 0.0), *ws), std::invalid_argument);
  PredictionWorkspace foreign;
  EXPECT_THROW(model.predict(Eigen::Vector2d(0.0, 0.0), foreign), std::invalid_argument);
}

TEST(SsgprModel, InvalidParametersThrow) {
  SsgprParams p;
  p.features = 0;
  EXPECT_THROW(SsgprModel(1, 1, p), std::invalid_argument);
  p = SsgprParams{};
  p.lengthscales = Eigen::Vector3d(1.0, 1.0, 1.0);
  EXPECT_THROW(SsgprModel(2, 1, p), std::invalid_argument);
  p = SsgprParams{};
  p.noise_variance = 0.0;
  EXPECT_THROW(SsgprModel(1, 1, p), std::invalid_argument);
  p = SsgprParams{};
  p.forgetting = 1.5;
  EXPECT_THROW(SsgprModel(1, 1, p), std::invalid_argument);
}

TEST(SsgprModel, TrustNeedsSamplesAndLowVariance) {
  SsgprParams p = params_1d(50);
  p.trust_min_samples = 20;
  SsgprModel model(1, 1, p);
  auto ws = model.make_workspace();
  RandomStream stream(1, "test.trust");
  for (int i = 0; i < 19; ++i) model.update(vec1(stream.uniform(-1.0, 1.0)), vec1(0.5));
  SsgprPredictionDetail detail;
  Prediction pr = model.predict(vec1(0.0), *ws, detail);
  EXPECT_FALSE(pr.output_trusted[0]);
  EXPECT_FALSE(pr.trustworthy);
  EXPECT_EQ(pr.value(0), 0.0);
  EXPECT_TRUE(std::isinf(pr.confidence(0)));
  EXPECT_LT(detail.variance_fraction, 0.5);  // the count alone withheld trust
  model.update(vec1(0.3), vec1(0.5));
  pr = model.predict(vec1(0.0), *ws, detail);
  EXPECT_TRUE(pr.trustworthy);
  EXPECT_GT(pr.max_activation, 0.5);
  // Far from every sample the posterior is nearly the prior: untrusted.
  pr = model.predict(vec1(8.0), *ws, detail);
  EXPECT_GT(detail.variance_fraction, 0.9);
  EXPECT_FALSE(pr.output_trusted[0]);
  EXPECT_NEAR(std::sqrt(detail.predictive_variance(0)), std::sqrt(p.signal_variance + p.noise_variance), 0.1);
}

TEST(SsgprModel, OutputScaleScalesMeanAndConfidence) {
  const Sample1D data = make_samples(100, 3);
  SsgprParams p = params_1d(20);
  SsgprModel unit(1, 2, p);
  p.output_scale = Eigen::Vector2d(1.0, 10.0);
  SsgprModel scaled(1, 2, p);
  for (int i = 0; i < 100; ++i) {
    unit.update(vec1(data.x[i]), Eigen::Vector2d(data.y[i], data.y[i]));
    scaled.update(vec1(data.x[i]), Eigen::Vector2d(data.y[i], 10.0 * data.y[i]));
  }
  auto wa = unit.make_workspace();
  auto wb = scaled.make_workspace();
  const Prediction a = unit.predict(vec1(0.4), *wa), b = scaled.predict(vec1(0.4), *wb);
  EXPECT_NEAR(b.value(1), 10.0 * a.value(1), 1e-12);
  EXPECT_NEAR(b.confidence(1), 10.0 * a.confidence(1), 1e-12);
  EXPECT_EQ(b.value(0), a.value(0));
  EXPECT_EQ(scaled.size(), 20u);
}

TEST(SsgprModel, ConstPredictFromTwoThreadsMatchesSerial) {
  const Sample1D data = make_samples(200, 6);
  SsgprModel model(1, 1, params_1d(40));
  for (int i = 0; i < 200; ++i) model.update(vec1(data.x[i]), vec1(data.y[i]));
  std::vector<double> serial(400), parallel(400);
  auto ws = model.make_workspace();
  for (int i = 0; i < 400; ++i) serial[i] = model.predict(vec1(-3.0 + 0.015 * i), *ws).value(0);
  auto run = [&](int first) {
    auto own = model.make_workspace();
    for (int i = first; i < 400; i += 2) parallel[i] = model.predict(vec1(-3.0 + 0.015 * i), *own).value(0);
  };
  std::thread a(run, 0), b(run, 1);
  a.join();
  b.join();
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace armfarm::ssgpr
