// Distance-metric gradient (PRESS + penalty) and its gradient / IDBD step.
#include "engine/lwpr/distance_metric.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace armfarm::lwpr {
namespace {

// The full-metric helpers below work on a value type T: double (one field) or Quad, four fields
// at once, field l in vector lane l (a GCC/Clang vector extension; only the AVX2 copies use it).
// Element-wise arithmetic, comparisons and selects on Quad round and decide exactly as the scalar
// code in each lane, so every field gets the bits it gets alone.
// These helpers, and those below that take or return T, are always inlined into one copy compiled
// for one target, so a Quad never crosses a call: GCC's note that passing one by value without
// AVX changes the ABI (-Wpsabi) does not apply, and is silenced for this file.
#pragma GCC diagnostic ignored "-Wpsabi"
typedef double Quad __attribute__((vector_size(4 * sizeof(double))));
typedef long long QuadBits __attribute__((vector_size(4 * sizeof(long long))));
template <class T>
constexpr int kLaneCount = static_cast<int>(sizeof(T) / sizeof(double));

// v in every lane.
template <class T>
__attribute__((always_inline)) inline T splat(double v) {
  if constexpr (std::is_same_v<T, double>) {
    return v;
  } else {
    T out;
    for (int l = 0; l < kLaneCount<T>; ++l) out[l] = v;
    return out;
  }
}
// Lane l's value.
template <class T>
__attribute__((always_inline)) inline double lane(const T& v, int l) {
  if constexpr (std::is_same_v<T, double>) {
    return v;
  } else {
    return v[l];
  }
}
// Whether lane l of a comparison's result is true (a bool, or a vector of all-ones / zero lanes).
template <class M>
__attribute__((always_inline)) inline bool lane_true(const M& m, int l) {
  if constexpr (std::is_same_v<M, bool>) {
    return m;
  } else {
    return m[l] != 0;
  }
}
// std::max(a, b), std::min(a, b), std::clamp(v, lo, hi) and std::abs lane by lane: the same
// comparisons and selects (libstdc++'s), so the same value in every lane, NaNs included.
template <class T>
__attribute__((always_inline)) inline T max_of(const T& a, const T& b) {
  return a < b ? b : a;
}
template <class T>
__attribute__((always_inline)) inline T min_of(const T& a, const T& b) {
  return b < a ? b : a;
}
template <class T>
__attribute__((always_inline)) inline T clamp_of(const T& v, double lo, double hi) {
  const T low = splat<T>(lo), high = splat<T>(hi);
  return v < low ? low : (high < v ? high : v);
}
template <class T>
__attribute__((always_inline)) inline T abs_of(const T& v) {
  if constexpr (std::is_same_v<T, double>) {
    return std::abs(v);
  } else {
    static_assert(std::is_same_v<T, Quad>, "lanes: double or Quad");
    QuadBits magnitude;
    for (int l = 0; l < kLaneCount<T>; ++l) magnitude[l] = 0x7fffffffffffffffLL;
    return (T)((QuadBits)v & magnitude);  // a cast between vectors of one size keeps the bits: |v| as fabs
  }
}

// exp(x) for the metrics' learning rates α = exp(log α) (calc_rate_exp()), on T = double or Quad:
// the same operations in every lane, so the same bits alone or in a vector, and with any libm.
// x = k·ln 2 + r with k = round(x/ln 2) and |r| ≤ ln 2/2 (Cody–Waite: ln 2 split so that k·ln2_hi
// is exact, its rounding error carried); exp(r) by its Taylor series to r¹³ (the next term is below
// 10⁻¹⁷), evaluated in Estrin's scheme for a short dependency chain, 1 + r added exactly; then 2^k
// as two exact power-of-two factors, so that results near overflow and in the subnormal range
// round once. x is clamped to [−746, 710] first (past them exp is 0 or +∞ in double; a NaN passes
// through).
constexpr double kRound = 6755399441055744.0;  // 1.5·2⁵²: t + kRound − kRound rounds t to an integer
constexpr double kInvLn2 = 1.4426950408889634074;
constexpr double kLn2Hi = 6.93147180369123816490e-01;  // ln 2's leading 32 bits: k·kLn2Hi is exact for |k| < 2²¹
constexpr double kLn2Lo = 1.90821492927058770002e-10;  // ln 2 − kLn2Hi

// 2^k for an integer-valued k in [−1022, 1023]: the exponent field built from k's bits.
template <class T>
__attribute__((always_inline)) inline T calc_power_of_two(const T& k) {
  const T shifted = k + kRound;  // k's two's complement in the low bits of the significand
  if constexpr (std::is_same_v<T, double>) {
    long long bits, base;
    std::memcpy(&bits, &shifted, sizeof bits);
    const double round = kRound;
    std::memcpy(&base, &round, sizeof base);
    const unsigned long long exponent = static_cast<unsigned long long>(bits - base + 1023) << 52;
    double out;
    std::memcpy(&out, &exponent, sizeof out);
    return out;
  } else {
    const QuadBits base = (QuadBits)splat<T>(kRound);
    const QuadBits exponent = ((QuadBits)shifted - base + 1023) << 52;
    return (T)exponent;
  }
}

template <class T>
__attribute__((always_inline)) inline T calc_rate_exp_of(const T& x_in) {
  const T x = clamp_of(x_in, -746.0, 710.0);
  const T k = (x * kInvLn2 + kRound) - kRound;
  const T a = x - k * kLn2Hi;  // exact
  const T b = k * kLn2Lo;
  const T r = a - b;
  const T r_error = (a - r) - b;  // what r = a − b rounded off (Fast2Sum: |a| ≥ |b|)
  // 1/j! for j = 2..13.
  constexpr double c2 = 1.0 / 2, c3 = 1.0 / 6, c4 = 1.0 / 24, c5 = 1.0 / 120, c6 = 1.0 / 720, c7 = 1.0 / 5040,
                   c8 = 1.0 / 40320, c9 = 1.0 / 362880, c10 = 1.0 / 3628800, c11 = 1.0 / 39916800,
                   c12 = 1.0 / 479001600, c13 = 1.0 / 6227020800;
  const T r2 = r * r;
  const T r4 = r2 * r2;
  const T q0 = (c2 + c3 * r) + r2 * (c4 + c5 * r);
  const T q1 = (c6 + c7 * r) + r2 * (c8 + c9 * r);
  const T q2 = (c10 + c11 * r) + r2 * (c12 + c13 * r);
  const T q = q0 + r4 * (q1 + r4 * q2);  // Σ_{j≥2} r^(j−2)/j!
  // 1 + r + r²q with 1 + r split exactly into hi + lo (Fast2Sum: |r| < 1), so that only the last
  // addition rounds at 1's scale.
  const T hi = 1.0 + r;
  const T lo = (1.0 - hi) + r;
  const T p = hi + ((lo + r_error * hi) + r2 * q);  // exp(r + r_error) ≈ exp(r)·(1 + r_error)
  const T k1 = (k * 0.5 + kRound) - kRound;  // k = k1 + k2, both within 2^k's normal range
  return (p * calc_power_of_two(k1)) * calc_power_of_two(k - k1);
}

// A learning rate α = exp(log α): with meta learning (log α moves at every step) calc_rate_exp(),
// which runs in vector lanes; without it the C library's exp, as before calc_rate_exp() existed,
// so that fields without meta learning keep their numbers (their log-rates rarely change, so the
// exp is rarely evaluated).
__attribute__((always_inline)) inline double calc_rate(bool meta, double log_alpha) {
  return meta ? calc_rate_exp_of(log_alpha) : std::exp(log_alpha);
}

// The full-metric loops below reproduce the evaluation order of the Eigen expressions they
// replaced, so the results are the same bits: Eigen's triangular matrix-vector product handles a
// factor of up to 8 columns as one panel, summing each row in ascending column order, and its
// MᵀM of up to 3 columns sums each coefficient in ascending order (from 4 columns on it sums in
// SIMD-width-dependent order, so those sizes call Eigen itself, as before).
constexpr int kTrmvPanel = 8;
constexpr int kOrderedProductMax = 3;

// Full metrics: the helpers take N > 0 for an input dimension known at compile time (the loops
// unroll: the cross benchmark's 2-D fields spend most of a dynamic loop's time in its control) or
// N = 0 for n at run time; the same operations in the same order either way.
template <int N>
inline int dim(int n) {
  return N > 0 ? N : n;
}

// md = M·d for an upper triangular M (n×n, column-major), n ≤ kTrmvPanel.
template <int N, class T>
__attribute__((always_inline)) inline void multiply_factor(const T* m, const T* d, int n_runtime, T* md) {
  const int n = dim<N>(n_runtime);
  for (int r = 0; r < n; ++r) {
    T v = splat<T>(0.0);
    for (int k = r; k < n; ++k) v += m[r + k * n] * d[k];
    md[r] = v;
  }
}

// D = MᵀM (n×n, column-major) for n ≤ kOrderedProductMax: the upper triangle summed in ascending
// order and mirrored (M_iᵀM_j and M_jᵀM_i are the same products in the same order).
template <int N, class T>
__attribute__((always_inline)) inline void multiply_factor_transposed(const T* m, int n_runtime, T* D) {
  const int n = dim<N>(n_runtime);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i <= j; ++i) {
      T v = m[i * n] * m[j * n];
      for (int k = 1; k < n; ++k) v += m[k + i * n] * m[k + j * n];
      D[i + j * n] = v;
      D[j + i * n] = v;
    }
  }
}

