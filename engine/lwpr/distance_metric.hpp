#pragma once
// Distance-metric adaptation of one receptive field: stochastic gradient descent on
//   J = (1/W) Σ_i Σ_r w_i e_cv,r,i² + (γ/n) Σ_jk D_jk²,
// the weighted leave-one-out (PRESS) errors of the field's R projection regressions (e_cv,r is the
// residual after projection r over 1 − w s_r²/Σλws_r², Vijayakumar et al. 2005) plus a penalty on narrow
// fields, w.r.t. the Cholesky factor M of D = MᵀM (Vijayakumar et al. 2005, section 3.2 and
// appendix; Schaal & Atkeson 1998 for the PRESS memory terms). Optional second-order learning
// rates by Incremental Delta-Bar-Delta (Sutton 1992). Normalised units throughout.
#include "engine/lwpr/lwpr_params.hpp"
#include "engine/lwpr/receptive_field.hpp"

#include <Eigen/Core>

namespace armfarm::lwpr {

/// What one sample contributes to the metric gradient. The PRESS sums (W, E) already include the
/// sample; the memory terms rf.press_H / press_R are still those before it.
struct MetricSample {
  MetricSample(const Eigen::VectorXd& s_, const Eigen::VectorXd& e_, const Eigen::VectorXd& e_cv_)
      : s(s_), e(e_), e_cv(e_cv_) {}
  double w = 0.0;        ///< activation of the sample (with the current metric)
  double q = 0.0;        ///< (x−c)ᵀD(x−c)
  const Eigen::VectorXd& s;     ///< projections s_r of the sample (≥ R elements)
  const Eigen::VectorXd& e;     ///< residual after each projection (after the PLS update) (≥ R)
  const Eigen::VectorXd& e_cv;  ///< its leave-one-out version e_r/(1 − w s_r²/Σλws_r²) (≥ R)
  double W = 0.0;        ///< Σλw including the sample
  double E = 0.0;        ///< Σλw Σ_r e_cv,r² including the sample
  /// M·(x−c) of a full metric (n elements) when the caller already has it (it computed q from
  /// it with calc_factor_product and the same M): the metric step then uses it instead of
  /// multiplying again (the same function, so the same bits). Null: the step computes it.
  const Eigen::VectorXd* md = nullptr;
};

/// exp(x) as the metric steps compute the learning rates α = exp(log α) with meta learning
/// (LwprParams::meta; without it they use the C library's exp): armfarm's own, within 0.7 ulp of
/// the exact value, the same bits in every vector copy and with any libm (glibc's exp differs
/// between its FMA and plain variants, and between versions). 0 below −745.2, +∞ above 709.8,
/// NaN for NaN.
double calc_rate_exp(double x);

/// ∂J1/∂w (the PRESS part of J w.r.t. this sample's activation), from the sample and the field's
/// memory terms (the univariate case of Schaal & Atkeson 1998's derivation, per projection).
double calc_press_dw(const ReceptiveField& rf, const MetricSample& sample);

/// Gradient of J w.r.t. the stored elements of M (shape of rf.metric_factor; only the upper
/// triangle is filled for full metrics): dJ1_dw·∂w/∂M + (w/W)·∂J2/∂M, with diff = x − c.
/// If `curvature` is non-null it also gets the diagonal second derivative estimate used by IDBD.
void calc_metric_gradient(const LwprParams& params, const ReceptiveField& rf, const Eigen::VectorXd& diff,
                          const MetricSample& sample, double dJ1_dw, double d2J1_dw2, Eigen::MatrixXd& grad,
                          Eigen::MatrixXd* curvature, Eigen::VectorXd& md_scratch);

/// One gradient (or IDBD) step on rf.metric_factor, then D = MᵀM. An element whose step would
/// exceed a tenth of max|M| is skipped and its learning rate halved (the library's safeguard); if
/// the new D is not finite the old M and D are kept. `transient` scales the step (≤ 1).
void update_distance_metric(const LwprParams& params, const Eigen::VectorXd& diff, const MetricSample& sample,
                            double transient, ReceptiveField& rf, FieldScratch& scratch);

/// What the fixed-size metric step of a full metric with N = 2 or 3 inputs reads
/// (update_small_full_metric): the MetricSample's terms in arrays (R = rf.n_reg() ≤ N entries of
/// s, e and e_cv, N of diff).
struct SmallMetricSample {
  double w = 0.0;          ///< activation of the sample: calc_kernel() of q = |M(x−c)|² (see below)
  double W = 0.0;          ///< Σλw including the sample
  double E = 0.0;          ///< Σλw Σ_r e_cv,r² including the sample
  double e_cv2 = 0.0;      ///< Σ_r e_cv,r² of the sample, summed in ascending r
  const double* s = nullptr;
  const double* e = nullptr;
  const double* e_cv = nullptr;
  const double* diff = nullptr;  ///< x − c
};

/// update_distance_metric() for a full metric of 2 or 3 inputs (n = rf.input_dim(), R = rf.n_reg())
/// compiled for each n and R: the same operations in the same order as the general step (M·(x−c),
/// dJ1/dw, gradient, curvature, safeguard, IDBD step, D = MᵀM), so the same bits, but for the
/// Gaussian kernel's slopes: they come from sample.w, which must be exp(−q/2) of q = |M(x−c)|² with
/// each row and the sum of squares in ascending order (the activation calc_activation() and the
/// model's scan give; the general step evaluates that exp again). With use_avx2 (only on a CPU
/// that has it, has_avx2()) the copy compiled for AVX2 runs, the same bits. Throws
/// std::invalid_argument for another n.
void update_small_full_metric(const LwprParams& params, const SmallMetricSample& sample, double transient,
                              ReceptiveField& rf, bool use_avx2);

/// What update_receptive_field() does for the metric of a full metric of 2 or 3 inputs after the
/// leave-one-out sums (update_D, the start rule passed): the sample's leave-one-out residuals from
/// scratch (s, residual, one_minus_h), sum_e2, press_E, the transient multiplier, the step of
/// update_small_full_metric() and the PRESS memory terms; the same bits as the general code, w the
/// field's activation as there. The AVX2 copy runs if scratch.use_avx2.
void update_small_full_field_metric(const LwprParams& params, const Eigen::VectorXd& x, double w,
                                    const FieldScratch& scratch, ReceptiveField& rf);

/// The most fields update_small_full_field_metrics() takes at once: the lanes of one AVX2 vector.
constexpr int kMetricLanes = 4;

/// update_small_full_field_metric() for `count` (1..kMetricLanes) different fields of the same n (2
/// or 3) and R and the same x, field k with activation w[k] and its own scratch[k] (its s,
/// residuals and 1 − h after the statistics): when every scratch says use_avx2 (only on a CPU that
/// has it), in the lanes of one vector, field k in lane k; else one by one. Each field ends with
/// the same bits as alone. Throws std::invalid_argument for another count, n or mixed n or R.
void update_small_full_field_metrics(const LwprParams& params, const Eigen::VectorXd& x, int count, const double* w,
                                     const FieldScratch* const* scratch, ReceptiveField* const* rf);

/// md = M·diff for an upper triangular n×n factor M (n): the full metric's part of q = |M·diff|².
void calc_factor_product(const Eigen::MatrixXd& M, const Eigen::VectorXd& diff, Eigen::VectorXd& md);

/// D = MᵀM for the field's storage layout (full or diagonal).
void calc_metric_from_factor(const Eigen::MatrixXd& M, Eigen::MatrixXd& D);

}  // namespace armfarm::lwpr
