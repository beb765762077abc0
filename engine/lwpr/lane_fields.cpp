// Lane fields: packing an output's copies into lane blocks and back, projections, prediction.
#include "engine/lwpr/lane_fields.hpp"

#include <algorithm>
#include <cstring>

namespace armfarm::lwpr {
namespace {

// Whether a and b have the same shape and the same bits (NaN and −0 included).
template <class A>
bool same_bits(const A& a, const A& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

constexpr int kL = kOutputLanes;

// Every per-projection array of a block, and every per-projection n-vector array, for loops over all of them.
template <class F>
void for_each_projection_array(LaneBlock& b, F f) {
  for (std::vector<double>* v : {&b.sum_w, &b.n_data, &b.ss2, &b.sys, &b.beta, &b.sum_e_cv2, &b.press_H, &b.press_R}) {
    f(*v);
  }
}
template <class F>
void for_each_vector_array(LaneBlock& b, F f) {
  for (std::vector<double>* v : {&b.sxy, &b.sxs, &b.directions, &b.loadings}) f(*v);
}

// Grows the block's arrays to hold `projections` projections (zeros).
void reserve_projections(LaneBlock& b, int n, int projections) {
  if (projections <= b.max_reg) return;
  const auto count = static_cast<std::size_t>(projections) * kL;
  for_each_projection_array(b, [&](std::vector<double>& v) { v.resize(count, 0.0); });
  for_each_vector_array(b, [&](std::vector<double>& v) { v.resize(count * static_cast<std::size_t>(n), 0.0); });
  b.max_reg = projections;
}

}  // namespace

void LaneScratch::resize(int n) {
  const auto count = static_cast<std::size_t>(std::max(n, 1)) * kL;
  z.assign(count, 0.0);
  s.assign(count, 0.0);
  residual.assign(count, 0.0);
  one_minus_h.assign(count, 0.0);
  y.assign(kL, 0.0);
}

bool lane_copies_agree(const std::vector<const ReceptiveField*>& copies) {
  if (copies.empty()) return false;
  const ReceptiveField& a = *copies[0];
  for (const ReceptiveField* c : copies) {
    const ReceptiveField& b = *c;
    if (b.n_reg() < 1 || a.n_reg() < 1) return false;
    if (!same_bits(a.center, b.center) || !same_bits(a.metric_factor, b.metric_factor) ||
        !same_bits(a.metric, b.metric) || !same_bits(a.log_alpha, b.log_alpha) ||
        !same_bits(a.meta_trace, b.meta_trace) || !same_bits(a.lambda, b.lambda) || !same_bits(a.mean_x, b.mean_x) ||
        a.trustworthy != b.trustworthy || !same_bits(a.sum_w(0), b.sum_w(0)) || !same_bits(a.n_data(0), b.n_data(0))) {
      return false;
    }
  }
  return true;
}

LaneField pack_lane_field(const std::vector<const ReceptiveField*>& copies) {
  const ReceptiveField& first = *copies.at(0);
  const int n = first.input_dim();
  LaneField f;
  f.center = first.center;
  f.metric_factor = first.metric_factor;
  f.metric = first.metric;
  f.log_alpha = first.log_alpha;
  f.meta_trace = first.meta_trace;
  f.lambda = first.lambda;
  f.mean_x = first.mean_x;
  f.trustworthy = first.trustworthy;
  f.n_out = static_cast<int>(copies.size());
  f.blocks.resize((copies.size() + kL - 1) / kL);
  for (int o = 0; o < f.n_out; ++o) {
    const ReceptiveField& rf = *copies[o];
    LaneBlock& b = f.blocks[o / kL];
    const int l = o % kL;
    const int R = rf.n_reg();
    reserve_projections(b, n, R);
    b.n_reg[l] = R;
    b.n_reg_lanes[l] = R;
    b.beta0[l] = rf.beta0;
    b.sum_e2[l] = rf.sum_e2;
    b.press_E[l] = rf.press_E;
    for (int r = 0; r < R; ++r) {
      const std::size_t k = static_cast<std::size_t>(r) * kL + l;
      b.sum_w[k] = rf.sum_w(r);
      b.n_data[k] = rf.n_data(r);
      b.ss2[k] = rf.ss2(r);
      b.sys[k] = rf.sys(r);
      b.beta[k] = rf.beta(r);
      b.sum_e_cv2[k] = rf.sum_e_cv2(r);
      b.press_H[k] = rf.press_H(r);
      b.press_R[k] = rf.press_R(r);
      for (int i = 0; i < n; ++i) {
        const std::size_t e = (static_cast<std::size_t>(r) * n + i) * kL + l;
        b.sxy[e] = rf.sxy(i, r);
        b.sxs[e] = rf.sxs(i, r);
        b.directions[e] = rf.directions(i, r);
        b.loadings[e] = rf.loadings(i, r);
      }
    }
  }
  return f;
}

ReceptiveField unpack_lane_field(const LaneField& f, int output) {
  const int n = f.input_dim();
  const LaneBlock& b = f.blocks.at(output / kL);
  const int l = output % kL;
  const int R = b.n_reg[l];
  ReceptiveField rf;
  rf.center = f.center;
  rf.metric_factor = f.metric_factor;
  rf.metric = f.metric;
  rf.log_alpha = f.log_alpha;
  rf.meta_trace = f.meta_trace;
  rf.lambda = f.lambda;
  rf.mean_x = f.mean_x;
  rf.trustworthy = f.trustworthy;
  rf.beta0 = b.beta0[l];
  rf.sum_e2 = b.sum_e2[l];
  rf.press_E = b.press_E[l];
  for (Eigen::VectorXd* v : {&rf.sum_w, &rf.n_data, &rf.ss2, &rf.sys, &rf.beta, &rf.sum_e_cv2, &rf.press_H, &rf.press_R}) {
    v->resize(R);
  }
  for (Eigen::MatrixXd* m : {&rf.sxy, &rf.sxs, &rf.directions, &rf.loadings}) m->resize(n, R);
  for (int r = 0; r < R; ++r) {
    const std::size_t k = static_cast<std::size_t>(r) * kL + l;
    rf.sum_w(r) = b.sum_w[k];
    rf.n_data(r) = b.n_data[k];
    rf.ss2(r) = b.ss2[k];
    rf.sys(r) = b.sys[k];
    rf.beta(r) = b.beta[k];
    rf.sum_e_cv2(r) = b.sum_e_cv2[k];
    rf.press_H(r) = b.press_H[k];
    rf.press_R(r) = b.press_R[k];
    for (int i = 0; i < n; ++i) {
      const std::size_t e = (static_cast<std::size_t>(r) * n + i) * kL + l;
      rf.sxy(i, r) = b.sxy[e];
      rf.sxs(i, r) = b.sxs[e];
      rf.directions(i, r) = b.directions[e];
      rf.loadings(i, r) = b.loadings[e];
    }
  }
  return rf;
}

void add_lane_projection(const LwprParams& params, LaneField& f, int output) {
  const int n = f.input_dim();
  LaneBlock& b = f.blocks.at(output / kL);
  const int l = output % kL;
  const int r = b.n_reg[l];
  reserve_projections(b, n, r + 1);
  const std::size_t k = static_cast<std::size_t>(r) * kL + l;
  b.sum_w[k] = kTinyWeight;
  b.n_data[k] = 0.0;
  b.ss2[k] = params.init_S2;
  b.sys[k] = 0.0;
  b.beta[k] = 0.0;
  b.sum_e_cv2[k] = 0.0;
  b.press_H[k] = 0.0;
  b.press_R[k] = 0.0;
  for (int i = 0; i < n; ++i) {
    const std::size_t e = (static_cast<std::size_t>(r) * n + i) * kL + l;
    b.sxy[e] = b.sxs[e] = b.directions[e] = b.loadings[e] = 0.0;
  }
  b.n_reg[l] = r + 1;
  b.n_reg_lanes[l] = r + 1;
}

namespace {

// The kOutputLanes lanes of a block as one vector (GCC/Clang vector extension: the compiler splits
// it into the target's registers) and a comparison's mask.
typedef double Lanes __attribute__((vector_size(kL * sizeof(double))));
typedef decltype(Lanes{} < Lanes{}) LaneMask;

__attribute__((always_inline)) inline void load_lanes(Lanes& v, const double* from) { std::memcpy(&v, from, sizeof v); }
__attribute__((always_inline)) inline void store_lanes(double* to, const Lanes& v) { std::memcpy(to, &v, sizeof v); }

// predict_receptive_field() of one block's lanes: lane l runs predict_field()'s operations on
// output l's copy (reductions in four partial sums, element i in sum i mod 4, added as
// (p0 + p1) + (p2 + p3)); a lane past its last projection keeps its y and leverage.
template <bool Leverage>
__attribute__((always_inline)) inline void predict_block(const LaneField& f, const LaneBlock& b, const double* z0,
                                                         double* z, double* y_out, double* leverage_out) {
  const int n = f.input_dim();
  Lanes n_reg;
  load_lanes(n_reg, b.n_reg_lanes);
  // s = Σ_i u_i z_i per lane (into `out`: a vector returned by value can change the call ABI between builds).
  auto reduce = [&](const double* u, bool first, Lanes& out) __attribute__((always_inline)) {
    Lanes part[4] = {};
    for (int i = 0; i < n; ++i) {
      Lanes uv, zv;
      load_lanes(uv, u + static_cast<std::size_t>(i) * kL);
      if (first) {
        zv = Lanes{} + z0[i];
      } else {
        load_lanes(zv, z + static_cast<std::size_t>(i) * kL);
      }
      part[i % 4] += uv * zv;
    }
    out = (part[0] + part[1]) + (part[2] + part[3]);
  };
  Lanes s;
  reduce(b.directions.data(), true, s);
  Lanes y;
  load_lanes(y, b.beta0);
  Lanes leverage = {};
  for (int r = 0; r < b.max_reg; ++r) {
    const LaneMask active = Lanes{} + static_cast<double>(r) < n_reg;
    Lanes beta, ss2;
    load_lanes(beta, b.beta.data() + static_cast<std::size_t>(r) * kL);
    y = active ? y + beta * s : y;
    if (Leverage) {
      load_lanes(ss2, b.ss2.data() + static_cast<std::size_t>(r) * kL);
      leverage = active ? leverage + s * s / ss2 : leverage;
    }
    if (r + 1 == b.max_reg) break;
    const double* p = b.loadings.data() + static_cast<std::size_t>(r) * n * kL;
    for (int i = 0; i < n; ++i) {
      Lanes zv, pv;
      if (r == 0) {
        zv = Lanes{} + z0[i];
      } else {
        load_lanes(zv, z + static_cast<std::size_t>(i) * kL);
      }
      load_lanes(pv, p + static_cast<std::size_t>(i) * kL);
      store_lanes(z + static_cast<std::size_t>(i) * kL, zv - s * pv);
    }
    reduce(b.directions.data() + static_cast<std::size_t>(r + 1) * n * kL, false, s);
  }
  store_lanes(y_out, y);
  if (Leverage) store_lanes(leverage_out, leverage);
}

template <bool Leverage>
__attribute__((always_inline)) inline void predict_lanes(const LaneField& f, const Eigen::VectorXd& x, double* y,
                                                         double* leverage, LaneScratch& scratch) {
  const int n = f.input_dim();
  double* z0 = scratch.s.data();  // x − x₀, the same for every lane
  for (int i = 0; i < n; ++i) z0[i] = x(i) - f.mean_x(i);
  double y_block[kL], leverage_block[kL];
  for (std::size_t k = 0; k < f.blocks.size(); ++k) {
    predict_block<Leverage>(f, f.blocks[k], z0, scratch.z.data(), y_block, leverage_block);
    const int first = static_cast<int>(k) * kL;
    const int count = std::min(kL, f.n_out - first);
    for (int l = 0; l < count; ++l) {
      y[first + l] = y_block[l];
      if (Leverage) leverage[first + l] = leverage_block[l];
    }
  }
}

template <bool Leverage>
void predict_lanes_portable(const LaneField& f, const Eigen::VectorXd& x, double* y, double* leverage,
                            LaneScratch& scratch) {
  predict_lanes<Leverage>(f, x, y, leverage, scratch);
}
template <bool Leverage>
__attribute__((target("avx2"))) void predict_lanes_avx2(const LaneField& f, const Eigen::VectorXd& x, double* y,
                                                        double* leverage, LaneScratch& scratch) {
  predict_lanes<Leverage>(f, x, y, leverage, scratch);
}
// No FMA under AVX-512 (GCC would contract a·b + c): the same roundings as the other copies.
template <bool Leverage>
__attribute__((target("avx512f,avx512vl,avx512dq"), optimize("fp-contract=off"))) void predict_lanes_avx512(
    const LaneField& f, const Eigen::VectorXd& x, double* y, double* leverage, LaneScratch& scratch) {
  predict_lanes<Leverage>(f, x, y, leverage, scratch);
}

}  // namespace

void predict_lane_field(const LaneField& f, const Eigen::VectorXd& x, double* y, double* leverage,
                        LaneScratch& scratch) {
  if (scratch.use_avx2 && scratch.use_avx512) {
    if (leverage != nullptr) return predict_lanes_avx512<true>(f, x, y, leverage, scratch);
    return predict_lanes_avx512<false>(f, x, y, leverage, scratch);
  }
  if (scratch.use_avx2) {
    if (leverage != nullptr) return predict_lanes_avx2<true>(f, x, y, leverage, scratch);
    return predict_lanes_avx2<false>(f, x, y, leverage, scratch);
  }
  if (leverage != nullptr) return predict_lanes_portable<true>(f, x, y, leverage, scratch);
  predict_lanes_portable<false>(f, x, y, leverage, scratch);
}

double calc_lane_noise_variance(const LaneField& f, int output) {
  const LaneBlock& b = f.blocks.at(output / kL);
  const int l = output % kL;
  const std::size_t k = static_cast<std::size_t>(b.n_reg[l] - 1) * kL + l;
  return b.sum_e_cv2[k] / b.sum_w[k];
}

std::size_t count_lane_field_doubles(const LaneField& f) {
  const auto n = static_cast<std::size_t>(f.input_dim());
  const auto shared = static_cast<std::size_t>(f.center.size() + f.metric_factor.size() + f.metric.size() +
                                               f.log_alpha.size() + f.meta_trace.size() + f.mean_x.size());
  std::size_t doubles = 0;
  for (int o = 0; o < f.n_out; ++o) {
    const auto R = static_cast<std::size_t>(f.n_reg(o));
    doubles += shared + 8 * R + 4 * n * R + 5;  // as LwprModel counts a ReceptiveField
  }
  return doubles;
}

}  // namespace armfarm::lwpr