// Gradient (and with c ≠ nullptr the IDBD curvature) of J w.r.t. the full factor M (n×n, upper
// triangle filled, lower set to 0; m = M, dd = D, both column-major), given d = x − c, md = M·d and
// the kernel slopes dw/dq and d²w/dq² at q. Row r's sums run over all n columns in ascending order
// (M's lower zeros included), as Eigen's row products did; |M_r|² once per row.
template <int N, class T>
__attribute__((always_inline)) inline void calc_full_gradient(const LwprParams& params, const T* m, const T* dd,
                                                              int n_runtime, const T* d, const T* md, const T& w,
                                                              const T& W, const T& dw_dq, const T& d2w_dq2,
                                                              const T& dJ1_dw, const T& d2J1_dw2, T* g, T* c) {
  const int n = dim<N>(n_runtime);
  const double penalty = params.penalty / n;  // γ/n
  const T penalty_weight = w / W;
  // q = |M d|²: ∂q/∂M_rl = 2(Md)_r d_l;  J2 = (γ/n)·tr(D²): ∂J2/∂M = 4(γ/n)·M D.
  for (int r = 0; r < n; ++r) {
    T row2 = m[r] * m[r];
    for (int k = 1; k < n; ++k) row2 += m[r + k * n] * m[r + k * n];
    for (int l = 0; l < r; ++l) {
      g[r + l * n] = splat<T>(0.0);
      if (c != nullptr) c[r + l * n] = splat<T>(0.0);
    }
    for (int l = r; l < n; ++l) {
      const T* D_l = dd + l * n;
      T dot = m[r] * D_l[0];
      for (int k = 1; k < n; ++k) dot += m[r + k * n] * D_l[k];
      const T dJ2 = 4.0 * penalty * dot;
      const T d2J2 = 4.0 * penalty * (m[r + l * n] * m[r + l * n] + row2 + D_l[l]);
      const T dq = 2.0 * md[r] * d[l];
      const T d2q = 2.0 * d[l] * d[l];
      const T dw = dw_dq * dq;
      g[r + l * n] = dJ1_dw * dw + penalty_weight * dJ2;
      if (c != nullptr) {
        const T d2w = d2w_dq2 * dq * dq + dw_dq * d2q;
        c[r + l * n] = d2J1_dw2 * dw * dw + dJ1_dw * d2w + penalty_weight * d2J2;
      }
    }
  }
}

