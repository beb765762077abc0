#pragma once
// Hyperparameters of SSGPR fitted on an initial batch by maximising the exact (full) GP log
// marginal likelihood of the squared-exponential kernel, summed over outputs that share the
// hyperparameters:
//   log p(Y) = Σ_o [−½ y_oᵀK⁻¹y_o − ½ log|K| − (N/2) log 2π],  K = σ_f² K_SE(ℓ) + σ_n² I (N×N).
// The full GP, not the feature model, is fitted: its likelihood does not depend on the random
// frequencies, so the fitted values hold for every D and seed (Gijsberts & Metta fit theirs on
// a batch in the same way). Optimiser: iRprop− (Igel & Hüsken 2000) on θ = (log ℓ_1..n_in,
// log σ_f², log σ_n²): it uses only the signs of the gradient with one adaptive step per
// parameter, so the very different gradient scales of lengthscales and variances need no line
// search or tuning, and it is deterministic; the best θ seen is returned. Cost O(N³) per step.
#include "engine/ssgpr/ssgpr_params.hpp"

#include <Eigen/Core>

#include <cstddef>

namespace armfarm::ssgpr {

/// How the hyperparameters are fitted.
struct SsgprFitConfig {
  /// iRprop− steps (each one log-likelihood and gradient evaluation).
  int iterations = 80;
  /// The first this many rows of the batch are used (O(N³) per step).
  std::size_t max_samples = 400;
  /// Set output_scale to each output's root mean square on the batch before fitting (σ_f² and
  /// σ_n² are then in units of that scale).
  bool fit_output_scale = true;
  /// Initial step of every log-parameter, and its bounds.
  double initial_step = 0.1;
  double min_step = 1e-6;
  double max_step = 1.0;
  /// σ_n² is kept at least this fraction of σ_f² (conditioning of K).
  double min_noise_fraction = 1e-6;
};

/// What a fit did.
struct SsgprFitReport {
  double log_likelihood_start = 0.0;
  double log_likelihood_end = 0.0;
  int iterations = 0;
};

/// The GP log marginal likelihood of Y (N×n_out, in output_scale units) at X (N×n_in) and, if
/// `gradient` is not null, its gradient (n_in + 2) w.r.t. (log ℓ, log σ_f², log σ_n²).
/// Throws std::invalid_argument if K is not positive definite or the sizes disagree.
double calc_gp_log_likelihood(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, const Eigen::VectorXd& lengthscales,
                              double signal_variance, double noise_variance, Eigen::VectorXd* gradient);

/// `start` with lengthscales (n_in), signal_variance, noise_variance (and, if configured,
/// output_scale) fitted to the batch (X: N×n_in, Y: N×n_out, finite, N ≥ 2), starting from
/// start's values. Throws std::invalid_argument for bad sizes or values.
SsgprParams calc_fitted_params(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y, const SsgprParams& start,
                               const SsgprFitConfig& config, SsgprFitReport* report = nullptr);

}  // namespace armfarm::ssgpr
