#pragma once
// Incremental sparse-spectrum Gaussian-process regression (I-SSGPR; Gijsberts & Metta, Neural
// Networks 41, 2013), with random Fourier features of a squared-exponential kernel (Rahimi &
// Recht 2007). Bayesian linear regression on the 2D features
//   φ(x) = √(σ_f²/D) [cos(Ωx); sin(Ωx)]      (Ω: D×n_in, row i = z_i ⊘ ℓ, z_i ~ N(0, I))
// with prior w ~ N(0, I) per output and noise σ_n²: A = σ_n² I + ΦᵀΦ (2D×2D, one Cholesky
// factor L shared by all outputs), B = ΦᵀY (2D×n_out), W = A⁻¹B. Each sample costs O(D²).
// Inputs in the caller's units; the model learns y / output_scale internally.
#include "engine/learner/learner.hpp"
#include "engine/ssgpr/ssgpr_params.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <memory>

namespace armfarm::ssgpr {

/// Scratch space of SsgprModel::predict (one per thread).
class SsgprWorkspace final : public PredictionWorkspace {
 public:
  Eigen::VectorXd features;  ///< 2D
  Eigen::VectorXd solved;    ///< 2D, L⁻¹φ
};

/// Per-output detail of a prediction, in the caller's units (sizes n_out), whether or not the
/// output is trusted.
struct SsgprPredictionDetail {
  Eigen::VectorXd mean;                 ///< posterior mean of y
  Eigen::VectorXd latent_variance;      ///< posterior variance of f(x), σ_n² φᵀA⁻¹φ · scale²
  Eigen::VectorXd predictive_variance;  ///< of a new observation, σ_n²(1 + φᵀA⁻¹φ) · scale²
  double variance_fraction = 1.0;       ///< σ_n² φᵀA⁻¹φ / σ_f² (1 before any data)
};

/// The learnt state (for saving and restoring); sizes with F = 2D.
struct SsgprState {
  Eigen::MatrixXd frequencies;  ///< Ω, D×n_in
  Eigen::MatrixXd factor;       ///< L, F×F lower triangular, L Lᵀ = A
  Eigen::MatrixXd rhs;          ///< B = Σ λ^(n−i) φ_i y_iᵀ (y scaled), F×n_out
  Eigen::MatrixXd weights;      ///< W, F×n_out
  std::uint64_t n_updates = 0;
};

class SsgprModel final : public Learner {
 public:
  /// A model without data: frequencies drawn from RandomStream(params.seed, "ssgpr.features")
  /// (row by row), L = σ_n I, B = W = 0. Throws std::invalid_argument for invalid parameters.
  SsgprModel(int n_in, int n_out, const SsgprParams& params);

  /// A model restored from saved state. Throws std::invalid_argument if the sizes do not match,
  /// a value is not finite, or L's diagonal is not positive.
  SsgprModel(int n_in, int n_out, const SsgprParams& params, SsgprState state);

  int input_dim() const override { return n_in_; }
  int output_dim() const override { return n_out_; }

  /// Learns (x, y) (n_in, n_out): with forgetting L ← √λ L, B ← λB; then L ← chol(LLᵀ + φφᵀ),
  /// B += φyᵀ, W += A⁻¹φ (y − Wᵀφ)ᵀ (exact: equals A⁻¹B), re-solved from B every
  /// resolve_interval updates. Throws std::invalid_argument with the model unchanged if a size
  /// is wrong or x, y or φ(x) holds NaN or Inf.
  void update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) override;

  std::unique_ptr<PredictionWorkspace> make_workspace() const override;

  /// Posterior mean with a one-standard-deviation confidence √(σ_n²(1 + φᵀA⁻¹φ))·scale. An
  /// output is trusted when n_updates ≥ trust_min_samples and variance_fraction ≤
  /// trust_variance_fraction (the same for every output, as they share A); untrusted outputs
  /// have value 0 and confidence +∞ (see detail for the numbers). max_activation is
  /// 1 − variance_fraction clamped to [0, 1]. Throws std::invalid_argument for a wrong size, a
  /// non-finite x, or a workspace not made by this class.
  Prediction predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace) const override;
  Prediction predict(const Eigen::VectorXd& x, PredictionWorkspace& workspace, SsgprPredictionDetail& detail) const;

  /// D, the number of random frequencies (the feature vector has 2D entries).
  std::size_t size() const override { return static_cast<std::size_t>(params_.features); }

  /// φ(x) (2D) into `features`; pure. Precondition: x has n_in entries.
  void calc_features(const Eigen::VectorXd& x, Eigen::Ref<Eigen::VectorXd> features) const;

  const SsgprParams& params() const { return params_; }
  const SsgprState& state() const { return state_; }
  std::uint64_t n_updates() const override { return state_.n_updates; }
  /// Bytes of the model's numbers: L, B, W, Ω and the update scratch (Learner::calc_memory_bytes).
  std::size_t calc_memory_bytes() const override;
  ConcreteLearner concrete() const override { return this; }

 private:
  void resolve_weights();

  int n_in_;
  int n_out_;
  SsgprParams params_;
  Eigen::VectorXd output_scale_;  // n_out
  double feature_scale_;          // √(σ_f²/D)
  SsgprState state_;
  // Update scratch (update() is not const; predict() uses the caller's workspace).
  Eigen::VectorXd phi_, rotated_, gain_, y_scaled_, error_;
};

}  // namespace armfarm::ssgpr
