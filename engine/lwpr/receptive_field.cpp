// One receptive field: kernel, incremental weighted PLS, leave-one-out statistics.
#include "engine/lwpr/receptive_field.hpp"

#include "engine/lwpr/distance_metric.hpp"
#include "engine/lwpr/small_field_statistics.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace armfarm::lwpr {
namespace {


// Reductions over length-n vectors keep kLanes partial sums, element i in lane i mod kLanes
// (the tail continues from lane 0), added in a fixed order at the end.
constexpr int kLanes = 4;
inline double sum_lanes(const double (&part)[kLanes]) { return (part[0] + part[1]) + (part[2] + part[3]); }

// Two doubles operated on lane by lane (a GCC/Clang vector extension: one SSE2 register). The
// kLanes = 4 lanes of a loop are two of them, lanes 0–1 and 2–3. Element-wise arithmetic on them
// rounds exactly as the scalar loop it replaces, and lane k of a reduction holds the elements
// i ≡ k (mod kLanes), so the results are the same bits as the scalar code's.
typedef double Pair __attribute__((vector_size(2 * sizeof(double))));
// The kLanes = 4 lanes of a loop as one vector (one AVX2 register): lane k holds the elements
// i ≡ k (mod kLanes), the same partial sums as two pairs. Only the AVX2 copies of the field
// update and prediction use it (on SSE2 the compiler splits it less well than two pairs).
typedef double Quad __attribute__((vector_size(kLanes * sizeof(double))));
// Loads and stores through references (a vector passed by value can change the call ABI between
// builds; these inline to plain moves anyway).
template <class V>
inline void load_vector(V& v, const double* from) {
  std::memcpy(&v, from, sizeof v);
}
template <class V>
inline void store_vector(double* to, const V& v) {
  std::memcpy(to, &v, sizeof v);
}

void refresh_projection(ReceptiveField& rf, int r) {
  const double norm = rf.sxy.col(r).norm();
  if (norm > 0.0) {
    rf.directions.col(r) = rf.sxy.col(r) / norm;
  } else {
    rf.directions.col(r).setZero();
  }
  rf.loadings.col(r) = rf.sxs.col(r) / rf.ss2(r);
  rf.beta(r) = rf.sys(r) / rf.ss2(r);
}

}  // namespace

double calc_q_limit(Kernel kernel, double cutoff) {
  if (cutoff <= 0.0) return std::numeric_limits<double>::infinity();
  if (kernel == Kernel::kGaussian) return -2.0 * std::log(cutoff);
  return 4.0 * (1.0 - std::sqrt(cutoff));
}

void FieldScratch::resize(int n, bool diagonal) {
  z.resize(n);
  diff.resize(n);
  md.resize(n);
  s.resize(n);
  residual.resize(n);
  e_cv.resize(n);
  one_minus_h.resize(n);
  const int cols = diagonal ? 1 : n;
  grad.resize(n, cols);
  curvature.resize(n, cols);
  old_factor.resize(n, cols);
  new_metric.resize(n, cols);
}

ReceptiveField make_receptive_field(const LwprParams& params, const Eigen::VectorXd& x, const Eigen::MatrixXd& D) {
  const int n = static_cast<int>(x.size());
  ReceptiveField rf;
  rf.center = x;
  if (params.diag_only) {
    rf.metric = D.diagonal();
    rf.metric_factor = rf.metric.array().sqrt().matrix();
  } else {
    rf.metric = D;
    Eigen::LLT<Eigen::MatrixXd> llt(D);  // D = LLᵀ = MᵀM with M = Lᵀ upper triangular
    rf.metric_factor = llt.matrixU();
    calc_metric_from_factor(rf.metric_factor, rf.metric);
  }
  rf.log_alpha = Eigen::MatrixXd::Constant(rf.metric.rows(), rf.metric.cols(), std::log(params.init_alpha));
  rf.meta_trace = Eigen::MatrixXd::Zero(rf.metric.rows(), rf.metric.cols());
  if (!params.diag_only) rf.log_alpha.triangularView<Eigen::StrictlyLower>().setZero();
  rf.lambda = params.init_lambda;
  rf.mean_x = x;
  rf.beta0 = 0.0;
  rf.sum_w.resize(0);
  rf.n_data.resize(0);
  rf.sxy.resize(n, 0);
  rf.sxs.resize(n, 0);
  rf.ss2.resize(0);
  rf.sys.resize(0);
  rf.sum_e_cv2.resize(0);
  rf.press_H.resize(0);
  rf.press_R.resize(0);
  rf.directions.resize(n, 0);
  rf.loadings.resize(n, 0);
  rf.beta.resize(0);
  for (int r = 0; r < std::min(params.init_n_reg, n); ++r) add_projection(params, rf);
  rf.n_data.setConstant(kTinyWeight);
  return rf;
}

void add_projection(const LwprParams& params, ReceptiveField& rf) {
  const int n = rf.input_dim();
  const int r = rf.n_reg();
  auto grow = [r](Eigen::VectorXd& v, double value) {
    v.conservativeResize(r + 1);
    v(r) = value;
  };
  auto grow_cols = [n, r](Eigen::MatrixXd& m) {
    m.conservativeResize(n, r + 1);
    m.col(r).setZero();
  };
  grow(rf.sum_w, kTinyWeight);
  grow(rf.n_data, 0.0);
  grow_cols(rf.sxy);
  grow_cols(rf.sxs);
  grow(rf.ss2, params.init_S2);
  grow(rf.sys, 0.0);
  grow(rf.sum_e_cv2, 0.0);
  grow(rf.press_H, 0.0);
  grow(rf.press_R, 0.0);
  grow_cols(rf.directions);
  grow_cols(rf.loadings);
  grow(rf.beta, 0.0);
}