// Step 1 of a full metric's update: scratch.grad (and with meta learning scratch.curvature) =
// the gradient of J w.r.t. M at the sample, from md = M·(x − c) (sample.md if given, else
// computed into scratch.md).
template <int N>
void calc_full_metric_gradient(const LwprParams& params, const Eigen::VectorXd& diff, const MetricSample& sample,
                               double dJ1_dw, const ReceptiveField& rf, FieldScratch& scratch) {
  const int n = dim<N>(rf.input_dim());
  const double d2J1_dw2 = 2.0 * sample.e_cv.head(rf.n_reg()).squaredNorm() / (sample.W * sample.W);
  scratch.grad.resize(n, n);
  if (params.meta) scratch.curvature.resize(n, n);
  const double* md = nullptr;
  if (sample.md != nullptr) {
    md = sample.md->data();  // calc_factor_product's: multiply_factor<N> for n ≤ kTrmvPanel, else Eigen's, as below
  } else if (N > 0 || n <= kTrmvPanel) {
    scratch.md.resize(n);
    multiply_factor<N>(rf.metric_factor.data(), diff.data(), n, scratch.md.data());
    md = scratch.md.data();
  } else {
    scratch.md.noalias() = rf.metric_factor.triangularView<Eigen::Upper>() * diff;
    md = scratch.md.data();
  }
  double* curvature = params.meta ? scratch.curvature.data() : nullptr;
  const KernelSlopes slopes = calc_kernel_slopes(params.kernel, sample.q);
  calc_full_gradient<N>(params, rf.metric_factor.data(), rf.metric.data(), n, diff.data(), md, sample.w, sample.W,
                        slopes.dw_dq, slopes.d2w_dq2, dJ1_dw, d2J1_dw2, scratch.grad.data(), curvature);
}

// Step 2: whether the gradient's upper triangle is finite, and max|M| over the upper triangle
// (the step safeguard's scale).
template <int N>
__attribute__((always_inline)) inline bool check_full_gradient(const double* g, const double* m, int n_runtime, double& max_abs) {
  const int n = dim<N>(n_runtime);
  bool finite = true;
  max_abs = 0.0;
  for (int col = 0; col < n; ++col) {
    for (int row = 0; row <= col; ++row) {
      finite = finite && std::isfinite(g[row + col * n]);
      max_abs = std::max(max_abs, std::abs(m[row + col * n]));
    }
  }
  return finite;
}

// Step 3: the gradient (or IDBD) step on M's upper triangle. Each element's rate α = exp(log α)
// (with meta learning log α first moves against the gradient's correlation with the trace); an
// element whose step would exceed `bound` is skipped and its rate halved (the library's
// safeguard); with meta learning the trace decays by the curvature and takes the applied step.
// m, log_alpha_data and trace are M, log α and the IDBD trace (n×n, column-major).
template <int N>
__attribute__((always_inline)) inline void step_full_factor(const LwprParams& params, const double* g,
                                                            const double* curvature, double transient, double bound,
                                                            int n_runtime, double* m, double* log_alpha_data,
                                                            double* trace) {
  const int n = dim<N>(n_runtime);
  const double log_half = std::log(0.5);
  // Without meta learning the rates only change when a step is too large, so neighbouring elements
  // nearly always share one log-rate: exp() is evaluated only when the log-rate differs from the
  // previous element's (the same value, bit for bit, as evaluating it every time).
  double last_log_alpha = std::numeric_limits<double>::quiet_NaN();
  double last_alpha = 0.0;
  for (int col = 0; col < n; ++col) {
    for (int row = 0; row <= col; ++row) {
      const int at = row + col * n;
      const double grad = g[at];
      double& log_alpha = log_alpha_data[at];
      if (params.meta) {
        const double change = std::clamp(-params.meta_rate * grad * trace[at], -0.1, 0.1);
        log_alpha = std::clamp(log_alpha + change, -10.0, 10.0);
      }
      if (!(log_alpha == last_log_alpha)) {
        last_log_alpha = log_alpha;
        last_alpha = calc_rate(params.meta, log_alpha);
      }
      const double alpha = last_alpha;
      const double step = alpha * transient * grad;
      double applied = 0.0;
      if (std::abs(step) > bound) {
        log_alpha += log_half;  // too large a step: halve the rate, skip this element
      } else {
        m[at] -= step;
        applied = -step;
      }
      if (params.meta) {
        const double decay = std::max(0.0, 1.0 - alpha * curvature[at]);
        trace[at] = trace[at] * decay + applied;
      }
    }
  }
}

// Step 4: D = MᵀM for the stepped factor; if it or M is not finite, M goes back to `old` (a
// field never keeps a NaN metric), else D becomes the field's metric.
template <int N>
void accept_full_metric(const double* old, ReceptiveField& rf, FieldScratch& scratch) {
  const int n = dim<N>(rf.input_dim());
  double* m = rf.metric_factor.data();
  scratch.new_metric.resize(n, n);
  double* D_new = scratch.new_metric.data();
  if (N > 0 || n <= kOrderedProductMax) {
    multiply_factor_transposed<N>(m, n, D_new);
  } else {
    scratch.new_metric.noalias() = rf.metric_factor.transpose() * rf.metric_factor;
  }
  bool finite = true;
  for (int i = 0; i < n * n; ++i) finite = finite && std::isfinite(D_new[i]) && std::isfinite(m[i]);
  if (!finite) {
    for (int i = 0; i < n * n; ++i) m[i] = old[i];
    return;
  }
  rf.metric.swap(scratch.new_metric);
}

// One gradient (or IDBD) step on a full factor: the gradient (step 1); nothing more if it is not
// finite (a degenerate sample keeps the metric); the step on the upper triangle, bounded by a
// tenth of max|M| (steps 2–3); D = MᵀM, kept only if finite (step 4).
template <int N>
void update_full_metric(const LwprParams& params, const Eigen::VectorXd& diff, const MetricSample& sample,
                        double dJ1_dw, double transient, ReceptiveField& rf, FieldScratch& scratch) {
  const int n = dim<N>(rf.input_dim());
  calc_full_metric_gradient<N>(params, diff, sample, dJ1_dw, rf, scratch);
  const double* g = scratch.grad.data();
  double max_abs = 0.0;
  if (!check_full_gradient<N>(g, rf.metric_factor.data(), n, max_abs)) return;
  scratch.old_factor.resize(n, n);
  double* old = scratch.old_factor.data();
  const double* m = rf.metric_factor.data();
  for (int i = 0; i < n * n; ++i) old[i] = m[i];
  const double* curvature = params.meta ? scratch.curvature.data() : nullptr;
  step_full_factor<N>(params, g, curvature, transient, 0.1 * max_abs, n, rf.metric_factor.data(), rf.log_alpha.data(),
                      rf.meta_trace.data());
  accept_full_metric<N>(old, rf, scratch);
}

