// Distance-metric gradient (PRESS + penalty) and its gradient / IDBD step.
#include "engine/lwpr/distance_metric.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace armfarm::lwpr {

double calc_press_dw(const ReceptiveField& rf, const MetricSample& sample) {
  // J1 sums the leave-one-out errors of the R univariate regressions. Per projection r, with
  // P_r = 1/Σλws_r²: ∂J1/∂w ≈ −E/W² + (1/W)·Σ_r (e_cv,r² − 2 e_r P_r s_r H_r − 2 P_r² s_r² R_r),
  // where the H and R terms carry the effect of w on β_r and P_r for the samples already seen.
  double sum = 0.0;
  for (int r = 0; r < rf.n_reg(); ++r) {
    const double ps = sample.s(r) / rf.ss2(r);
    const double e_cv = sample.e_cv(r);
    sum += e_cv * e_cv - 2.0 * sample.e(r) * ps * rf.press_H(r) - 2.0 * ps * ps * rf.press_R(r);
  }
  return -sample.E / (sample.W * sample.W) + sum / sample.W;
}

void calc_metric_gradient(const LwprParams& params, const ReceptiveField& rf, const Eigen::VectorXd& diff,
                          const MetricSample& sample, double dJ1_dw, double d2J1_dw2, Eigen::MatrixXd& grad,
                          Eigen::MatrixXd* curvature, Eigen::VectorXd& md) {
  const int n = rf.input_dim();
  const Eigen::MatrixXd& M = rf.metric_factor;
  const Eigen::MatrixXd& D = rf.metric;
  const double dw_dq = calc_kernel_dq(params.kernel, sample.q);
  const double d2w_dq2 = calc_kernel_dq2(params.kernel, sample.q);
  const double penalty = params.penalty / n;  // γ/n
  const double penalty_weight = sample.w / sample.W;
  grad.resize(M.rows(), M.cols());
  if (curvature != nullptr) curvature->resize(M.rows(), M.cols());

  auto accumulate = [&](int row, int col, double dq, double d2q, double dJ2, double d2J2) {
    const double dw = dw_dq * dq;
    grad(row, col) = dJ1_dw * dw + penalty_weight * dJ2;
    if (curvature != nullptr) {
      const double d2w = d2w_dq2 * dq * dq + dw_dq * d2q;
      (*curvature)(row, col) = d2J1_dw2 * dw * dw + dJ1_dw * d2w + penalty_weight * d2J2;
    }
  };

  if (rf.diagonal()) {
    // q = Σ_i M_i² d_i²;  J2 = (γ/n)·Σ_i M_i⁴.
    for (int i = 0; i < n; ++i) {
      const double m = M(i, 0);
      const double d2 = diff(i) * diff(i);
      accumulate(i, 0, 2.0 * m * d2, 2.0 * d2, 4.0 * penalty * m * m * m, 12.0 * penalty * m * m);
    }
    return;
  }
  // q = |M d|²: ∂q/∂M_rl = 2(Md)_r d_l;  J2 = (γ/n)·tr(D²): ∂J2/∂M = 4(γ/n)·M D.
  md.noalias() = M.triangularView<Eigen::Upper>() * diff;
  for (int l = 0; l < n; ++l) {
    for (int r = 0; r <= l; ++r) {
      const double dJ2 = 4.0 * penalty * M.row(r).dot(D.col(l));
      const double d2J2 = 4.0 * penalty * (M(r, l) * M(r, l) + M.row(r).squaredNorm() + D(l, l));
      accumulate(r, l, 2.0 * md(r) * diff(l), 2.0 * diff(l) * diff(l), dJ2, d2J2);
    }
    for (int r = l + 1; r < n; ++r) {
      grad(r, l) = 0.0;
      if (curvature != nullptr) (*curvature)(r, l) = 0.0;
    }
  }
}

void calc_metric_from_factor(const Eigen::MatrixXd& M, Eigen::MatrixXd& D) {
  if (M.cols() == 1) {
    D = M.array().square().matrix();
    return;
  }
  D.noalias() = M.transpose() * M;
}

