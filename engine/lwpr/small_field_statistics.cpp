// The PLS statistics of a field of 2 or 3 inputs on local values (small_field_statistics.hpp).
#include "engine/lwpr/small_field_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <emmintrin.h>
#include <type_traits>
#include <utility>

namespace armfarm::lwpr {
namespace {

// These mirror the general field update (receptive_field.cpp, StatisticsRun): the same floor of
// 1 − h (kMinOneMinusH), and reductions in four partial sums, element i in partial sum i mod 4 (here i < 4, so
// element i in partial sum i), added as (p0 + p1) + (p2 + p3), the unused partial sums 0.
constexpr int kLanes = 4;
inline double sum_lanes(const double (&part)[kLanes]) { return (part[0] + part[1]) + (part[2] + part[3]); }

// f(std::integral_constant<int, r>) for r = 0..R−1, in order.
template <class F, int... R>
__attribute__((always_inline)) inline void for_each_projection(F&& f, std::integer_sequence<int, R...>) {
  (f(std::integral_constant<int, R>{}), ...);
}
template <int R, class F>
__attribute__((always_inline)) inline void for_each_projection(F&& f) {
  for_each_projection(f, std::make_integer_sequence<int, R>{});
}

// Two doubles operated on lane by lane (a GCC/Clang vector extension, one SSE2 register), as the
// general code's Pair: elements 0 and 1 of every length-N vector; element 2 of N = 3 is a scalar.
// Element-wise arithmetic on them rounds exactly as the scalar code. Loads and stores through
// references (a vector passed by value can change the call ABI between builds).
typedef double Pair __attribute__((vector_size(2 * sizeof(double))));
__attribute__((always_inline)) inline void load_pair(Pair& v, const double* from) { std::memcpy(&v, from, sizeof v); }
__attribute__((always_inline)) inline void store_pair(double* to, const Pair& v) { std::memcpy(to, &v, sizeof v); }

// A length-N vector of locals: elements 0–1 as a pair, element 2 (N = 3) alone.
template <int N>
struct Small {
  static constexpr bool kTail = N == 3;
  Pair head;
  double tail = 0.0;
  __attribute__((always_inline)) void load(const double* from) {
    load_pair(head, from);
    if (kTail) tail = from[2];
  }
  __attribute__((always_inline)) void store(double* to) const {
    store_pair(to, head);
    if (kTail) to[2] = tail;
  }
};

// a[k] ← λ·a[k] + add for k < K (the forgetting-weighted sums Σλw and Σλ·1 of the K projections).
template <int K>
__attribute__((always_inline)) inline void forget(double* a, double lambda, double add) {
  double old[K];
  for (int k = 0; k < K; ++k) old[k] = a[k];
  int k = 0;
  if (K >= 2) {
    Pair v;
    load_pair(v, old);
    const Pair updated = lambda * v + add;
    store_pair(a, updated);
    k = 2;
  }
  for (; k < K; ++k) a[k] = lambda * old[k] + add;
}

// Projection r's direction statistics before the reduction: v = λ_slow·sxy + w·res·z (stored) and
// the partial sums of |v|² and v·z, element i in partial sum i (0 + the product; partial sum 2 is 0
// for N = 2, partial sum 3 always).
struct Partials {
  Pair norm2_head;
  Pair dot_head;
  double norm2_tail;
  double dot_tail;
};
// One field's (p0 + p1) + (p2 + p3).
__attribute__((always_inline)) inline double reduce(const Pair& head, double tail) {
  const double part[kLanes] = {head[0], head[1], tail, 0.0};
  return sum_lanes(part);
}
// Two fields' (p0 + p1) + (p2 + p3), field a in lane 0 and b in lane 1: the same additions.
__attribute__((always_inline)) inline Pair reduce_both(const Pair& head_a, double tail_a, const Pair& head_b,
                                                       double tail_b) {
  const Pair p0 = {head_a[0], head_b[0]};
  const Pair p1 = {head_a[1], head_b[1]};
  const Pair p2 = {tail_a, tail_b};
  const Pair p3 = {0.0, 0.0};
  return (p0 + p1) + (p2 + p3);
}

// One field's update for one sample, N inputs: the input residual z, the output residual and the
// chain's values in locals. start() is the general code's start() (the sums, β₀, the means, z and
// projection 0's direction statistics), chain(r) its chain() for projection r, pass<Last>(r) its
// pass(): projection r's direction, loadings and (unless Last) the deflation, with projection
// r+1's direction statistics. Each element's operations are the general code's in the same order.
// Every array is read into locals before the stores, so the compiler needs no aliasing checks.
// BothRuns below runs the scalar steps of two fields at once.
template <int N>
struct SmallRun {
  double w;
  ReceptiveField& rf;
  FieldScratch& scratch;
  double lambda;
  double lambda_slow;
  Small<N> z;
  double res;
  double norm2;  // |sxy_r|² and sxy_r·z of the projection whose chain runs next
  double dot;
  double inv_norm;
  double s;
  double ws;
  double inv_ss2;

