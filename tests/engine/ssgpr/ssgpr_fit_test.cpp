// Marginal-likelihood fit: analytic gradient against finite differences; the fitted lengthscale
// of a GP sample with a known lengthscale lands near it.
#include "engine/ssgpr/ssgpr_fit.hpp"

#include "engine/random/random_stream.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace armfarm::ssgpr {
namespace {

// N inputs uniform in [−3, 3]^n_in and one GP draw per output with the given hyperparameters.
void make_gp_batch(int N, const Eigen::VectorXd& ell, double sf2, double sn2, int n_out, std::uint64_t seed,
                   Eigen::MatrixXd& X, Eigen::MatrixXd& Y) {
  RandomStream stream(seed, "test.gp_batch");
  const int n_in = static_cast<int>(ell.size());
  X.resize(N, n_in);
  for (int i = 0; i < N; ++i) {
    for (int d = 0; d < n_in; ++d) X(i, d) = stream.uniform(-3.0, 3.0);
  }
  Eigen::MatrixXd K(N, N);
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < N; ++j) {
      K(i, j) = sf2 * std::exp(-0.5 * (X.row(i) - X.row(j)).cwiseQuotient(ell.transpose()).squaredNorm());
    }
  }
  K.diagonal().array() += sn2;
  const Eigen::MatrixXd L = K.llt().matrixL();
  Eigen::MatrixXd Z(N, n_out);
  for (int o = 0; o < n_out; ++o) {
    for (int i = 0; i < N; ++i) Z(i, o) = stream.normal();
  }
  Y = L * Z;
}

TEST(SsgprFit, GradientMatchesFiniteDifferences) {
  Eigen::MatrixXd X, Y;
  make_gp_batch(40, Eigen::Vector2d(0.8, 1.5), 1.0, 0.05, 2, 1, X, Y);
  const Eigen::Vector2d ell(0.6, 2.0);
  const double sf2 = 1.4, sn2 = 0.08;
  Eigen::VectorXd gradient;
  calc_gp_log_likelihood(X, Y, ell, sf2, sn2, &gradient);
  ASSERT_EQ(gradient.size(), 4);
  const double h = 1e-5;
  auto at = [&](int k, double delta) {
    Eigen::Vector2d l = ell;
    double f = sf2, n = sn2;
    if (k < 2) l(k) *= std::exp(delta);
    if (k == 2) f *= std::exp(delta);
    if (k == 3) n *= std::exp(delta);
    return calc_gp_log_likelihood(X, Y, l, f, n, nullptr);
  };
  for (int k = 0; k < 4; ++k) {
    const double numeric = (at(k, h) - at(k, -h)) / (2 * h);
    EXPECT_NEAR(gradient(k), numeric, 1e-5 * (1.0 + std::abs(numeric))) << "parameter " << k;
  }
}

TEST(SsgprFit, FittedLengthscaleOfKnownGpLandsNearIt) {
  // A 1-D GP draw with ℓ = 0.5, σ_f² = 1, σ_n² = 0.01, 3 outputs sharing them; start far off.
  Eigen::MatrixXd X, Y;
  make_gp_batch(150, Eigen::VectorXd::Constant(1, 0.5), 1.0, 0.01, 3, 2, X, Y);
  SsgprParams start;
  start.lengthscales = Eigen::VectorXd::Constant(1, 2.0);
  start.signal_variance = 0.3;
  start.noise_variance = 0.3;
  SsgprFitConfig config;
  config.fit_output_scale = false;
  SsgprFitReport report;
  const SsgprParams fitted = calc_fitted_params(X, Y, start, config, &report);
  EXPECT_GT(report.log_likelihood_end, report.log_likelihood_start + 10.0);
  EXPECT_NEAR(fitted.lengthscales(0), 0.5, 0.1);
  EXPECT_NEAR(std::log(fitted.noise_variance), std::log(0.01), std::log(2.0));
  EXPECT_NEAR(std::log(fitted.signal_variance), std::log(1.0), std::log(2.5));
}

TEST(SsgprFit, IrrelevantInputGetsLongLengthscaleAndScalesAreFitted) {
  // y depends on input 0 only (ℓ = 0.7); input 1 is noise the kernel should learn to ignore.
  Eigen::MatrixXd X, Y;
  make_gp_batch(120, Eigen::Vector2d(0.7, 1e6), 1.0, 0.01, 1, 3, X, Y);
  Y *= 20.0;  // an output in other units: the RMS output scale takes it out
  SsgprParams start;
  start.lengthscales = Eigen::Vector2d(1.0, 1.0);
  const SsgprParams fitted = calc_fitted_params(X, Y, start, SsgprFitConfig{});
  EXPECT_GT(fitted.lengthscales(1), 5.0 * fitted.lengthscales(0));
  EXPECT_NEAR(fitted.lengthscales(0), 0.7, 0.2);
  const double rms = std::sqrt(Y.squaredNorm() / Y.rows());
  EXPECT_DOUBLE_EQ(fitted.output_scale(0), rms);
}

TEST(SsgprFit, BadBatchThrows) {
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(5, 1), Y = Eigen::MatrixXd::Zero(4, 1);
  EXPECT_THROW(calc_fitted_params(X, Y, SsgprParams{}, SsgprFitConfig{}), std::invalid_argument);
  Y = Eigen::MatrixXd::Zero(5, 1);
  X(2, 0) = std::nan("");
  EXPECT_THROW(calc_fitted_params(X, Y, SsgprParams{}, SsgprFitConfig{}), std::invalid_argument);
}

}  // namespace
}  // namespace armfarm::ssgpr
