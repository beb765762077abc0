#pragma once
// One receptive field of LWPR: a Gaussian (or bisquare) kernel around a centre c with distance
// metric D = MᵀM, and a local linear model y ≈ β₀ + Σ_r β_r s_r fitted by incremental weighted
// partial least squares (PLS) on forgetting-weighted sufficient statistics (Vijayakumar et al.
// 2005, section 3 and table 2). All vectors here are in normalised units (x / norm_in, y / norm_out).
#include "engine/lwpr/lwpr_params.hpp"

#include <Eigen/Core>

namespace armfarm::lwpr {

/// The state of one receptive field. n = input dimension, R = number of PLS projections.
/// Diagonal metrics (LwprParams::diag_only) keep M, D, log_alpha and meta_trace as n×1 columns
/// (the diagonal); full metrics keep them n×n with M upper triangular.
struct ReceptiveField {
  Eigen::VectorXd center;      ///< c (n)
  Eigen::MatrixXd metric_factor;  ///< M, D = MᵀM (n×n upper triangular, or n×1 diagonal)
  Eigen::MatrixXd metric;      ///< D (n×n, or n×1 diagonal)
  Eigen::MatrixXd log_alpha;   ///< log of the per-element learning rates of M (shape of M)
  Eigen::MatrixXd meta_trace;  ///< IDBD memory trace of M's updates (shape of M)

  double lambda = 0.999;       ///< forgetting factor, annealed towards final_lambda
  Eigen::VectorXd mean_x;      ///< weighted mean x₀ of the inputs seen (n)
  double beta0 = 0.0;          ///< weighted mean of the outputs seen: the local model's offset
  Eigen::VectorXd sum_w;       ///< Σλw per projection (R)
  Eigen::VectorXd n_data;      ///< Σλ·1 per projection: samples seen, forgetting-discounted; 0 for an added projection (R)

  Eigen::MatrixXd sxy;         ///< Σλw z res, per projection: the PLS direction u_r before normalising (n×R)
  Eigen::MatrixXd sxs;         ///< Σλw z s, per projection: the input loadings p_r·Σws² (n×R)
  Eigen::VectorXd ss2;         ///< Σλw s² per projection (R)
  Eigen::VectorXd sys;         ///< Σλw s res per projection: β_r·Σws² (R)

  Eigen::VectorXd sum_e_cv2;   ///< Σλw e_cv² with r+1 projections (leave-one-out error) (R)
  double sum_e2 = 0.0;         ///< Σλw e² of the full model (fitted, not cross-validated)
  double press_E = 0.0;        ///< Σλw Σ_r e_cv,r² (per-projection leave-one-out), for the metric gradient
  Eigen::VectorXd press_H;     ///< PRESS memory Σλ w s_r e_cv/(1−h) (R)
  Eigen::VectorXd press_R;     ///< PRESS memory Σλ w² s_r² e_cv²/(1−h) (R)

  bool trustworthy = false;    ///< has seen enough samples (n_data ≥ trust threshold) to predict

  // Derived from the statistics above by refresh_receptive_field() (cached for prediction):
  Eigen::MatrixXd directions;  ///< u_r = sxy_r/|sxy_r|, zero while sxy_r = 0 (n×R)
  Eigen::MatrixXd loadings;    ///< p_r = sxs_r/ss2_r (n×R)
  Eigen::VectorXd beta;        ///< β_r = sys_r/ss2_r (R)