  __attribute__((always_inline)) SmallRun(double w_in, ReceptiveField& rf_in, FieldScratch& scratch_in)
      : w(w_in), rf(rf_in), scratch(scratch_in), lambda(rf_in.lambda) {}

  __attribute__((always_inline)) Partials direction_partials(double* sxy, const Small<N>& old, double w_res) {
    Small<N> v;
    v.head = lambda_slow * old.head + w_res * z.head;
    const Pair zero = {0.0, 0.0};
    Partials out{zero + v.head * v.head, zero + v.head * z.head, 0.0, 0.0};
    if (Small<N>::kTail) {
      v.tail = lambda_slow * old.tail + w_res * z.tail;
      out.norm2_tail += v.tail * v.tail;
      out.dot_tail += v.tail * z.tail;
    }
    v.store(sxy);
    return out;
  }

  // start()'s element-wise part, given its scalars: the sums, the means, z and projection 0's
  // direction statistics. All reads come before the stores.
  template <int R>
  __attribute__((always_inline)) Partials start_elements(const double* x, double w_old, double inv_w_new,
                                                         double w_res) {
    double* mean_x = rf.mean_x.data();
    double* sxy = rf.sxy.data();
    Small<N> xs, mean_old, sxy_old;
    xs.load(x);
    mean_old.load(mean_x);
    sxy_old.load(sxy);
    forget<R>(rf.sum_w.data(), lambda, w);
    forget<R>(rf.n_data.data(), lambda, 1.0);
    Small<N> m;
    m.head = (w_old * mean_old.head + w * xs.head) * inv_w_new;
    z.head = xs.head - m.head;
    if (Small<N>::kTail) {
      m.tail = (w_old * mean_old.tail + w * xs.tail) * inv_w_new;
      z.tail = xs.tail - m.tail;
    }
    m.store(mean_x);
    return direction_partials(sxy, sxy_old, w_res);
  }

  template <int R>
  __attribute__((always_inline)) void start(const double* x, double y) {
    lambda_slow = 1.0 - (1.0 - lambda) / 10.0;  // PLS directions forget more slowly
    const double w_old = lambda * rf.sum_w.data()[0];
    const double inv_w_new = 1.0 / (w_old + w);
    const double beta0 = (w_old * rf.beta0 + w * y) * inv_w_new;
    rf.beta0 = beta0;
    res = y - beta0;
    const Partials sums = start_elements<R>(x, w_old, inv_w_new, w * res);
    norm2 = reduce(sums.norm2_head, sums.norm2_tail);
    dot = reduce(sums.dot_head, sums.dot_tail);
  }

  __attribute__((always_inline)) void chain(int r) {
    // u_r = 0 while sxy_r = 0 (then 1/√0 = +∞ is not used).
    const double inv_root = 1.0 / std::sqrt(norm2);
    inv_norm = norm2 > 0.0 ? inv_root : 0.0;
    s = dot * inv_norm;
    ws = w * s;
    const double ss2 = lambda * rf.ss2.data()[r] + ws * s;
    const double sys = lambda * rf.sys.data()[r] + ws * res;
    rf.ss2.data()[r] = ss2;
    rf.sys.data()[r] = sys;
    inv_ss2 = 1.0 / ss2;
    const double beta = sys * inv_ss2;
    rf.beta.data()[r] = beta;
    res -= beta * s;
    scratch.s.data()[r] = s;
    scratch.residual.data()[r] = res;
    scratch.one_minus_h.data()[r] = std::max(1.0 - ws * s * inv_ss2, kMinOneMinusH);
  }

