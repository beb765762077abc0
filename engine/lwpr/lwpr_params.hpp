#pragma once
// The learning parameters of an LWPR model (Vijayakumar, D'Souza & Schaal 2005; the parameter
// table of the thesis's appendix E). Names follow the published library so that parameter files
// carry over. Units: inputs and outputs are in the caller's units; all distances, metrics and
// kernels are computed after normalisation (x / norm_in, y / norm_out).
#include <Eigen/Core>

#include <cstddef>

namespace armfarm::lwpr {

/// Shape of a receptive field's activation as a function of q = (x−c)ᵀD(x−c).
enum class Kernel {
  kGaussian,  ///< w = exp(−q/2)
  kBisquare,  ///< w = (1 − q/4)² for q < 4, else 0 (same curvature as the Gaussian at the centre)
};

/// When a field starts its leave-one-out statistics and distance-metric learning.
enum class LooStart {
  kLibrary,  ///< once n_data > 0.1/(1−λ) (100 samples at λ = 0.999), as the published library
  kEarly,    ///< once n_data > min(0.1/(1−λ), 4·(R+1)): D adapts from a few samples (the jobs' default)
};

/// Immutable description of how an LWPR model learns. Plain data with the published library's
/// defaults; checked by validate_lwpr_params() when a model is built.
struct LwprParams {
  /// Initial distance metric of a new field: 1×1 (scalar·I), n_in×1 (diagonal) or n_in×n_in
  /// (full, symmetric positive definite).
  Eigen::MatrixXd init_D = Eigen::MatrixXd::Constant(1, 1, 25.0);
  /// Initial learning rate of the distance-metric gradient descent (every element of M).
  double init_alpha = 50.0;
  /// Penalty factor γ of the regulariser (γ/n_in)·Σ D_ij² in the PRESS cost; larger → wider fields.
  double penalty = 1e-6;
  /// Treat D (and its learning rates and memory terms) as diagonal: O(n) per field instead of O(n²).
  bool diag_only = true;
  /// Adapt D by stochastic gradient descent on the leave-one-out (PRESS) cost plus penalty.
  bool update_D = true;
  /// Second-order (IDBD) adaptation of the learning rates of D, with rate `meta_rate`.
  bool meta = false;
  double meta_rate = 250.0;
  /// A new field is created when no field of an output is activated more than w_gen.
  double w_gen = 0.1;
  /// When two fields are activated more than w_prune, the narrower one (larger trace D) is removed.
  /// The default 1.0 never prunes (activations are ≤ 1), as in the published C library.
  double w_prune = 1.0;
  /// Forgetting factor λ of each field: λ ← tau_lambda·λ + (1 − tau_lambda)·final_lambda per update.
  double init_lambda = 0.999;
  double final_lambda = 0.99999;
  double tau_lambda = 0.9999;
  /// Initial value of each projection's weighted variance Σλwd s² (keeps β finite before data).
  double init_S2 = 1e-10;
  /// Add a projection when the leave-one-out MSE with R projections over that with R−1 is below this.
  double add_threshold = 0.5;
  Kernel kernel = Kernel::kGaussian;
  /// Input and output scale factors: 1 element (all dimensions) or one per dimension; > 0.
  Eigen::VectorXd norm_in = Eigen::VectorXd::Ones(1);
  Eigen::VectorXd norm_out = Eigen::VectorXd::Ones(1);
  /// Blend the predictions of all active fields (true) or take the most active one (false).
  bool blend = true;
  /// Allow projections beyond the initial `init_n_reg` to be added.
  bool add_proj = true;
  /// Number of PLS projections a new field starts with (≥ 1; at most n_in are used).
  int init_n_reg = 2;

  // --- Ours (not in the published library) ---
  /// Most receptive fields per output; 0 = unlimited. At the cap no field is created.
  std::size_t max_fields = 0;
  /// Fields activated at most this much are neither updated (training) nor used (prediction).
  double cutoff = 1e-3;
  /// Samples (counted whatever their activation, discounted by λ: n_data) after which a field may
  /// predict; 0 → 2·n_in (the library's rule).
  double trust_n_data = 0.0;
  /// Start rule of the leave-one-out statistics and metric learning (engine/lwpr/README.md).
  LooStart loo_start = LooStart::kLibrary;
};

/// Throws std::invalid_argument naming the parameter if `params` is unusable for a model with
/// n_in inputs and n_out outputs (wrong sizes, non-finite or out-of-range values, D not SPD).
void validate_lwpr_params(const LwprParams& params, int n_in, int n_out);

/// The initial distance metric as an n_in×n_in matrix (expands a scalar or a diagonal).
/// Precondition: validate_lwpr_params() passed.
Eigen::MatrixXd calc_init_metric(const LwprParams& params, int n_in);

/// A normalisation vector of size `dim` (expands a 1-element vector). Precondition: validated.
Eigen::VectorXd calc_norm_vector(const Eigen::VectorXd& norm, int dim);

}  // namespace armfarm::lwpr