void refresh_receptive_field(ReceptiveField& rf) {
  for (int r = 0; r < rf.n_reg(); ++r) refresh_projection(rf, r);
}

double calc_kernel(Kernel kernel, double q) {
  if (kernel == Kernel::kGaussian) return std::exp(-0.5 * q);
  if (q >= 4.0) return 0.0;
  const double a = 1.0 - 0.25 * q;
  return a * a;
}

double calc_kernel_dq(Kernel kernel, double q) {
  if (kernel == Kernel::kGaussian) return -0.5 * std::exp(-0.5 * q);
  if (q >= 4.0) return 0.0;
  return -0.5 * (1.0 - 0.25 * q);
}

double calc_kernel_dq2(Kernel kernel, double q) {
  if (kernel == Kernel::kGaussian) return 0.25 * std::exp(-0.5 * q);
  if (q >= 4.0) return 0.0;
  return 0.125;
}

KernelSlopes calc_kernel_slopes(Kernel kernel, double q) {
  if (kernel == Kernel::kGaussian) {
    const double w = std::exp(-0.5 * q);
    return {-0.5 * w, 0.25 * w};
  }
  if (q >= 4.0) return {0.0, 0.0};
  return {-0.5 * (1.0 - 0.25 * q), 0.125};
}

double calc_activation(const ReceptiveField& rf, Kernel kernel, const Eigen::VectorXd& x, double cutoff,
                       FieldScratch& scratch) {
  return calc_activation_within(rf, kernel, x, calc_q_limit(kernel, cutoff), scratch);
}

double calc_activation_within(const ReceptiveField& rf, Kernel kernel, const Eigen::VectorXd& x, double q_limit,
                              FieldScratch& scratch) {
  const int n = rf.input_dim();
  double q = 0.0;
  const double* xc = x.data();
  const double* cc = rf.center.data();
  if (rf.diagonal()) {
    const double* dd = rf.metric.data();
    // Blocks of 4 so the compiler can vectorise; the early exit is checked once per block.
    int i = 0;
    for (; i + 4 <= n; i += 4) {
      const double d0 = xc[i] - cc[i], d1 = xc[i + 1] - cc[i + 1];
      const double d2 = xc[i + 2] - cc[i + 2], d3 = xc[i + 3] - cc[i + 3];
      q += dd[i] * d0 * d0 + dd[i + 1] * d1 * d1 + dd[i + 2] * d2 * d2 + dd[i + 3] * d3 * d3;
      if (q >= q_limit) return 0.0;
    }
    for (; i < n; ++i) {
      const double d = xc[i] - cc[i];
      q += dd[i] * d * d;
    }
  } else {
    scratch.diff = x - rf.center;
    const Eigen::MatrixXd& M = rf.metric_factor;
    for (int r = 0; r < n; ++r) {
      const double v = M.row(r).tail(n - r).dot(scratch.diff.tail(n - r));
      q += v * v;
      if (q >= q_limit) return 0.0;
    }
  }
  if (q >= q_limit) return 0.0;
  return calc_kernel(kernel, q);
}

namespace {

// predict_receptive_field() on vectors V (Pair or Quad, as update_statistics below): one pass per
// projection, projection r's deflation fused with projection r+1's dot product. With Leverage
// false the leverage is not computed (and not written); y is the same either way. N > 0 fixes the
// input dimension at compile time: the loops unroll, and z lives in a local array that the
// compiler keeps in registers (no store and reload of z per projection); N = 0 takes n from the
// field and z from the scratch. The same operations in the same order either way.
template <int N, class V, bool Leverage>
__attribute__((always_inline)) inline double predict_field(const ReceptiveField& rf, const Eigen::VectorXd& x,
                                                           double& leverage, FieldScratch& scratch) {
  constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
  constexpr int kGroups = kLanes / kWidth;
  const int n = N > 0 ? N : rf.input_dim();
  double z_local[N > 0 ? N : 1];
  double* z = N > 0 ? z_local : scratch.z.data();
  const double* xp = x.data();
  const double* mean_x = rf.mean_x.data();
  const double* u = rf.directions.col(0).data();
  V lanes[kGroups] = {};
  int i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    for (int g = 0; g < kGroups; ++g) {
      V xv, mv, uv;
      load_vector(xv, xp + i + g * kWidth);
      load_vector(mv, mean_x + i + g * kWidth);
      load_vector(uv, u + i + g * kWidth);
      const V zv = xv - mv;
      store_vector(z + i + g * kWidth, zv);
      lanes[g] += uv * zv;
    }
  }
  double part[kLanes];
  for (int k = 0; k < kLanes; ++k) part[k] = lanes[k / kWidth][k % kWidth];
  // At most kLanes − 1 elements are left, element i + k in lane k (written out, as in update_statistics).
  auto first_tail = [&](int k) __attribute__((always_inline)) {
    z[i + k] = xp[i + k] - mean_x[i + k];
    part[k] += u[i + k] * z[i + k];
  };
  if (i < n) first_tail(0);
  if (i + 1 < n) first_tail(1);
  if (i + 2 < n) first_tail(2);
  double s = sum_lanes(part);
  double y = rf.beta0;
  if (Leverage) leverage = 0.0;
  const int n_reg = rf.n_reg();
  for (int r = 0;; ++r) {
    y += rf.beta(r) * s;
    if (Leverage) leverage += s * s / rf.ss2(r);
    if (r + 1 == n_reg) break;
    const double* p = rf.loadings.col(r).data();
    const double* u_next = rf.directions.col(r + 1).data();
    V next_lanes[kGroups] = {};
    for (i = 0; i + kLanes <= n; i += kLanes) {
      for (int g = 0; g < kGroups; ++g) {
        V zv, pv, uv;
        load_vector(zv, z + i + g * kWidth);
        load_vector(pv, p + i + g * kWidth);
        load_vector(uv, u_next + i + g * kWidth);
        zv -= s * pv;
        store_vector(z + i + g * kWidth, zv);
        next_lanes[g] += uv * zv;
      }
    }
    double next[kLanes];
    for (int k = 0; k < kLanes; ++k) next[k] = next_lanes[k / kWidth][k % kWidth];
    auto next_tail = [&](int k) __attribute__((always_inline)) {
      z[i + k] -= s * p[i + k];
      next[k] += u_next[i + k] * z[i + k];
    };
    if (i < n) next_tail(0);
    if (i + 1 < n) next_tail(1);
    if (i + 2 < n) next_tail(2);
    s = sum_lanes(next);
  }
  return y;
}