  // pass()'s element-wise part; with Last, nothing more (the partials are not used), otherwise
  // projection r+1's direction statistics, whose reduction is the caller's.
  template <bool Last>
  __attribute__((always_inline)) Partials pass_elements(int r) {
    double* sxy_next = rf.sxy.data() + (r + 1) * N;  // read only unless Last
    Small<N> sxy_r, sxs_old, sxy_next_old;
    sxy_r.load(rf.sxy.data() + r * N);
    sxs_old.load(rf.sxs.data() + r * N);
    if (!Last) sxy_next_old.load(sxy_next);
    Small<N> u, v, p;
    u.head = sxy_r.head * inv_norm;
    v.head = lambda * sxs_old.head + ws * z.head;
    p.head = v.head * inv_ss2;
    if (!Last) z.head = z.head - s * p.head;
    if (Small<N>::kTail) {
      u.tail = sxy_r.tail * inv_norm;
      v.tail = lambda * sxs_old.tail + ws * z.tail;
      p.tail = v.tail * inv_ss2;
      if (!Last) z.tail -= s * p.tail;
    }
    u.store(rf.directions.data() + r * N);
    v.store(rf.sxs.data() + r * N);
    p.store(rf.loadings.data() + r * N);
    if (Last) return Partials{};
    return direction_partials(sxy_next, sxy_next_old, w * res);
  }

  template <bool Last>
  __attribute__((always_inline)) void pass(int r) {
    const Partials sums = pass_elements<Last>(r);
    if (!Last) {
      norm2 = reduce(sums.norm2_head, sums.norm2_tail);
      dot = reduce(sums.dot_head, sums.dot_tail);
    }
  }
};

// Two fields' scalar steps at once, field a in lane 0 and field b in lane 1 of pairs: each lane's
// operations are the single field's (divpd and sqrtpd round each lane as divsd and sqrtsd; the
// selects are chain()'s conditionals lane by lane), so the same bits with one instruction for both.
template <int N>
struct BothRuns {
  SmallRun<N>& a;
  SmallRun<N>& b;
  Pair norm2;  // |sxy_r|² and sxy_r·z of both fields, for chain()
  Pair dot;

  template <int Ra, int Rb>
  __attribute__((always_inline)) void start(const double* x, double y) {
    const Pair one = {1.0, 1.0};
    const Pair lambda = {a.lambda, b.lambda};
    const Pair w = {a.w, b.w};
    const Pair lambda_slow = one - (one - lambda) / 10.0;
    a.lambda_slow = lambda_slow[0];
    b.lambda_slow = lambda_slow[1];
    const Pair sum_w0 = {a.rf.sum_w.data()[0], b.rf.sum_w.data()[0]};
    const Pair beta0_old = {a.rf.beta0, b.rf.beta0};
    const Pair w_old = lambda * sum_w0;
    const Pair inv_w_new = one / (w_old + w);
    const Pair beta0 = (w_old * beta0_old + w * y) * inv_w_new;
    a.rf.beta0 = beta0[0];
    b.rf.beta0 = beta0[1];
    const Pair res = y - beta0;
    a.res = res[0];
    b.res = res[1];
    const Pair w_res = w * res;
    const Partials sums_a = a.template start_elements<Ra>(x, w_old[0], inv_w_new[0], w_res[0]);
    const Partials sums_b = b.template start_elements<Rb>(x, w_old[1], inv_w_new[1], w_res[1]);
    norm2 = reduce_both(sums_a.norm2_head, sums_a.norm2_tail, sums_b.norm2_head, sums_b.norm2_tail);
    dot = reduce_both(sums_a.dot_head, sums_a.dot_tail, sums_b.dot_head, sums_b.dot_tail);
  }

