#pragma once
// The parameters of an SSGPR model (Gijsberts & Metta 2013): the number of random Fourier
// features, the squared-exponential kernel's hyperparameters, forgetting and the trust rule.
// Units: lengthscales in the caller's input units; variances in units of (y / output_scale)².
#include <Eigen/Core>

#include <cstdint>

namespace armfarm::ssgpr {

/// Immutable description of an SSGPR model; checked by validate_ssgpr_params().
struct SsgprParams {
  /// D, the number of random frequencies; the feature vector [cos(Ωx); sin(Ωx)] has 2D entries.
  int features = 200;
  /// Per-input lengthscales ℓ of k(x, x') = σ_f² exp(−½ Σ_d (x_d − x'_d)²/ℓ_d²): 1 element (all
  /// inputs) or n_in; > 0.
  Eigen::VectorXd lengthscales = Eigen::VectorXd::Ones(1);
  /// σ_f², the kernel's (prior latent) variance, in (y / output_scale)² units; > 0.
  double signal_variance = 1.0;
  /// σ_n², the observation noise variance, in (y / output_scale)² units; > 0 (it also
  /// regularises the Gram matrix A = ΦᵀΦ + σ_n² I).
  double noise_variance = 0.01;
  /// The model learns y / output_scale (1 element or n_out; > 0); predictions are scaled back.
  Eigen::VectorXd output_scale = Eigen::VectorXd::Ones(1);
  /// λ in (0, 1]: each update first multiplies A and Φᵀy by λ (exponentially weighted least
  /// squares); 1 = no forgetting. The prior σ_n² I decays with the data (λⁿσ_n² I after n samples).
  double forgetting = 1.0;
  /// Seed of the frequency draws (RandomStream(seed, "ssgpr.features")).
  std::uint64_t seed = 1;
  /// An output is trusted at x once the model has learnt at least this many samples ...
  std::uint64_t trust_min_samples = 20;
  /// ... and the posterior latent variance at x is at most this fraction of the prior σ_f²
  /// (in [0, 1]; 1 = the sample count alone decides).
  double trust_variance_fraction = 0.5;
  /// Every this many updates the weights are re-solved from A and Φᵀy (removes the rounding
  /// drift of the per-sample gain update); 0 = never.
  std::uint64_t resolve_interval = 1000;
};

/// Throws std::invalid_argument naming the parameter if `params` is unusable for n_in inputs and
/// n_out outputs (sizes, non-finite or out-of-range values).
void validate_ssgpr_params(const SsgprParams& params, int n_in, int n_out);

/// A vector of size `dim` from a 1-element or `dim`-element one. Precondition: validated.
Eigen::VectorXd calc_expanded_vector(const Eigen::VectorXd& v, int dim);

}  // namespace armfarm::ssgpr