template <bool Leverage>
double predict_field_sse2(const ReceptiveField& rf, const Eigen::VectorXd& x, double& leverage, FieldScratch& scratch) {
  return predict_field<0, Pair, Leverage>(rf, x, leverage, scratch);
}
// AVX2, with a fixed-size copy for 21 inputs (as update_statistics_avx2).
template <bool Leverage>
__attribute__((target("avx2"))) double predict_field_avx2(const ReceptiveField& rf, const Eigen::VectorXd& x,
                                                          double& leverage, FieldScratch& scratch) {
  if (rf.input_dim() == 21) return predict_field<21, Quad, Leverage>(rf, x, leverage, scratch);
  return predict_field<0, Quad, Leverage>(rf, x, leverage, scratch);
}

}  // namespace

double predict_receptive_field(const ReceptiveField& rf, const Eigen::VectorXd& x, double& leverage,
                               FieldScratch& scratch) {
  // Below kLanes inputs no block runs, and the two copies are the same scalar code.
  if (scratch.use_avx2 && rf.input_dim() >= kLanes) return predict_field_avx2<true>(rf, x, leverage, scratch);
  return predict_field_sse2<true>(rf, x, leverage, scratch);
}

double predict_receptive_field_value(const ReceptiveField& rf, const Eigen::VectorXd& x, FieldScratch& scratch) {
  double unused = 0.0;
  if (scratch.use_avx2 && rf.input_dim() >= kLanes) return predict_field_avx2<false>(rf, x, unused, scratch);
  return predict_field_sse2<false>(rf, x, unused, scratch);
}

double calc_field_noise_variance(const ReceptiveField& rf) {
  const int last = rf.n_reg() - 1;
  return rf.sum_e_cv2(last) / rf.sum_w(last);
}