  __attribute__((always_inline)) void chain(int r) {
    const Pair zero = {0.0, 0.0};
    const Pair one = {1.0, 1.0};
    const Pair w = {a.w, b.w};
    const Pair lambda = {a.lambda, b.lambda};
    const Pair res_old = {a.res, b.res};
    const Pair inv_root = one / static_cast<Pair>(_mm_sqrt_pd(static_cast<__m128d>(norm2)));
    const Pair inv_norm = norm2 > zero ? inv_root : zero;
    const Pair s = dot * inv_norm;
    const Pair ws = w * s;
    const Pair ss2_old = {a.rf.ss2.data()[r], b.rf.ss2.data()[r]};
    const Pair sys_old = {a.rf.sys.data()[r], b.rf.sys.data()[r]};
    const Pair ss2 = lambda * ss2_old + ws * s;
    const Pair sys = lambda * sys_old + ws * res_old;
    a.rf.ss2.data()[r] = ss2[0];
    b.rf.ss2.data()[r] = ss2[1];
    a.rf.sys.data()[r] = sys[0];
    b.rf.sys.data()[r] = sys[1];
    const Pair inv_ss2 = one / ss2;
    const Pair beta = sys * inv_ss2;
    a.rf.beta.data()[r] = beta[0];
    b.rf.beta.data()[r] = beta[1];
    const Pair res = res_old - beta * s;
    a.scratch.s.data()[r] = s[0];
    b.scratch.s.data()[r] = s[1];
    a.scratch.residual.data()[r] = res[0];
    b.scratch.residual.data()[r] = res[1];
    const Pair floor = {kMinOneMinusH, kMinOneMinusH};
    const Pair one_minus_h = one - ws * s * inv_ss2;
    const Pair kept = one_minus_h < floor ? floor : one_minus_h;  // std::max(one_minus_h, floor)
    a.scratch.one_minus_h.data()[r] = kept[0];
    b.scratch.one_minus_h.data()[r] = kept[1];
    a.inv_norm = inv_norm[0];
    b.inv_norm = inv_norm[1];
    a.s = s[0];
    b.s = s[1];
    a.ws = ws[0];
    b.ws = ws[1];
    a.inv_ss2 = inv_ss2[0];
    b.inv_ss2 = inv_ss2[1];
    a.res = res[0];
    b.res = res[1];
  }