namespace {

// The diagonal metric without meta learning, the common case: the same gradient and step as the
// general path below (same expressions, same order, so the same bits), in two passes over the n
// elements instead of eight: (1) the gradient and max|M|, (2) step, safeguard and D = M².
void update_diagonal_metric(const LwprParams& params, const Eigen::VectorXd& diff, const MetricSample& sample,
                            double dJ1_dw, double transient, ReceptiveField& rf, FieldScratch& scratch) {
  const int n = rf.input_dim();
  const double dw_dq = calc_kernel_dq(params.kernel, sample.q);
  const double penalty = params.penalty / n;
  const double penalty_weight = sample.w / sample.W;
  double* M = rf.metric_factor.data();
  double* grad = scratch.grad.data();
  const double* d = diff.data();
  double max_abs = 0.0;
  bool finite = true;
  for (int i = 0; i < n; ++i) {
    const double m = M[i];
    const double d2 = d[i] * d[i];
    const double g = dJ1_dw * (dw_dq * (2.0 * m * d2)) + penalty_weight * (4.0 * penalty * m * m * m);
    grad[i] = g;
    finite = finite && std::isfinite(g);
    max_abs = std::max(max_abs, std::abs(m));
  }
  if (!finite) return;  // a degenerate sample: keep the metric as it is
  const double bound = 0.1 * max_abs;
  const double log_half = std::log(0.5);
  double* log_alpha = rf.log_alpha.data();
  double* old = scratch.old_factor.data();
  double* D_new = scratch.new_metric.data();
  double last_log_alpha = std::numeric_limits<double>::quiet_NaN();
  double last_alpha = 0.0;
  for (int i = 0; i < n; ++i) {
    if (!(log_alpha[i] == last_log_alpha)) {
      last_log_alpha = log_alpha[i];
      last_alpha = std::exp(log_alpha[i]);
    }
    const double step = last_alpha * transient * grad[i];
    old[i] = M[i];
    if (std::abs(step) > bound) {
      log_alpha[i] += log_half;  // too large a step: halve the rate, skip this element
    } else {
      M[i] -= step;
    }
    D_new[i] = M[i] * M[i];
    finite = finite && std::isfinite(D_new[i]);
  }
  if (!finite) {
    std::copy(old, old + n, M);  // never leave a field with a NaN metric
    return;
  }
  std::copy(D_new, D_new + n, rf.metric.data());
}

}  // namespace

void update_distance_metric(const LwprParams& params, const Eigen::VectorXd& diff, const MetricSample& sample,
                            double transient, ReceptiveField& rf, FieldScratch& scratch) {
  const double dJ1_dw = calc_press_dw(rf, sample);
  if (rf.diagonal() && !params.meta) {
    update_diagonal_metric(params, diff, sample, dJ1_dw, transient, rf, scratch);
    return;
  }
  const double d2J1_dw2 = 2.0 * sample.e_cv.head(rf.n_reg()).squaredNorm() / (sample.W * sample.W);
  calc_metric_gradient(params, rf, diff, sample, dJ1_dw, d2J1_dw2, scratch.grad,
                       params.meta ? &scratch.curvature : nullptr, scratch.md);
  if (!scratch.grad.allFinite()) return;  // a degenerate sample: keep the metric as it is

  Eigen::MatrixXd& M = rf.metric_factor;
  scratch.old_factor = M;
  const double bound = 0.1 * M.cwiseAbs().maxCoeff();
  const bool full = !rf.diagonal();
  const double log_half = std::log(0.5);
  // Without meta learning the rates only change when a step is too large, so neighbouring elements
  // nearly always share one log-rate: exp() is evaluated only when the log-rate differs from the
  // previous element's (the same value, bit for bit, as evaluating it every time).
  double last_log_alpha = std::numeric_limits<double>::quiet_NaN();
  double last_alpha = 0.0;
  for (Eigen::Index col = 0; col < M.cols(); ++col) {
    const Eigen::Index last_row = full ? col : M.rows() - 1;
    for (Eigen::Index row = 0; row <= last_row; ++row) {
      const double g = scratch.grad(row, col);
      double& log_alpha = rf.log_alpha(row, col);
      if (params.meta) {
        const double change = std::clamp(-params.meta_rate * g * rf.meta_trace(row, col), -0.1, 0.1);
        log_alpha = std::clamp(log_alpha + change, -10.0, 10.0);
      }
      if (!(log_alpha == last_log_alpha)) {
        last_log_alpha = log_alpha;
        last_alpha = std::exp(log_alpha);
      }
      const double alpha = last_alpha;
      const double step = alpha * transient * g;
      double applied = 0.0;
      if (std::abs(step) > bound) {
        log_alpha += log_half;  // too large a step: halve the rate, skip this element
      } else {
        M(row, col) -= step;
        applied = -step;
      }
      if (params.meta) {
        const double decay = std::max(0.0, 1.0 - alpha * scratch.curvature(row, col));
        rf.meta_trace(row, col) = rf.meta_trace(row, col) * decay + applied;
      }
    }
  }
  calc_metric_from_factor(M, scratch.new_metric);
  if (!scratch.new_metric.allFinite() || !M.allFinite()) {
    M = scratch.old_factor;  // never leave a field with a NaN metric
    return;
  }
  rf.metric.swap(scratch.new_metric);
}

}  // namespace armfarm::lwpr