namespace {

// The three kinds of pass over length-n vectors that update_statistics() makes, each on elements
// [i, i + kWidth) of V (a Pair or a Quad) or on one element (the scalar tails). Element-wise, so
// any vector width rounds the same; the reductions are the caller's. A fused pass runs two of
// them in one loop, the same operations in the same order per element as the separate passes.
// (a) The weighted mean x₀ ← (w_old·x₀ + w·x)/Σλw and the centred input z = x − x₀.
template <class V>
__attribute__((always_inline)) inline void update_mean(const double* x, double* mean_x, double* z, double w_old,
                                                       double w, double inv_w_new, V& zv) {
  V xv, mv;
  load_vector(xv, x);
  load_vector(mv, mean_x);
  const V m = (w_old * mv + w * xv) * inv_w_new;
  store_vector(mean_x, m);
  zv = xv - m;
  store_vector(z, zv);
}
// (b) Projection r's direction statistics sxy ← λ_slow·sxy + w·res·z (u_r before normalising).
template <class V>
__attribute__((always_inline)) inline void update_direction_sums(double* sxy, const V& zv, double lambda_slow,
                                                                 double w_res, V& v) {
  load_vector(v, sxy);
  v = lambda_slow * v + w_res * zv;
  store_vector(sxy, v);
}
// (c) Projection r's normalised direction u = sxy/|sxy|, its loadings' statistics sxs ← λ·sxs + ws·z
// and p = sxs/Σλws²; with Deflate, the next projection's input z − s·p (in zv, and stored).
template <bool Deflate, class V>
__attribute__((always_inline)) inline void update_loadings(double* z, const double* sxy, double* sxs, double* u,
                                                           double* p, double inv_norm, double ws, double inv_ss2,
                                                           double s, double lambda, V& zv) {
  V yv, sv;
  load_vector(zv, z);
  load_vector(yv, sxy);
  load_vector(sv, sxs);
  store_vector(u, yv * inv_norm);
  const V v = lambda * sv + ws * zv;
  store_vector(sxs, v);
  const V pv = v * inv_ss2;
  store_vector(p, pv);
  if (Deflate) {
    zv = zv - s * pv;
    store_vector(z, zv);
  }
}

// One projection's reduction: |sxy|² and sxy·z, element i in lane i mod kLanes.
struct DirectionSums {
  double norm2 = 0.0;
  double dot = 0.0;
};

// Over blocks of kLanes elements (kLanes/kWidth vectors V each, element i in lane i mod kLanes),
// then the at most kLanes − 1 elements left one by one (element i + k in lane k, written out so
// that the partial sums stay in registers): `input(i, zv)` produces the input z at [i, i + width)
// (a mean or a deflation pass, `Width` wide), then (b) updates `sxy` with it and accumulates the
// sums. This is projection r+1's pass (1) fused with what produces its input.
template <class V, class Input, class InputTail>
__attribute__((always_inline)) inline DirectionSums run_direction_pass(int n, double* sxy, const double* z,
                                                                       double lambda_slow, double w_res, Input input,
                                                                       InputTail input_tail) {
  constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
  constexpr int kGroups = kLanes / kWidth;
  V norm2_lanes[kGroups] = {}, dot_lanes[kGroups] = {};
  int i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    for (int g = 0; g < kGroups; ++g) {
      V zv;
      input(i + g * kWidth, zv);
      V v;
      update_direction_sums<V>(sxy + i + g * kWidth, zv, lambda_slow, w_res, v);
      norm2_lanes[g] += v * v;
      dot_lanes[g] += v * zv;
    }
  }
  double norm2_part[kLanes], dot_part[kLanes];
  for (int k = 0; k < kLanes; ++k) {
    norm2_part[k] = norm2_lanes[k / kWidth][k % kWidth];
    dot_part[k] = dot_lanes[k / kWidth][k % kWidth];
  }
  auto tail = [&](int k) __attribute__((always_inline)) {
    input_tail(i + k);
    const double v = lambda_slow * sxy[i + k] + w_res * z[i + k];
    sxy[i + k] = v;
    norm2_part[k] += v * v;
    dot_part[k] += v * z[i + k];
  };
  if (i < n) tail(0);
  if (i + 1 < n) tail(1);
  if (i + 2 < n) tail(2);
  return {sum_lanes(norm2_part), sum_lanes(dot_part)};
}

// The forgetting-weighted sums, means and PLS statistics of update_receptive_field() for one
// sample; leaves s_r, the residuals and 1 − h_r in `scratch`. N > 0 fixes the input dimension at
// compile time (the loops unroll; most of a 2-D field's update went to loop control), N = 0 takes
// it from the field; the same operations in the same order either way.
// V is the vector the loops run on: Pair (SSE2, two per block of kLanes) or Quad (AVX2, one per
// block); either way element i is in lane i mod kLanes, so the same bits. Always inlined, so that
// the AVX2 copy below compiles it, and the helpers above, for AVX2.
// A run is resumable: start() does the sums, the means and projection 0's pass (1), each step()
// one projection's scalar chain and pass (2) fused with the next projection's pass (1), so that
// two fields' runs can alternate step by step (update_statistics_pair) with each field's
// operations in the same order as alone.
template <int N, class V>
struct StatisticsRun {
  const Eigen::VectorXd& x;
  double w;
  ReceptiveField& rf;
  FieldScratch& scratch;
  double lambda;
  double lambda_slow;
  int n_reg;
  int n;
  double* z;
  double res;
  DirectionSums sums;
  int r = 0;

  __attribute__((always_inline)) StatisticsRun(const Eigen::VectorXd& x_in, double w_in, ReceptiveField& rf_in,
                                               FieldScratch& scratch_in)
      : x(x_in),
        w(w_in),
        rf(rf_in),
        scratch(scratch_in),
        lambda(rf_in.lambda),
        lambda_slow(1.0 - (1.0 - rf_in.lambda) / 10.0),  // PLS directions forget more slowly
        n_reg(rf_in.n_reg()),
        n(N > 0 ? N : rf_in.input_dim()),
        z(scratch_in.z.data()) {}

  // Forgetting-weighted sums: Σλw (the weights, for the means and the MSE normalisation) and
  // n_data = Σλ·1, the discounted number of samples each projection has seen (the algorithm counts
  // samples, whatever their activation: a narrow field in 21-D sees small w but must still reach
  // the trust count and the add-projection test); β₀, x₀, z = x − x₀ and projection 0's pass (1).
  __attribute__((always_inline)) void start(double y) {
    const double w_old = lambda * rf.sum_w(0);
    const double inv_w_new = 1.0 / (w_old + w);  // 1/Σλw of projection 0, as stored below
    for (int k = 0; k < n_reg; ++k) {
      rf.sum_w(k) = lambda * rf.sum_w(k) + w;
      rf.n_data(k) = lambda * rf.n_data(k) + 1.0;
    }
    rf.beta0 = (w_old * rf.beta0 + w * y) * inv_w_new;
    double* mean_x = rf.mean_x.data();
    const double* xp = x.data();
    double* zp = z;
    const double wv = w;
    res = y - rf.beta0;
    sums = run_direction_pass<V>(
        n, rf.sxy.col(0).data(), z, lambda_slow, w * res,
        [&](int i, V& zv) __attribute__((always_inline)) {
          update_mean<V>(xp + i, mean_x + i, zp + i, w_old, wv, inv_w_new, zv);
        },
        [&](int i) __attribute__((always_inline)) {
          const double m = (w_old * mean_x[i] + wv * xp[i]) * inv_w_new;
          mean_x[i] = m;
          zp[i] = xp[i] - m;
        });
  }