  // Both fields' pass() of a projection that is neither's last.
  __attribute__((always_inline)) void pass(int r) {
    const Partials sums_a = a.template pass_elements<false>(r);
    const Partials sums_b = b.template pass_elements<false>(r);
    norm2 = reduce_both(sums_a.norm2_head, sums_a.norm2_tail, sums_b.norm2_head, sums_b.norm2_tail);
    dot = reduce_both(sums_a.dot_head, sums_a.dot_tail, sums_b.dot_head, sums_b.dot_tail);
  }
};

template <int N, int R>
__attribute__((always_inline)) inline void run_single(const double* x, double y, double w, ReceptiveField& rf,
                                                      FieldScratch& scratch) {
  SmallRun<N> run(w, rf, scratch);
  run.template start<R>(x, y);
  for_each_projection<R>([&](auto r) __attribute__((always_inline)) {
    run.chain(r);
    run.template pass<r + 1 == R>(r);
  });
}

// Two fields in lockstep: while both have projection r, their scalar steps run as pairs
// (BothRuns), and while both have projection r+1 their passes' reductions too; past the shorter
// field's last projection the other runs alone.
template <int N, int Ra, int Rb>
__attribute__((always_inline)) inline void run_pair(const double* x, double y, double w_a, ReceptiveField& rf_a,
                                                    FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b,
                                                    FieldScratch& scratch_b) {
  SmallRun<N> a(w_a, rf_a, scratch_a);
  SmallRun<N> b(w_b, rf_b, scratch_b);
  BothRuns<N> both{a, b, {}, {}};
  both.template start<Ra, Rb>(x, y);
  for_each_projection<(Ra > Rb ? Ra : Rb)>([&](auto r) __attribute__((always_inline)) {
    if constexpr (r < Ra && r < Rb) {
      both.chain(r);  // both fields' sums are pairs: from start() or both's pass of r − 1
    } else if constexpr (r < Ra) {
      a.chain(r);
    } else {
      b.chain(r);
    }
    if constexpr (r + 1 < Ra && r + 1 < Rb) {
      both.pass(r);
    } else {
      if constexpr (r < Ra) a.template pass<r + 1 == Ra>(r);
      if constexpr (r < Rb) b.template pass<r + 1 == Rb>(r);
    }
  });
}

// Four fields of the same R as two pairs in lockstep: both pairs' scalar steps (BothRuns), then
// both pairs' passes, projection by projection, so that one pair's chain through √ and the
// divisions overlaps the other's. Each field's operations are those it runs alone, in order.
template <int N, int R>
__attribute__((always_inline)) inline void run_two_pairs(const double* x, double y, const double* w,
                                                         ReceptiveField* const* rf, FieldScratch* const* scratch) {
  SmallRun<N> a(w[0], *rf[0], *scratch[0]);
  SmallRun<N> b(w[1], *rf[1], *scratch[1]);
  SmallRun<N> c(w[2], *rf[2], *scratch[2]);
  SmallRun<N> d(w[3], *rf[3], *scratch[3]);
  BothRuns<N> ab{a, b, {}, {}};
  BothRuns<N> cd{c, d, {}, {}};
  ab.template start<R, R>(x, y);
  cd.template start<R, R>(x, y);
  for_each_projection<R>([&](auto r) __attribute__((always_inline)) {
    ab.chain(r);
    cd.chain(r);
    if constexpr (r + 1 < R) {
      ab.pass(r);
      cd.pass(r);
    } else {
      a.template pass<true>(r);
      b.template pass<true>(r);
      c.template pass<true>(r);
      d.template pass<true>(r);
    }
  });
}

template <int N>
__attribute__((always_inline)) inline bool dispatch_two_pairs(const double* x, double y, const double* w,
                                                              ReceptiveField* const* rf, FieldScratch* const* scratch) {
  const int r = rf[0]->n_reg();
  for (int k = 1; k < 4; ++k) {
    if (rf[k]->n_reg() != r) return false;
  }
  switch (r) {
    case 1: run_two_pairs<N, 1>(x, y, w, rf, scratch); return true;
    case 2: run_two_pairs<N, 2>(x, y, w, rf, scratch); return true;
    case 3:
      if constexpr (N >= 3) {
        run_two_pairs<N, 3>(x, y, w, rf, scratch);
        return true;
      }
      return false;
    default: return false;
  }
}

template <int N>
__attribute__((always_inline)) inline bool dispatch_single(const double* x, double y, double w, ReceptiveField& rf,
                                                           FieldScratch& scratch) {
  switch (rf.n_reg()) {
    case 1: run_single<N, 1>(x, y, w, rf, scratch); return true;
    case 2: run_single<N, 2>(x, y, w, rf, scratch); return true;
    case 3:
      if constexpr (N >= 3) {
        run_single<N, 3>(x, y, w, rf, scratch);
        return true;
      }
      return false;
    default: return false;
  }
}

template <int N, int Ra>
__attribute__((always_inline)) inline bool dispatch_pair_b(const double* x, double y, double w_a, ReceptiveField& rf_a,
                                                           FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b,
                                                           FieldScratch& scratch_b) {
  switch (rf_b.n_reg()) {
    case 1: run_pair<N, Ra, 1>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b); return true;
    case 2: run_pair<N, Ra, 2>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b); return true;
    case 3:
      if constexpr (N >= 3) {
        run_pair<N, Ra, 3>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
        return true;
      }
      return false;
    default: return false;
  }
}