  int input_dim() const { return static_cast<int>(center.size()); }
  int n_reg() const { return static_cast<int>(ss2.size()); }
  bool diagonal() const { return metric.cols() == 1; }
};

/// Initial Σw of a new projection and n_data of a new field's projections, so that divisions stay finite.
constexpr double kTinyWeight = 1e-10;
/// Floor of 1 − leverage in the leave-one-out residuals.
constexpr double kMinOneMinusH = 1e-3;

/// Whether this CPU runs AVX2 (checked once).
bool has_avx2();
/// Whether this CPU runs AVX-512 F, VL and DQ (checked once).
bool has_avx512();

/// Scratch space for one field update or prediction (sized once, reused; no allocation per call).
struct FieldScratch {
  Eigen::VectorXd z;        ///< input residual (n)
  Eigen::VectorXd diff;     ///< x − c (n)
  Eigen::VectorXd md;       ///< M(x − c) (n)
  Eigen::VectorXd s;        ///< projections (n: capacity for R ≤ n)
  Eigen::VectorXd residual; ///< output residual after each projection (n)
  Eigen::VectorXd e_cv;     ///< leave-one-out residual of each projection's regression (n)
  Eigen::VectorXd one_minus_h; ///< 1 − w s_r²/Σλws_r² per projection (n)
  Eigen::MatrixXd grad;     ///< gradient of the cost w.r.t. M (shape of M)
  Eigen::MatrixXd curvature;///< its second derivative (shape of M), for IDBD
  Eigen::MatrixXd old_factor;  ///< M before a metric step, to restore it
  Eigen::MatrixXd new_metric;  ///< D after a metric step, before it is accepted
  /// The statistics of a field of 2 or 3 inputs on local values (update_small_field_statistics).
  /// They give the same bits as the general code, which tests run by clearing this.
  bool small_statistics = true;
  /// Field updates of more than 3 inputs on AVX2 (the same bits as SSE2; has_avx2() by default,
  /// tests compare the two).
  bool use_avx2 = has_avx2();
  /// With use_avx2, the field update of 21 inputs on AVX-512 (the same bits; has_avx512() by
  /// default, tests compare it with AVX2 and SSE2).
  bool use_avx512 = has_avx512();
  /// The metric step of a full metric with 2 or 3 inputs, with its leave-one-out glue, on
  /// fixed-size arrays (update_small_full_field_metric). It gives the same bits as the general
  /// code, which tests run by clearing this.
  bool small_full_metric = true;
  void resize(int n, bool diagonal);
};

/// Makes a field centred at x (normalised) with metric D (n×n; its diagonal if diag_only) and
/// `params.init_n_reg` empty projections. It has seen no data yet.
ReceptiveField make_receptive_field(const LwprParams& params, const Eigen::VectorXd& x,
                                    const Eigen::MatrixXd& D);

/// Kernel activation w(q) and its derivatives w.r.t. q = (x−c)ᵀD(x−c).
double calc_kernel(Kernel kernel, double q);
double calc_kernel_dq(Kernel kernel, double q);
double calc_kernel_dq2(Kernel kernel, double q);

/// dw/dq and d²w/dq² at q together (one exp for the Gaussian): the same values as
/// calc_kernel_dq() and calc_kernel_dq2().
struct KernelSlopes {
  double dw_dq = 0.0;
  double d2w_dq2 = 0.0;
};
KernelSlopes calc_kernel_slopes(Kernel kernel, double q);

/// Smallest q at which the activation is at most `cutoff` (+∞ when cutoff = 0): the distance
/// scan stops a field's sum there. Depends only on the parameters; compute it once per model.
double calc_q_limit(Kernel kernel, double cutoff);

/// The field's activation at x (normalised). O(n) for diagonal metrics, O(n²) for full ones.
/// Returns 0 without finishing the sum once q is past the point where w ≤ `cutoff`.
double calc_activation(const ReceptiveField& rf, Kernel kernel, const Eigen::VectorXd& x, double cutoff,
                       FieldScratch& scratch);

/// calc_activation() with the cutoff given as q_limit = calc_q_limit(kernel, cutoff).
double calc_activation_within(const ReceptiveField& rf, Kernel kernel, const Eigen::VectorXd& x, double q_limit,
                              FieldScratch& scratch);

/// The local model's prediction at x (normalised). Also returns in `leverage` Σ_r s_r²/Σλws_r²,
/// the field's uncertainty about its own fit at x.
double predict_receptive_field(const ReceptiveField& rf, const Eigen::VectorXd& x, double& leverage,
                               FieldScratch& scratch);

/// predict_receptive_field() without the leverage: the same prediction, bit for bit.
double predict_receptive_field_value(const ReceptiveField& rf, const Eigen::VectorXd& x, FieldScratch& scratch);

/// The field's leave-one-out estimate of the output noise variance (normalised units²).
double calc_field_noise_variance(const ReceptiveField& rf);

/// Learns one sample (x, y) (normalised) seen with activation w > 0. w must be computed with the
/// current metric, as calc_kernel() of q = (x−c)ᵀD(x−c); for a full metric q = |M(x−c)|², each
/// row of M(x−c) and the sum of squares in ascending order, as calc_activation() and the model's
/// scan compute it. A full metric's step of 2 or 3 inputs with the Gaussian kernel takes w itself
/// as exp(−q/2), which gives the same bits. Updates the means, the PLS projections and
/// regressions, the leave-one-out error statistics, the distance metric (if params.update_D),
/// adds a projection when the add_threshold rule says so, and anneals λ. n_data counts samples
/// (forgetting-discounted, Σλ·1), whatever their activation; sum_w sums activations.
/// `trust_n_data` is the sample count after which the field predicts.
void update_receptive_field(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x,
                            double y, double w, ReceptiveField& rf, FieldScratch& scratch);

/// update_receptive_field() for two different fields and the same sample (x, y), with their own
/// activations and scratch: the two fields' PLS statistics run projection by projection in turn,
/// so that one field's chain through √ and the divisions overlaps the other's passes. Each field
/// ends with the same bits as update_receptive_field() gives it.
void update_receptive_field_pair(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, double y,
                                 double w_a, ReceptiveField& rf_a, FieldScratch& scratch_a, double w_b,
                                 ReceptiveField& rf_b, FieldScratch& scratch_b);

/// The most fields update_receptive_fields() takes at once (the metric step's vector lanes).
constexpr int kFieldGroup = 4;

/// update_receptive_field() for `count` (1..kFieldGroup) different fields and the same sample
/// (x, y), field k with activation w[k] and its own scratch[k]: the statistics two at a time (as
/// update_receptive_field_pair), then the metric steps of the fields with a full metric of 2 or 3
/// inputs and the same R together, in vector lanes (update_small_full_field_metrics()). Each field
/// ends with the same bits as update_receptive_field() gives it. Throws std::invalid_argument for
/// another count.
void update_receptive_fields(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, double y,
                             int count, const double* w, ReceptiveField* const* rf, FieldScratch* const* scratch);

/// Recomputes the cached directions, loadings and β from the sufficient statistics.
void refresh_receptive_field(ReceptiveField& rf);

/// Appends an empty projection to the field (R → R+1). Precondition: R < n.
void add_projection(const LwprParams& params, ReceptiveField& rf);

}  // namespace armfarm::lwpr