  // Incremental PLS (Vijayakumar et al. 2005, table 2): each projection regresses the residual
  // left by the previous ones on s_r = u_rᵀz_r and deflates the input by s_r·p_r. Per projection:
  // (1) u_r's statistics with |·|² and ·z accumulated (the previous step or start()), (2) the
  // normalised direction, the loadings and the deflation; one division for 1/|u_r| and one for
  // 1/Σλws_r². Pass (2) of projection r runs in one loop with pass (1) of projection r+1; pass (2)
  // of the last projection does not deflate (nothing reads it). Returns whether a projection is left.
  // The scalar chain of projection r: s_r, the regression, the residual and 1 − h_r.
  double inv_norm;
  double s;
  double ws;
  double inv_ss2;
  __attribute__((always_inline)) void chain() {
    // u_r = 0 while sxy_r = 0 (then 1/√0 = +∞ is not used).
    const double inv_root = 1.0 / std::sqrt(sums.norm2);
    inv_norm = sums.norm2 > 0.0 ? inv_root : 0.0;
    s = sums.dot * inv_norm;
    ws = w * s;
    // The chain's values in locals: stored, never read back (a store and reload on the chain
    // through the two divisions cost a store-forwarding delay per projection).
    const double ss2 = lambda * rf.ss2(r) + ws * s;
    const double sys = lambda * rf.sys(r) + ws * res;
    rf.ss2(r) = ss2;
    rf.sys(r) = sys;
    inv_ss2 = 1.0 / ss2;
    const double beta = sys * inv_ss2;
    rf.beta(r) = beta;
    res -= beta * s;
    scratch.s(r) = s;
    scratch.residual(r) = res;
    scratch.one_minus_h(r) = std::max(1.0 - ws * s * inv_ss2, kMinOneMinusH);
  }
  // Projection r's pass (2), fused with projection r+1's pass (1) unless r is the last.
  __attribute__((always_inline)) bool pass() {
    const double inv_norm = this->inv_norm;
    const double s = this->s;
    const double ws = this->ws;
    const double inv_ss2 = this->inv_ss2;
    const double* sxy = rf.sxy.col(r).data();
    double* sxs = rf.sxs.col(r).data();
    double* u = rf.directions.col(r).data();
    double* p = rf.loadings.col(r).data();
    double* zp = z;
    const double lam = lambda;
    auto loadings_tail = [&](int i, bool deflate) __attribute__((always_inline)) {
      u[i] = sxy[i] * inv_norm;
      const double v = lam * sxs[i] + ws * zp[i];
      sxs[i] = v;
      p[i] = v * inv_ss2;
      if (deflate) zp[i] -= s * p[i];
    };
    if (r + 1 == n_reg) {
      constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
      int i = 0;
      for (; i + kWidth <= n; i += kWidth) {
        V zv;
        update_loadings<false, V>(zp + i, sxy + i, sxs + i, u + i, p + i, inv_norm, ws, inv_ss2, s, lam, zv);
      }
      for (int t = 0; t < kWidth - 1 && i < n; ++t, ++i) loadings_tail(i, false);  // unrolled
      return false;
    }
    sums = run_direction_pass<V>(
        n, rf.sxy.col(r + 1).data(), z, lambda_slow, w * res,
        [&](int i, V& zv) __attribute__((always_inline)) {
          update_loadings<true, V>(zp + i, sxy + i, sxs + i, u + i, p + i, inv_norm, ws, inv_ss2, s, lam, zv);
        },
        [&](int i) __attribute__((always_inline)) { loadings_tail(i, true); });
    ++r;
    return true;
  }
};

template <int N, class V>
__attribute__((always_inline)) inline void update_statistics(const Eigen::VectorXd& x, double y, double w,
                                                             ReceptiveField& rf, FieldScratch& scratch) {
  StatisticsRun<N, V> run(x, w, rf, scratch);
  run.start(y);
  do {
    run.chain();
  } while (run.pass());
}

// Two fields' statistics for the same sample, their runs alternating projection by projection:
// each field's chain through √ and the two divisions waits while the other's passes run. Each
// field's operations are those of update_statistics() in the same order, so the same bits.
template <int N, class V>
__attribute__((always_inline)) inline void update_statistics_pair(const Eigen::VectorXd& x, double y, double w_a,
                                                                  ReceptiveField& rf_a, FieldScratch& scratch_a,
                                                                  double w_b, ReceptiveField& rf_b,
                                                                  FieldScratch& scratch_b) {
  StatisticsRun<N, V> a(x, w_a, rf_a, scratch_a);
  StatisticsRun<N, V> b(x, w_b, rf_b, scratch_b);
  a.start(y);
  b.start(y);
  bool more_a = true;
  bool more_b = true;
  while (more_a && more_b) {
    a.chain();
    b.chain();
    more_a = a.pass();
    more_b = b.pass();
  }
  while (more_a) {
    a.chain();
    more_a = a.pass();
  }
  while (more_b) {
    b.chain();
    more_b = b.pass();
  }
}