// J1 sums the leave-one-out errors of the R univariate regressions. Per projection r, with
// P_r = 1/Σλws_r²: ∂J1/∂w ≈ −E/W² + (1/W)·Σ_r (e_cv,r² − 2 e_r P_r s_r H_r − 2 P_r² s_r² R_r),
// where the H and R terms carry the effect of w on β_r and P_r for the samples already seen.
// s, e, e_cv: the sample's R = rf.n_reg() projections, residuals and leave-one-out residuals (R
// fixed at compile time if R > 0).
// ss2, press_H, press_R: the field's Σλws², H and R (before this sample's memory terms).
template <int R, class T>
__attribute__((always_inline)) inline T calc_press_dw_of(int n_runtime, const T* ss2, const T* press_H,
                                                         const T* press_R, const T* s, const T* e, const T* e_cv,
                                                         const T& W, const T& E) {
  const int n_reg = R > 0 ? R : n_runtime;
  T sum = splat<T>(0.0);
  for (int r = 0; r < n_reg; ++r) {
    const T ps = s[r] / ss2[r];
    const T e_cv_r = e_cv[r];
    sum += e_cv_r * e_cv_r - 2.0 * e[r] * ps * press_H[r] - 2.0 * ps * ps * press_R[r];
  }
  return -E / (W * W) + sum / W;
}

}  // namespace

double calc_rate_exp(double x) { return calc_rate_exp_of(x); }

double calc_press_dw(const ReceptiveField& rf, const MetricSample& sample) {
  return calc_press_dw_of<0>(rf.n_reg(), rf.ss2.data(), rf.press_H.data(), rf.press_R.data(), sample.s.data(),
                             sample.e.data(), sample.e_cv.data(), sample.W, sample.E);
}

void calc_factor_product(const Eigen::MatrixXd& M, const Eigen::VectorXd& diff, Eigen::VectorXd& md) {
  const int n = static_cast<int>(M.rows());
  if (n > kTrmvPanel) {
    md.noalias() = M.triangularView<Eigen::Upper>() * diff;
    return;
  }
  md.resize(n);
  switch (n) {
    case 2: multiply_factor<2>(M.data(), diff.data(), n, md.data()); break;
    case 3: multiply_factor<3>(M.data(), diff.data(), n, md.data()); break;
    default: multiply_factor<0>(M.data(), diff.data(), n, md.data()); break;
  }
}

void calc_metric_gradient(const LwprParams& params, const ReceptiveField& rf, const Eigen::VectorXd& diff,
                          const MetricSample& sample, double dJ1_dw, double d2J1_dw2, Eigen::MatrixXd& grad,
                          Eigen::MatrixXd* curvature, Eigen::VectorXd& md) {
  const int n = rf.input_dim();
  const Eigen::MatrixXd& M = rf.metric_factor;
  grad.resize(M.rows(), M.cols());
  if (curvature != nullptr) curvature->resize(M.rows(), M.cols());
  double* g = grad.data();
  double* c = curvature != nullptr ? curvature->data() : nullptr;
  if (!rf.diagonal()) {
    calc_factor_product(M, diff, md);
    const KernelSlopes slopes = calc_kernel_slopes(params.kernel, sample.q);
    const double* m = M.data();
    const double* dd = rf.metric.data();
    switch (n) {
      case 2:
        calc_full_gradient<2>(params, m, dd, n, diff.data(), md.data(), sample.w, sample.W, slopes.dw_dq,
                              slopes.d2w_dq2, dJ1_dw, d2J1_dw2, g, c);
        break;
      case 3:
        calc_full_gradient<3>(params, m, dd, n, diff.data(), md.data(), sample.w, sample.W, slopes.dw_dq,
                              slopes.d2w_dq2, dJ1_dw, d2J1_dw2, g, c);
        break;
      default:
        calc_full_gradient<0>(params, m, dd, n, diff.data(), md.data(), sample.w, sample.W, slopes.dw_dq,
                              slopes.d2w_dq2, dJ1_dw, d2J1_dw2, g, c);
        break;
    }
    return;
  }
  // q = Σ_i M_i² d_i²;  J2 = (γ/n)·Σ_i M_i⁴.
  const KernelSlopes slopes = calc_kernel_slopes(params.kernel, sample.q);
  const double penalty = params.penalty / n;  // γ/n
  const double penalty_weight = sample.w / sample.W;
  for (int i = 0; i < n; ++i) {
    const double mi = M(i, 0);
    const double d2 = diff(i) * diff(i);
    const double dq = 2.0 * mi * d2, d2q = 2.0 * d2;
    const double dJ2 = 4.0 * penalty * mi * mi * mi, d2J2 = 12.0 * penalty * mi * mi;
    const double dw = slopes.dw_dq * dq;
    g[i] = dJ1_dw * dw + penalty_weight * dJ2;
    if (c != nullptr) {
      const double d2w = slopes.d2w_dq2 * dq * dq + slopes.dw_dq * d2q;
      c[i] = d2J1_dw2 * dw * dw + dJ1_dw * d2w + penalty_weight * d2J2;
    }
  }
}

