// Marginal-likelihood fit of the SE kernel's hyperparameters by iRprop−.
#include "engine/ssgpr/ssgpr_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace armfarm::ssgpr {
namespace {

constexpr double kLog2Pi = 1.8378770664093454836;

}  // namespace

double calc_gp_log_likelihood(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, const Eigen::VectorXd& lengthscales,
                              double signal_variance, double noise_variance, Eigen::VectorXd* gradient) {
  const Eigen::Index N = X.rows(), n_in = X.cols(), n_out = Y.cols();
  if (Y.rows() != N || lengthscales.size() != n_in || N < 1) {
    throw std::invalid_argument("SSGPR fit: X, Y and lengthscales have inconsistent sizes");
  }
  const Eigen::MatrixXd Xs = X * lengthscales.cwiseInverse().asDiagonal();  // x_d / ℓ_d
  const Eigen::VectorXd sq = Xs.rowwise().squaredNorm();
  Eigen::MatrixXd Kse = (sq.replicate(1, N) + sq.transpose().replicate(N, 1) - 2.0 * Xs * Xs.transpose());
  Kse = (-0.5 * Kse.cwiseMax(0.0)).array().exp().matrix() * signal_variance;  // σ_f² K_SE
  Eigen::MatrixXd K = Kse;
  K.diagonal().array() += noise_variance;
  const Eigen::LLT<Eigen::MatrixXd> llt(K);
  if (llt.info() != Eigen::Success) throw std::invalid_argument("SSGPR fit: the kernel matrix is not positive definite");
  const Eigen::MatrixXd alpha = llt.solve(Y);  // N×n_out
  const double log_det = 2.0 * llt.matrixL().toDenseMatrix().diagonal().array().log().sum();
  const double value = -0.5 * (Y.cwiseProduct(alpha)).sum() - 0.5 * n_out * log_det - 0.5 * n_out * N * kLog2Pi;
  if (gradient != nullptr) {
    // ∂/∂θ = ½ tr(M ∂K/∂θ), M = Σ_o α_o α_oᵀ − n_out K⁻¹.
    Eigen::MatrixXd M = alpha * alpha.transpose() - n_out * llt.solve(Eigen::MatrixXd::Identity(N, N));
    const Eigen::MatrixXd MK = M.cwiseProduct(Kse);
    gradient->resize(n_in + 2);
    for (Eigen::Index d = 0; d < n_in; ++d) {
      // ∂K_ij/∂log ℓ_d = σ_f² K_SE,ij (x_id − x_jd)²/ℓ_d²; Σ_ij MK_ij (a_i − a_j)² with a = Xs(:, d).
      const Eigen::VectorXd a = Xs.col(d);
      const Eigen::VectorXd a2 = a.cwiseAbs2();
      const double s = 2.0 * a2.dot(MK.rowwise().sum()) - 2.0 * a.dot(MK * a);
      (*gradient)(d) = 0.5 * s;
    }
    (*gradient)(n_in) = 0.5 * MK.sum();
    (*gradient)(n_in + 1) = 0.5 * noise_variance * M.trace();
  }
  return value;
}

SsgprParams calc_fitted_params(const Eigen::MatrixXd& X_all, const Eigen::MatrixXd& Y_all, const SsgprParams& start,
                               const SsgprFitConfig& config, SsgprFitReport* report) {
  const int n_in = static_cast<int>(X_all.cols()), n_out = static_cast<int>(Y_all.cols());
  validate_ssgpr_params(start, n_in, n_out);
  if (X_all.rows() != Y_all.rows() || X_all.rows() < 2) throw std::invalid_argument("SSGPR fit: need N >= 2 rows in both X and Y");
  if (!X_all.allFinite() || !Y_all.allFinite()) throw std::invalid_argument("SSGPR fit: the batch holds NaN or Inf");
  if (config.iterations < 0 || !(config.min_step > 0.0 && config.min_step <= config.initial_step &&
                                 config.initial_step <= config.max_step) ||
      !(config.min_noise_fraction > 0.0) || config.max_samples < 2) {
    throw std::invalid_argument("SSGPR fit: invalid fit configuration");
  }
  const Eigen::Index N = std::min<Eigen::Index>(X_all.rows(), static_cast<Eigen::Index>(config.max_samples));
  const Eigen::MatrixXd X = X_all.topRows(N);
  SsgprParams params = start;
  if (config.fit_output_scale) {
    Eigen::VectorXd rms = (Y_all.topRows(N).colwise().squaredNorm() / static_cast<double>(N)).cwiseSqrt().transpose();
    for (Eigen::Index o = 0; o < rms.size(); ++o) {
      if (!(rms(o) > 0.0)) rms(o) = 1.0;
    }
    params.output_scale = rms;
  }
  const Eigen::VectorXd scale = calc_expanded_vector(params.output_scale, n_out);
  const Eigen::MatrixXd Y = Y_all.topRows(N) * scale.cwiseInverse().asDiagonal();

  const int P = n_in + 2;
  Eigen::VectorXd theta(P);
  theta.head(n_in) = calc_expanded_vector(params.lengthscales, n_in).array().log().matrix();
  theta(n_in) = std::log(params.signal_variance);
  theta(n_in + 1) = std::log(params.noise_variance);
  auto evaluate = [&](Eigen::VectorXd& th, Eigen::VectorXd* gradient) {
    th(n_in + 1) = std::max(th(n_in + 1), th(n_in) + std::log(config.min_noise_fraction));
    return calc_gp_log_likelihood(X, Y, th.head(n_in).array().exp().matrix(), std::exp(th(n_in)), std::exp(th(n_in + 1)),
                                  gradient);
  };
  Eigen::VectorXd gradient(P), previous = Eigen::VectorXd::Zero(P), step = Eigen::VectorXd::Constant(P, config.initial_step);
  double value = evaluate(theta, &gradient);
  double best_value = value;
  Eigen::VectorXd best = theta;
  if (report != nullptr) report->log_likelihood_start = value;
  int done = 0;
  for (; done < config.iterations; ++done) {
    for (int i = 0; i < P; ++i) {
      const double product = gradient(i) * previous(i);
      if (product > 0.0) {
        step(i) = std::min(step(i) * 1.2, config.max_step);
      } else if (product < 0.0) {
        step(i) = std::max(step(i) * 0.5, config.min_step);
        gradient(i) = 0.0;  // iRprop−: no move after a sign change
      }
      if (gradient(i) > 0.0) theta(i) += step(i);
      if (gradient(i) < 0.0) theta(i) -= step(i);
    }
    previous = gradient;
    try {
      value = evaluate(theta, &gradient);
    } catch (const std::invalid_argument&) {
      theta = best;  // K lost definiteness: go back and take smaller steps
      step *= 0.5;
      previous.setZero();
      value = evaluate(theta, &gradient);
    }
    if (value > best_value) {
      best_value = value;
      best = theta;
    }
    if (step.maxCoeff() <= config.min_step) break;
  }
  params.lengthscales = best.head(n_in).array().exp().matrix();
  params.signal_variance = std::exp(best(n_in));
  params.noise_variance = std::exp(best(n_in + 1));
  if (report != nullptr) {
    report->log_likelihood_end = best_value;
    report->iterations = done;
  }
  return params;
}

}  // namespace armfarm::ssgpr