// The 21-input update for AVX-512 (F, VL, DQ): the same template on Quad, so the same operations on
// the same lanes; the target gives the compiler 32 vector registers and EVEX forms (what it saves,
// and why blocks of 8 are not used: engine/lwpr/README.md, "AVX-512 on Zen 4").
// AVX-512F has FMA and GCC contracts a·b + c into it under this target, so these copies are
// compiled with fp-contract=off: no FMA, the same roundings as SSE2 and AVX2.
#define ARMFARM_AVX512 target("avx512f,avx512vl,avx512dq"), optimize("fp-contract=off")
__attribute__((ARMFARM_AVX512)) void update_statistics_avx512(const Eigen::VectorXd& x, double y, double w,
                                                             ReceptiveField& rf, FieldScratch& scratch) {
  update_statistics<21, Quad>(x, y, w, rf, scratch);
}
__attribute__((ARMFARM_AVX512)) void update_statistics_pair_avx512(const Eigen::VectorXd& x, double y, double w_a,
                                                                  ReceptiveField& rf_a, FieldScratch& scratch_a,
                                                                  double w_b, ReceptiveField& rf_b,
                                                                  FieldScratch& scratch_b) {
  update_statistics_pair<21, Quad>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
}
#undef ARMFARM_AVX512

// update_statistics<0> (input dimensions above 3) for SSE2 and for AVX2: the same operations in
// the same order on the same lanes, without FMA contraction (AVX2 alone does not enable FMA), so
// the same bits; AVX2 does each block of kLanes in one instruction instead of two. AVX2 also has
// a copy for 21 inputs, the 7-DOF arm's (q, q̇, q̈): its loops unroll and its tails are resolved
// at compile time (12 % fewer instructions per update at the reference point, 3 % less time).
void update_statistics_sse2(const Eigen::VectorXd& x, double y, double w, ReceptiveField& rf, FieldScratch& scratch) {
  update_statistics<0, Pair>(x, y, w, rf, scratch);
}
__attribute__((target("avx2"), noinline)) void update_statistics_avx2_21(const Eigen::VectorXd& x, double y, double w,
                                                                        ReceptiveField& rf, FieldScratch& scratch) {
  update_statistics<21, Quad>(x, y, w, rf, scratch);
}
__attribute__((target("avx2"), noinline)) void update_statistics_avx2_n(const Eigen::VectorXd& x, double y, double w,
                                                                       ReceptiveField& rf, FieldScratch& scratch) {
  update_statistics<0, Quad>(x, y, w, rf, scratch);
}
// The AVX2 entry points only choose (tail calls: none of the copies' stack frames is set up before
// the choice; with the AVX-512 call inside the AVX2 copy's frame the update took 4 % longer).
void update_statistics_avx2(const Eigen::VectorXd& x, double y, double w, ReceptiveField& rf, FieldScratch& scratch) {
  if (rf.input_dim() != 21) return update_statistics_avx2_n(x, y, w, rf, scratch);
  if (scratch.use_avx512) return update_statistics_avx512(x, y, w, rf, scratch);
  update_statistics_avx2_21(x, y, w, rf, scratch);
}
void update_statistics_pair_sse2(const Eigen::VectorXd& x, double y, double w_a, ReceptiveField& rf_a,
                                 FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b, FieldScratch& scratch_b) {
  update_statistics_pair<0, Pair>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
}
__attribute__((target("avx2"), noinline)) void update_statistics_pair_avx2_21(const Eigen::VectorXd& x, double y,
                                                                             double w_a, ReceptiveField& rf_a,
                                                                             FieldScratch& scratch_a, double w_b,
                                                                             ReceptiveField& rf_b,
                                                                             FieldScratch& scratch_b) {
  update_statistics_pair<21, Quad>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
}
__attribute__((target("avx2"), noinline)) void update_statistics_pair_avx2_n(const Eigen::VectorXd& x, double y,
                                                                            double w_a, ReceptiveField& rf_a,
                                                                            FieldScratch& scratch_a, double w_b,
                                                                            ReceptiveField& rf_b,
                                                                            FieldScratch& scratch_b) {
  update_statistics_pair<0, Quad>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
}
void update_statistics_pair_avx2(const Eigen::VectorXd& x, double y, double w_a, ReceptiveField& rf_a,
                                 FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b, FieldScratch& scratch_b) {
  if (rf_a.input_dim() != 21) return update_statistics_pair_avx2_n(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
  if (scratch_a.use_avx512 && scratch_b.use_avx512) {
    return update_statistics_pair_avx512(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
  }
  update_statistics_pair_avx2_21(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
}
}  // namespace

bool has_avx2() {
  static const bool supported = __builtin_cpu_supports("avx2") != 0;
  return supported;
}

bool has_avx512() {
  static const bool supported = __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512vl") != 0 &&
                                __builtin_cpu_supports("avx512dq") != 0;
  return supported;
}

namespace {

void update_field_statistics(const Eigen::VectorXd& x, double y, double w, ReceptiveField& rf, FieldScratch& scratch) {
  switch (rf.input_dim()) {
    case 2:
    case 3:  // on local values (small_field_statistics.cpp), the same bits as update_statistics<2 or 3, Pair>
      if (scratch.small_statistics && update_small_field_statistics(x, y, w, rf, scratch)) break;
      if (rf.input_dim() == 2) {
        update_statistics<2, Pair>(x, y, w, rf, scratch);
      } else {
        update_statistics<3, Pair>(x, y, w, rf, scratch);
      }
      break;
    default:
      if (scratch.use_avx2) {
        update_statistics_avx2(x, y, w, rf, scratch);
      } else {
        update_statistics_sse2(x, y, w, rf, scratch);
      }
      break;
  }
}

// finish_field_update()'s metric part (update_D, past the start rule): the sample's own
// leave-one-out residuals, sum_e2, press_E, the transient multiplier, the metric step and the
// PRESS memory terms.
void update_field_metric(const LwprParams& params, const Eigen::VectorXd& x, double w, ReceptiveField& rf,
                         FieldScratch& scratch) {
  const double lambda = rf.lambda;
  const int n_reg = rf.n_reg();
  const double e = scratch.residual(n_reg - 1);
  for (int r = 0; r < n_reg; ++r) {  // projection r's own leave-one-out residual
    scratch.e_cv(r) = scratch.residual(r) / scratch.one_minus_h(r);
  }
  rf.sum_e2 = lambda * rf.sum_e2 + w * e * e;
  rf.press_E = lambda * rf.press_E + w * scratch.e_cv.head(n_reg).squaredNorm();
  MetricSample sample(scratch.s, scratch.residual, scratch.e_cv);
  sample.w = w;
  scratch.diff = x - rf.center;
  if (rf.diagonal()) {
    sample.q = rf.metric.col(0).dot(scratch.diff.cwiseAbs2());
  } else {
    calc_factor_product(rf.metric_factor, scratch.diff, scratch.md);
    sample.q = scratch.md.squaredNorm();
    sample.md = &scratch.md;  // the metric step's M·(x − c): M is unchanged until then
  }
  sample.W = rf.sum_w(0);
  sample.E = rf.press_E;
  // The library's transient multiplier: small steps while the leave-one-out error is still
  // much larger than the fitted error (a young or changing field).
  const double ratio = rf.sum_e2 / (rf.sum_e_cv2(n_reg - 1) + 1e-10);
  const double transient = std::min(1.0, ratio * ratio * ratio * ratio);
  update_distance_metric(params, scratch.diff, sample, transient, rf, scratch);
  for (int r = 0; r < n_reg; ++r) {
    const double s = scratch.s(r);
    const double e_cv = scratch.e_cv(r);
    const double one_minus_h = scratch.one_minus_h(r);
    rf.press_H(r) = lambda * rf.press_H(r) + w * s * e_cv / one_minus_h;
    rf.press_R(r) = lambda * rf.press_R(r) + w * w * s * s * e_cv * e_cv / one_minus_h;
  }
}

// Which metric step a field's update makes after its leave-one-out sums.
enum class MetricStep { kNone, kSmallFull, kGeneral };

// What update_receptive_field() does after the statistics, in three parts so that a group's metric
// steps can run together: (1) the leave-one-out sums, and which metric step is due; (2) the step
// (update_small_full_field_metric() or update_field_metric()); (3) finish_field_update().
MetricStep update_loo_sums(const LwprParams& params, double w, ReceptiveField& rf, const FieldScratch& scratch) {
  const double lambda = rf.lambda;
  const int n_reg = rf.n_reg();
  // Leave-one-out statistics and the metric update wait until the field has some data: the
  // library's rule waits for n_data > 0.1/(1−λ) (100 samples at λ = 0.999); the early rule also
  // accepts 4·(R+1) samples, a few times the local model's parameter count, so D adapts much
  // earlier. The early rule keeps the online reaching job's learning curve; the library's is more
  // accurate on the side-by-side points (README, "Start rule").
  const double library_n = 0.1 / std::max(1.0 - lambda, 1e-12);
  const double ready_n = params.loo_start == LooStart::kEarly ? std::min(library_n, 4.0 * (n_reg + 1)) : library_n;
  if (rf.n_data(0) > ready_n) {
    // Leave-one-out error of the model with r+1 projections, for the add_threshold rule.
    double leverage_r = 0.0;
    for (int r = 0; r < n_reg; ++r) {
      leverage_r += 1.0 - scratch.one_minus_h(r);
      const double e_cv = scratch.residual(r) / std::max(1.0 - leverage_r, kMinOneMinusH);
      rf.sum_e_cv2(r) = lambda * rf.sum_e_cv2(r) + w * e_cv * e_cv;
    }
    // The rest feeds the metric step only: without update_D it is never read (a model's
    // parameters are fixed, in its file too), so sum_e2, press_E, press_H and press_R stay 0.
    if (params.update_D) {
      // The fixed-size step gives the same bits as update_field_metric().
      return rf.input_dim() <= 3 && !rf.diagonal() && scratch.small_full_metric ? MetricStep::kSmallFull
                                                                                 : MetricStep::kGeneral;
    }
  }
  return MetricStep::kNone;
}

// (3) The add-projection test, λ's annealing and the trust flag.
void finish_field_update(const LwprParams& params, double trust_n_data, ReceptiveField& rf) {
  const double lambda = rf.lambda;
  const int n_reg = rf.n_reg();

  // Add a projection when the last one still cut the leave-one-out error by enough and has seen
  // (nearly) all the data the field has.
  // The sample-count test, which needs no division, first: it fails until the last projection
  // has seen 0.5/(1−λ) samples (500 at λ = 0.999), so the three divisions are rarely evaluated.
  if (params.add_proj && n_reg >= 2 && n_reg < rf.input_dim() && rf.n_data(n_reg - 1) * (1.0 - lambda) > 0.5 &&
      rf.n_data(n_reg - 1) / rf.n_data(0) > 0.99) {
    const double mse_last = rf.sum_e_cv2(n_reg - 1) / rf.sum_w(n_reg - 1) + 1e-10;
    const double mse_prev = rf.sum_e_cv2(n_reg - 2) / rf.sum_w(n_reg - 2) + 1e-10;
    if (mse_last / mse_prev < params.add_threshold) add_projection(params, rf);
  }

  rf.lambda = params.tau_lambda * lambda + (1.0 - params.tau_lambda) * params.final_lambda;
  rf.trustworthy = rf.n_data(0) >= trust_n_data;
}

// Two different fields' statistics for the same sample, interleaved where their sizes allow.
void update_field_statistics_pair(const Eigen::VectorXd& x, double y, double w_a, ReceptiveField& rf_a,
                                  FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b, FieldScratch& scratch_b) {
  const int n = rf_a.input_dim();
  const bool small = n <= 3 && scratch_a.small_statistics && scratch_b.small_statistics;
  if (small && update_small_field_statistics_pair(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b)) {
    // n = 2 or 3: both fields' statistics on local values, their scalar steps as pairs of doubles
  } else if (n > 3 && rf_b.input_dim() == n && scratch_a.use_avx2 == scratch_b.use_avx2) {
    if (scratch_a.use_avx2) {
      update_statistics_pair_avx2(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
    } else {
      update_statistics_pair_sse2(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
    }
  } else {
    update_field_statistics(x, y, w_a, rf_a, scratch_a);
    update_field_statistics(x, y, w_b, rf_b, scratch_b);
  }
}

}  // namespace

void update_receptive_field(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, double y,
                            double w, ReceptiveField& rf, FieldScratch& scratch) {
  ReceptiveField* fields[1] = {&rf};
  FieldScratch* scratches[1] = {&scratch};
  update_receptive_fields(params, trust_n_data, x, y, 1, &w, fields, scratches);
}

static_assert(kFieldGroup <= kMetricLanes, "a group's metric steps fit one call");

void update_receptive_fields(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, double y,
                             int count, const double* w, ReceptiveField* const* rf, FieldScratch* const* scratch) {
  if (count < 1 || count > kFieldGroup) {
    throw std::invalid_argument("update_receptive_fields: 1 to " + std::to_string(kFieldGroup) + " fields");
  }
  int k = 0;
  bool small = count == 4 && rf[0]->input_dim() <= 3;
  for (int j = 0; j < count; ++j) small = small && scratch[j]->small_statistics;
  if (small && update_small_field_statistics_four(x, y, w, rf, scratch)) k = count;  // n = 2 or 3, one R
  for (; k + 1 < count; k += 2) {
    update_field_statistics_pair(x, y, w[k], *rf[k], *scratch[k], w[k + 1], *rf[k + 1], *scratch[k + 1]);
  }
  if (k < count) update_field_statistics(x, y, w[k], *rf[k], *scratch[k]);
  MetricStep due[kFieldGroup];
  for (k = 0; k < count; ++k) due[k] = update_loo_sums(params, w[k], *rf[k], *scratch[k]);
  // The fixed-size steps of fields with the same n and R together (fields are independent, so the
  // order of their steps does not matter), the general ones one by one.
  for (k = 0; k < count; ++k) {
    if (due[k] == MetricStep::kGeneral) update_field_metric(params, x, w[k], *rf[k], *scratch[k]);
    if (due[k] != MetricStep::kSmallFull) continue;
    double group_w[kFieldGroup];
    const FieldScratch* group_scratch[kFieldGroup];
    ReceptiveField* group_rf[kFieldGroup];
    int size = 0;
    for (int j = k; j < count; ++j) {
      if (due[j] != MetricStep::kSmallFull || rf[j]->input_dim() != rf[k]->input_dim() ||
          rf[j]->n_reg() != rf[k]->n_reg()) {
        continue;
      }
      group_w[size] = w[j];
      group_scratch[size] = scratch[j];
      group_rf[size] = rf[j];
      ++size;
      due[j] = MetricStep::kNone;  // taken
    }
    update_small_full_field_metrics(params, x, size, group_w, group_scratch, group_rf);
  }
  for (k = 0; k < count; ++k) finish_field_update(params, trust_n_data, *rf[k]);
}

void update_receptive_field_pair(const LwprParams& params, double trust_n_data, const Eigen::VectorXd& x, double y,
                                 double w_a, ReceptiveField& rf_a, FieldScratch& scratch_a, double w_b,
                                 ReceptiveField& rf_b, FieldScratch& scratch_b) {
  const double w[2] = {w_a, w_b};
  ReceptiveField* rf[2] = {&rf_a, &rf_b};
  FieldScratch* scratch[2] = {&scratch_a, &scratch_b};
  update_receptive_fields(params, trust_n_data, x, y, 2, w, rf, scratch);
}

}  // namespace armfarm::lwpr