void calc_metric_from_factor(const Eigen::MatrixXd& M, Eigen::MatrixXd& D) {
  if (M.cols() == 1) {
    D = M.array().square().matrix();
    return;
  }
  const int n = static_cast<int>(M.rows());
  if (n > kOrderedProductMax) {
    D.noalias() = M.transpose() * M;
    return;
  }
  D.resize(n, n);
  multiply_factor_transposed<0>(M.data(), n, D.data());
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
      last_alpha = calc_rate(false, log_alpha[i]);
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

namespace {

// The fixed-size path of a full metric with N = 2 or 3 inputs and R projections (both known at
// compile time: every loop unrolls, no alias checks, the values stay in registers), on T = double
// for one field or on Quad for four fields at once: each field's values are gathered into its lane
// from its own storage and scattered back, and every lane runs the one field's operations.

// Finiteness of many values: zero = Σ v·0 from 0 is NaN exactly when a v is not finite (x·0 is ±0
// for a finite x and NaN for ±∞ or NaN; no overflow: the products are zeros). The same answer as
// std::isfinite() of each, in two operations per value; this is one step of that sum.
template <class T>
__attribute__((always_inline)) inline T add_times_zero(const T& zero, const T& v) {
  return zero + v * 0.0;
}

// Without meta learning, calc_rate() of K elements of L fields (element k of field l at [k·L + l])
// with the C library's exp, once per run of equal log-rates in a field, as step_full_factor() (the
// same values either way). Not inlined: the caller's live values are saved once around this call,
// not around each exp() (every vector register is caller-saved).
template <int K, int L>
__attribute__((noinline)) void calc_library_rates(const double* log_alpha, double* alpha) {
  for (int l = 0; l < L; ++l) {
    alpha[l] = std::exp(log_alpha[l]);
    for (int k = 1; k < K; ++k) {
      const int at = k * L + l;
      alpha[at] = log_alpha[at] == log_alpha[at - L] ? alpha[at - L] : std::exp(log_alpha[at]);
    }
  }
}

// α_k = calc_rate(log α_k), k < K, in each lane.
template <int K, class T>
__attribute__((always_inline)) inline void calc_rates_of(bool meta, const T* log_alpha, T* alpha) {
  if (meta) {
    for (int k = 0; k < K; ++k) alpha[k] = calc_rate_exp_of(log_alpha[k]);
    return;
  }
  constexpr int L = kLaneCount<T>;
  double in[K * L], out[K * L];
  std::memcpy(in, log_alpha, sizeof in);
  calc_library_rates<K, L>(in, out);
  // Element by element: one wide load of the call's narrow stores would wait for them to retire
  // (no store forwarding).
  for (int k = 0; k < K; ++k) {
    if constexpr (L == 1) {
      alpha[k] = out[k];
    } else {
      for (int l = 0; l < L; ++l) alpha[k][l] = out[k * L + l];
    }
  }
}

// The fields of one metric step on T: lane l's field, scratch and activation. Lanes past the
// group's fields repeat lane 0's field, scratch and activation, so they compute lane 0's values,
// bit for bit, and writing them back writes what lane 0 writes: every store takes all lanes,
// unconditionally.
template <class T>
struct FieldLanes {
  static constexpr int kLanes = kLaneCount<T>;
  ReceptiveField* rf[kLanes];
  const FieldScratch* scratch[kLanes];
  double w[kLanes];

  // The vector whose lane l is f(l).
  template <class F>
  __attribute__((always_inline)) T gather(F&& f) const {
    if constexpr (std::is_same_v<T, double>) {
      return f(0);
    } else {
      T out;
      for (int l = 0; l < kLanes; ++l) out[l] = f(l);
      return out;
    }
  }
  // f(l, lane l of v) for every lane l.
  template <class F>
  __attribute__((always_inline)) void scatter(const T& v, F&& f) const {
    for (int l = 0; l < kLanes; ++l) f(l, lane(v, l));
  }
};

// What update_distance_metric() reads of the sample, on T (SmallMetricSample's terms).
template <int N, int R, class T>
struct SmallMetricLanes {
  T w, W, E, e_cv2;
  T s[R], e[R], e_cv[R], diff[N];
};

// step_full_factor() on the upper triangle in three passes: the log-rates (IDBD), their rates
// (calc_rates_of), then the steps, the safeguard and the traces. Each element's operations are
// step_full_factor()'s in the same order (there an element shares the previous one's rate when
// their log-rates are equal: the same value), so the same bits. m, g and curvature are n×n
// column-major; log_alpha and trace hold the upper triangle's elements column by column.
template <int N, class T>
__attribute__((always_inline)) inline void step_small_factor(const LwprParams& params, const T* g, const T* curvature,
                                                             const T& transient, const T& bound, T* m, T* log_alpha,
                                                             T* trace) {
  constexpr int kUpper = N * (N + 1) / 2;
  int at[kUpper];
  for (int col = 0, k = 0; col < N; ++col) {
    for (int row = 0; row <= col; ++row, ++k) at[k] = row + col * N;
  }
  if (params.meta) {
    for (int k = 0; k < kUpper; ++k) {
      const T change = clamp_of(-params.meta_rate * g[at[k]] * trace[k], -0.1, 0.1);
      log_alpha[k] = clamp_of(log_alpha[k] + change, -10.0, 10.0);
    }
  }
  T alpha[kUpper];
  calc_rates_of<kUpper>(params.meta, log_alpha, alpha);
  const double log_half = std::log(0.5);
  for (int k = 0; k < kUpper; ++k) {
    const T step = alpha[k] * transient * g[at[k]];
    // Too large a step: halve the rate, skip this element. M's element is written either way (a
    // select, not a conditional store), so that M stays in registers.
    const auto skip = abs_of(step) > bound;
    log_alpha[k] = skip ? log_alpha[k] + log_half : log_alpha[k];
    const T kept = m[at[k]];
    m[at[k]] = skip ? kept : kept - step;
    const T applied = skip ? splat<T>(0.0) : -step;
    if (params.meta) {
      const T decay = max_of(splat<T>(0.0), 1.0 - alpha[k] * curvature[at[k]]);
      trace[k] = trace[k] * decay + applied;
    }
  }
}

// update_distance_metric()'s steps: dJ1/dw, M·(x−c) and the gradient (step 1), its check and
// max|M| (step 2), the step (3) on a copy of M, D = MᵀM and its check (4). Each field's M, D, log α
// and trace are written as the general step leaves them: nothing for a non-finite gradient, and M
// and D only if the stepped ones are finite.
template <int N, int R, class T>
__attribute__((always_inline)) inline void step_small_full_metric(const LwprParams& params,
                                                                  const SmallMetricLanes<N, R, T>& sample,
                                                                  const T& transient, const FieldLanes<T>& lanes) {
  static_assert(N == 2 || N == 3, "the fixed-size full metric step is for 2 or 3 inputs");
  static_assert(R >= 1 && R <= N, "1 to N projections");
  constexpr int kSize = N * N;
  constexpr int kUpper = N * (N + 1) / 2;
  constexpr int L = kLaneCount<T>;
  ReceptiveField* const* rf = lanes.rf;
  T ss2[R], press_H[R], press_R[R];
  for (int r = 0; r < R; ++r) {
    ss2[r] = lanes.gather([&](int l) { return rf[l]->ss2.data()[r]; });
    press_H[r] = lanes.gather([&](int l) { return rf[l]->press_H.data()[r]; });
    press_R[r] = lanes.gather([&](int l) { return rf[l]->press_R.data()[r]; });
  }
  const T dJ1_dw = calc_press_dw_of<R>(R, ss2, press_H, press_R, sample.s, sample.e, sample.e_cv, sample.W, sample.E);
  const T d2J1_dw2 = 2.0 * sample.e_cv2 / (sample.W * sample.W);
  T m[kSize], dd[kSize];
  for (int i = 0; i < kSize; ++i) {
    m[i] = lanes.gather([&](int l) { return rf[l]->metric_factor.data()[i]; });
    dd[i] = lanes.gather([&](int l) { return rf[l]->metric.data()[i]; });
  }
  T md[N];
  multiply_factor<N>(m, sample.diff, N, md);  // calc_factor_product's
  T dw_dq, d2w_dq2;
  if (params.kernel == Kernel::kGaussian) {
    dw_dq = -0.5 * sample.w;  // calc_kernel_slopes() at q, whose exp(−q/2) is w
    d2w_dq2 = 0.25 * sample.w;
  } else {
    T q = md[0] * md[0];  // md's squaredNorm: Eigen sums up to 3 elements in ascending order
    for (int r = 1; r < N; ++r) q += md[r] * md[r];
    KernelSlopes slopes[L];
    for (int l = 0; l < L; ++l) slopes[l] = calc_kernel_slopes(params.kernel, lane(q, l));
    dw_dq = lanes.gather([&](int l) { return slopes[l].dw_dq; });
    d2w_dq2 = lanes.gather([&](int l) { return slopes[l].d2w_dq2; });
  }
  T g[kSize], c[kSize];
  T* curvature = params.meta ? c : nullptr;
  calc_full_gradient<N>(params, m, dd, N, sample.diff, md, sample.w, sample.W, dw_dq, d2w_dq2, dJ1_dw, d2J1_dw2, g,
                        curvature);
  int at[kUpper];
  for (int col = 0, k = 0; col < N; ++col) {
    for (int row = 0; row <= col; ++row, ++k) at[k] = row + col * N;
  }
  T zero = splat<T>(0.0), max_abs = splat<T>(0.0);
  T log_alpha[kUpper], trace[kUpper];
  for (int k = 0; k < kUpper; ++k) {
    zero = add_times_zero(zero, g[at[k]]);
    max_abs = max_of(max_abs, abs_of(m[at[k]]));
    log_alpha[k] = lanes.gather([&](int l) { return rf[l]->log_alpha.data()[at[k]]; });
    trace[k] = lanes.gather([&](int l) { return rf[l]->meta_trace.data()[at[k]]; });
  }
  const auto finite_gradient = zero == zero;
  bool any = false;
  for (int l = 0; l < L; ++l) any = any || lane_true(finite_gradient, l);
  if (!any) return;  // a degenerate sample in every field: each keeps its metric as it is
  T stepped[kSize];
  std::copy(m, m + kSize, stepped);
  T new_log_alpha[kUpper], new_trace[kUpper];
  std::copy(log_alpha, log_alpha + kUpper, new_log_alpha);
  std::copy(trace, trace + kUpper, new_trace);
  step_small_factor<N>(params, g, curvature, transient, 0.1 * max_abs, stepped, new_log_alpha, new_trace);
  // A field whose gradient is not finite keeps its log α and trace (selects, not conditional stores).
  for (int k = 0; k < kUpper; ++k) {
    const T kept_log_alpha = finite_gradient ? new_log_alpha[k] : log_alpha[k];
    lanes.scatter(kept_log_alpha, [&](int l, double v) { rf[l]->log_alpha.data()[at[k]] = v; });
    if (params.meta) {
      const T kept_trace = finite_gradient ? new_trace[k] : trace[k];
      lanes.scatter(kept_trace, [&](int l, double v) { rf[l]->meta_trace.data()[at[k]] = v; });
    }
  }
  // The stepped factor as values in registers (the empty asm only pins each in a register), so
  // that the code below does not read them back from `stepped` with wide loads right after its
  // element stores (which missed store forwarding).
  T m_new[kSize];
  for (int i = 0; i < kSize; ++i) {
    T v = stepped[i];
    asm("" : "+x"(v));
    m_new[i] = v;
  }
  T D_new[kSize];
  multiply_factor_transposed<N>(m_new, N, D_new);
  // D_new is symmetric (each pair computed once), so its upper triangle decides for all of it.
  T zero_new = splat<T>(0.0);
  for (int k = 0; k < kUpper; ++k) zero_new = add_times_zero(zero_new, D_new[at[k]]);
  for (int i = 0; i < kSize; ++i) zero_new = add_times_zero(zero_new, m_new[i]);
  // Never a NaN metric: a field keeps M and D unless its gradient and its new M and D are finite.
  const auto accepted = finite_gradient && zero_new == zero_new;
  for (int i = 0; i < kSize; ++i) {
    const T kept_m = accepted ? m_new[i] : m[i];
    const T kept_D = accepted ? D_new[i] : dd[i];
    lanes.scatter(kept_m, [&](int l, double v) { rf[l]->metric_factor.data()[i] = v; });
    lanes.scatter(kept_D, [&](int l, double v) { rf[l]->metric.data()[i] = v; });
  }
}

// finish_field_update()'s metric part (update_small_full_field_metric()): the same operations in
// the same order as its general code, then the step above, then the PRESS memory terms.
template <int N, int R, class T>
__attribute__((always_inline)) inline void update_small_full_field_metric_of(const LwprParams& params, const double* x,
                                                                             const FieldLanes<T>& lanes) {
  ReceptiveField* const* rf = lanes.rf;
  const FieldScratch* const* scratch = lanes.scratch;
  const T lambda = lanes.gather([&](int l) { return rf[l]->lambda; });
  SmallMetricLanes<N, R, T> sample;
  sample.w = lanes.gather([&](int l) { return lanes.w[l]; });
  const T& w = sample.w;
  T one_minus_h[R];
  for (int r = 0; r < R; ++r) {
    sample.s[r] = lanes.gather([&](int l) { return scratch[l]->s.data()[r]; });
    sample.e[r] = lanes.gather([&](int l) { return scratch[l]->residual.data()[r]; });
    one_minus_h[r] = lanes.gather([&](int l) { return scratch[l]->one_minus_h.data()[r]; });
    sample.e_cv[r] = sample.e[r] / one_minus_h[r];  // projection r's own residual
  }
  const T e = sample.e[R - 1];
  const T sum_e2 = lambda * lanes.gather([&](int l) { return rf[l]->sum_e2; }) + w * e * e;
  lanes.scatter(sum_e2, [&](int l, double v) { rf[l]->sum_e2 = v; });
  T e_cv2 = sample.e_cv[0] * sample.e_cv[0];  // e_cv.head(R).squaredNorm(): Eigen sums up to 3 in ascending order
  for (int r = 1; r < R; ++r) e_cv2 += sample.e_cv[r] * sample.e_cv[r];
  sample.e_cv2 = e_cv2;
  sample.E = lambda * lanes.gather([&](int l) { return rf[l]->press_E; }) + w * e_cv2;
  lanes.scatter(sample.E, [&](int l, double v) { rf[l]->press_E = v; });
  for (int k = 0; k < N; ++k) sample.diff[k] = x[k] - lanes.gather([&](int l) { return rf[l]->center.data()[k]; });
  sample.W = lanes.gather([&](int l) { return rf[l]->sum_w.data()[0]; });
  // The library's transient multiplier: small steps while the leave-one-out error is still much
  // larger than the fitted error (a young or changing field).
  const T ratio = sum_e2 / (lanes.gather([&](int l) { return rf[l]->sum_e_cv2.data()[R - 1]; }) + 1e-10);
  const T transient = min_of(splat<T>(1.0), ratio * ratio * ratio * ratio);
  step_small_full_metric<N, R>(params, sample, transient, lanes);
  for (int r = 0; r < R; ++r) {
    const T s = sample.s[r], e_cv = sample.e_cv[r];
    const T H = lambda * lanes.gather([&](int l) { return rf[l]->press_H.data()[r]; }) + w * s * e_cv / one_minus_h[r];
    const T Rm = lambda * lanes.gather([&](int l) { return rf[l]->press_R.data()[r]; }) +
                 w * w * s * s * e_cv * e_cv / one_minus_h[r];
    lanes.scatter(H, [&](int l, double v) { rf[l]->press_H.data()[r] = v; });
    lanes.scatter(Rm, [&](int l, double v) { rf[l]->press_R.data()[r] = v; });
  }
}

// Each (n, R) compiled for SSE2 and for AVX2 on one field (target("avx2") without FMA: the same
// operations with three-operand encodings, so the same bits and fewer register copies), and for
// AVX2 on four.
template <int N, int R>
void step_one_sse2(const LwprParams& params, const SmallMetricLanes<N, R, double>& sample, double transient,
                   const FieldLanes<double>& field) {
  step_small_full_metric<N, R>(params, sample, transient, field);
}
template <int N, int R>
__attribute__((target("avx2"))) void step_one_avx2(const LwprParams& params,
                                                   const SmallMetricLanes<N, R, double>& sample, double transient,
                                                   const FieldLanes<double>& field) {
  step_small_full_metric<N, R>(params, sample, transient, field);
}
template <int N, int R>
void field_metric_one_sse2(const LwprParams& params, const double* x, const FieldLanes<double>& field) {
  update_small_full_field_metric_of<N, R>(params, x, field);
}
template <int N, int R>
__attribute__((target("avx2"))) void field_metric_one_avx2(const LwprParams& params, const double* x,
                                                           const FieldLanes<double>& field) {
  update_small_full_field_metric_of<N, R>(params, x, field);
}
template <int N, int R>
__attribute__((target("avx2"))) void field_metric_four_avx2(const LwprParams& params, const double* x,
                                                            const FieldLanes<Quad>& fields) {
  update_small_full_field_metric_of<N, R>(params, x, fields);
}

template <int N, int R>
void step_one(bool avx2, const LwprParams& params, const SmallMetricSample& in, double transient, ReceptiveField& rf) {
  SmallMetricLanes<N, R, double> sample;
  sample.w = in.w;
  sample.W = in.W;
  sample.E = in.E;
  sample.e_cv2 = in.e_cv2;
  std::copy(in.s, in.s + R, sample.s);
  std::copy(in.e, in.e + R, sample.e);
  std::copy(in.e_cv, in.e_cv + R, sample.e_cv);
  std::copy(in.diff, in.diff + N, sample.diff);
  FieldLanes<double> field;
  field.rf[0] = &rf;
  field.scratch[0] = nullptr;
  field.w[0] = in.w;
  if (avx2) {
    step_one_avx2<N, R>(params, sample, transient, field);
  } else {
    step_one_sse2<N, R>(params, sample, transient, field);
  }
}

// The fields' metric steps: four at a time on AVX2 when every scratch allows it, else one by one.
template <int N, int R>
void field_metrics(const LwprParams& params, const double* x, int count, const double* w,
                   const FieldScratch* const* scratch, ReceptiveField* const* rf) {
  bool avx2 = true;
  for (int k = 0; k < count; ++k) avx2 = avx2 && scratch[k]->use_avx2;
  if (avx2 && count > 1) {
    FieldLanes<Quad> fields;
    for (int l = 0; l < FieldLanes<Quad>::kLanes; ++l) {
      const int k = l < count ? l : 0;
      fields.rf[l] = rf[k];
      fields.scratch[l] = scratch[k];
      fields.w[l] = w[k];
    }
    field_metric_four_avx2<N, R>(params, x, fields);
    return;
  }
  for (int k = 0; k < count; ++k) {
    FieldLanes<double> field;
    field.rf[0] = rf[k];
    field.scratch[0] = scratch[k];
    field.w[0] = w[k];
    if (scratch[k]->use_avx2) {
      field_metric_one_avx2<N, R>(params, x, field);
    } else {
      field_metric_one_sse2<N, R>(params, x, field);
    }
  }
}

}  // namespace

void update_small_full_metric(const LwprParams& params, const SmallMetricSample& sample, double transient,
                              ReceptiveField& rf, bool use_avx2) {
  switch (rf.input_dim() * 4 + rf.n_reg()) {
    case 2 * 4 + 1: step_one<2, 1>(use_avx2, params, sample, transient, rf); break;
    case 2 * 4 + 2: step_one<2, 2>(use_avx2, params, sample, transient, rf); break;
    case 3 * 4 + 1: step_one<3, 1>(use_avx2, params, sample, transient, rf); break;
    case 3 * 4 + 2: step_one<3, 2>(use_avx2, params, sample, transient, rf); break;
    case 3 * 4 + 3: step_one<3, 3>(use_avx2, params, sample, transient, rf); break;
    default: throw std::invalid_argument("update_small_full_metric: a full metric of 2 or 3 inputs only");
  }
}

void update_small_full_field_metrics(const LwprParams& params, const Eigen::VectorXd& x, int count, const double* w,
                                     const FieldScratch* const* scratch, ReceptiveField* const* rf) {
  if (count < 1 || count > kMetricLanes) {
    throw std::invalid_argument("update_small_full_field_metrics: 1 to " + std::to_string(kMetricLanes) + " fields");
  }
  const int n = rf[0]->input_dim(), n_reg = rf[0]->n_reg();
  for (int k = 1; k < count; ++k) {
    if (rf[k]->input_dim() != n || rf[k]->n_reg() != n_reg) {
      throw std::invalid_argument(
          "update_small_full_field_metrics: fields of one input dimension and projection count");
    }
  }
  switch (n * 4 + n_reg) {
    case 2 * 4 + 1: field_metrics<2, 1>(params, x.data(), count, w, scratch, rf); break;
    case 2 * 4 + 2: field_metrics<2, 2>(params, x.data(), count, w, scratch, rf); break;
    case 3 * 4 + 1: field_metrics<3, 1>(params, x.data(), count, w, scratch, rf); break;
    case 3 * 4 + 2: field_metrics<3, 2>(params, x.data(), count, w, scratch, rf); break;
    case 3 * 4 + 3: field_metrics<3, 3>(params, x.data(), count, w, scratch, rf); break;
    default: throw std::invalid_argument("update_small_full_field_metrics: a full metric of 2 or 3 inputs only");
  }
}

void update_small_full_field_metric(const LwprParams& params, const Eigen::VectorXd& x, double w,
                                    const FieldScratch& scratch, ReceptiveField& rf) {
  const FieldScratch* scratches[1] = {&scratch};
  ReceptiveField* fields[1] = {&rf};
  update_small_full_field_metrics(params, x, 1, &w, scratches, fields);
}

void update_distance_metric(const LwprParams& params, const Eigen::VectorXd& diff, const MetricSample& sample,
                            double transient, ReceptiveField& rf, FieldScratch& scratch) {
  const double dJ1_dw = calc_press_dw(rf, sample);
  if (!rf.diagonal()) {
    switch (rf.input_dim()) {
      case 2: update_full_metric<2>(params, diff, sample, dJ1_dw, transient, rf, scratch); break;
      case 3: update_full_metric<3>(params, diff, sample, dJ1_dw, transient, rf, scratch); break;
      default: update_full_metric<0>(params, diff, sample, dJ1_dw, transient, rf, scratch); break;
    }
    return;
  }
  if (!params.meta) {
    update_diagonal_metric(params, diff, sample, dJ1_dw, transient, rf, scratch);
    return;
  }
  // A diagonal metric with meta learning: IDBD log-rates per element, then D = M².
  const double d2J1_dw2 = 2.0 * sample.e_cv.head(rf.n_reg()).squaredNorm() / (sample.W * sample.W);
  calc_metric_gradient(params, rf, diff, sample, dJ1_dw, d2J1_dw2, scratch.grad, &scratch.curvature, scratch.md);
  const int n = rf.input_dim();
  const double* g = scratch.grad.data();
  const double* curvature = scratch.curvature.data();
  double* m = rf.metric_factor.data();
  bool finite = true;
  double max_abs = 0.0;
  for (int i = 0; i < n; ++i) {
    finite = finite && std::isfinite(g[i]);
    max_abs = std::max(max_abs, std::abs(m[i]));
  }
  if (!finite) return;  // a degenerate sample: keep the metric as it is

  scratch.old_factor.resize(n, 1);
  double* old = scratch.old_factor.data();
  std::copy(m, m + n, old);
  const double bound = 0.1 * max_abs;
  const double log_half = std::log(0.5);
  double* log_alpha = rf.log_alpha.data();
  double* trace = rf.meta_trace.data();
  for (int i = 0; i < n; ++i) {
    const double change = std::clamp(-params.meta_rate * g[i] * trace[i], -0.1, 0.1);
    log_alpha[i] = std::clamp(log_alpha[i] + change, -10.0, 10.0);
    const double alpha = calc_rate(true, log_alpha[i]);
    const double step = alpha * transient * g[i];
    double applied = 0.0;
    if (std::abs(step) > bound) {
      log_alpha[i] += log_half;  // too large a step: halve the rate, skip this element
    } else {
      m[i] -= step;
      applied = -step;
    }
    const double decay = std::max(0.0, 1.0 - alpha * curvature[i]);
    trace[i] = trace[i] * decay + applied;
  }
  calc_metric_from_factor(rf.metric_factor, scratch.new_metric);
  if (!scratch.new_metric.allFinite() || !rf.metric_factor.allFinite()) {
    std::copy(old, old + n, m);  // never leave a field with a NaN metric
    return;
  }
  rf.metric.swap(scratch.new_metric);
}

}  // namespace armfarm::lwpr