template <int N>
__attribute__((always_inline)) inline bool dispatch_pair(const double* x, double y, double w_a, ReceptiveField& rf_a,
                                                         FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b,
                                                         FieldScratch& scratch_b) {
  const int r_b = rf_b.n_reg();
  if (r_b < 1 || r_b > N) return false;
  switch (rf_a.n_reg()) {
    case 1: return dispatch_pair_b<N, 1>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
    case 2: return dispatch_pair_b<N, 2>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
    case 3:
      if constexpr (N >= 3) return dispatch_pair_b<N, 3>(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
      return false;
    default: return false;
  }
}

// Each (n, R) compiled twice: for SSE2 and for AVX2 (target("avx2") without FMA: the same
// roundings; the three-operand encodings save register copies).
bool small_statistics_sse2(const Eigen::VectorXd& x, double y, double w, ReceptiveField& rf, FieldScratch& scratch) {
  if (rf.input_dim() == 2) return dispatch_single<2>(x.data(), y, w, rf, scratch);
  return dispatch_single<3>(x.data(), y, w, rf, scratch);
}
__attribute__((target("avx2"))) bool small_statistics_avx2(const Eigen::VectorXd& x, double y, double w,
                                                           ReceptiveField& rf, FieldScratch& scratch) {
  if (rf.input_dim() == 2) return dispatch_single<2>(x.data(), y, w, rf, scratch);
  return dispatch_single<3>(x.data(), y, w, rf, scratch);
}
bool small_statistics_pair_sse2(const Eigen::VectorXd& x, double y, double w_a, ReceptiveField& rf_a,
                                FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b, FieldScratch& scratch_b) {
  if (rf_a.input_dim() == 2) return dispatch_pair<2>(x.data(), y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
  return dispatch_pair<3>(x.data(), y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
}
__attribute__((target("avx2"))) bool small_statistics_pair_avx2(const Eigen::VectorXd& x, double y, double w_a,
                                                                ReceptiveField& rf_a, FieldScratch& scratch_a,
                                                                double w_b, ReceptiveField& rf_b,
                                                                FieldScratch& scratch_b) {
  if (rf_a.input_dim() == 2) return dispatch_pair<2>(x.data(), y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
  return dispatch_pair<3>(x.data(), y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
}

bool small_statistics_four_sse2(const Eigen::VectorXd& x, double y, const double* w, ReceptiveField* const* rf,
                                FieldScratch* const* scratch) {
  if (rf[0]->input_dim() == 2) return dispatch_two_pairs<2>(x.data(), y, w, rf, scratch);
  return dispatch_two_pairs<3>(x.data(), y, w, rf, scratch);
}
__attribute__((target("avx2"))) bool small_statistics_four_avx2(const Eigen::VectorXd& x, double y, const double* w,
                                                                ReceptiveField* const* rf,
                                                                FieldScratch* const* scratch) {
  if (rf[0]->input_dim() == 2) return dispatch_two_pairs<2>(x.data(), y, w, rf, scratch);
  return dispatch_two_pairs<3>(x.data(), y, w, rf, scratch);
}

}  // namespace

bool update_small_field_statistics_four(const Eigen::VectorXd& x, double y, const double* w, ReceptiveField* const* rf,
                                        FieldScratch* const* scratch) {
  const int n = rf[0]->input_dim();
  if (n != 2 && n != 3) return false;
  bool avx2 = true;
  for (int k = 0; k < 4; ++k) {
    if (rf[k]->input_dim() != n) return false;
    avx2 = avx2 && scratch[k]->use_avx2;
  }
  if (avx2) return small_statistics_four_avx2(x, y, w, rf, scratch);
  return small_statistics_four_sse2(x, y, w, rf, scratch);
}

bool update_small_field_statistics(const Eigen::VectorXd& x, double y, double w, ReceptiveField& rf,
                                   FieldScratch& scratch) {
  const int n = rf.input_dim();
  if (n != 2 && n != 3) return false;
  if (scratch.use_avx2) return small_statistics_avx2(x, y, w, rf, scratch);
  return small_statistics_sse2(x, y, w, rf, scratch);
}

bool update_small_field_statistics_pair(const Eigen::VectorXd& x, double y, double w_a, ReceptiveField& rf_a,
                                        FieldScratch& scratch_a, double w_b, ReceptiveField& rf_b,
                                        FieldScratch& scratch_b) {
  const int n = rf_a.input_dim();
  if ((n != 2 && n != 3) || rf_b.input_dim() != n) return false;
  if (scratch_a.use_avx2 && scratch_b.use_avx2) {
    return small_statistics_pair_avx2(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
  }
  return small_statistics_pair_sse2(x, y, w_a, rf_a, scratch_a, w_b, rf_b, scratch_b);
}

}  // namespace armfarm::lwpr
