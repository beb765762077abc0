// update_lane_field() and update_lane_field_pair() bit for bit against update_receptive_field()
// on each output's copy, on every copy of the kernel (AVX-512, AVX2, SSE2).
#include "engine/lwpr/lane_fields.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace armfarm::lwpr {
namespace {

template <class A>
bool same_bits(const A& a, const A& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every member, bit for bit; returns whether all agree (one failure message per member).
bool expect_same_field(const ReceptiveField& a, const ReceptiveField& b) {
  bool ok = true;
  auto check = [&](bool same, const char* what) {
    EXPECT_TRUE(same) << what;
    ok = ok && same;
  };
  check(same_bits(a.center, b.center), "center");
  check(same_bits(a.metric_factor, b.metric_factor), "metric_factor");
  check(same_bits(a.metric, b.metric), "metric");
  check(same_bits(a.log_alpha, b.log_alpha), "log_alpha");
  check(same_bits(a.meta_trace, b.meta_trace), "meta_trace");
  check(same_bits(a.lambda, b.lambda), "lambda");
  check(same_bits(a.mean_x, b.mean_x), "mean_x");
  check(same_bits(a.beta0, b.beta0), "beta0");
  check(same_bits(a.sum_w, b.sum_w), "sum_w");
  check(same_bits(a.n_data, b.n_data), "n_data");
  check(same_bits(a.sxy, b.sxy), "sxy");
  check(same_bits(a.sxs, b.sxs), "sxs");
  check(same_bits(a.ss2, b.ss2), "ss2");
  check(same_bits(a.sys, b.sys), "sys");
  check(same_bits(a.sum_e_cv2, b.sum_e_cv2), "sum_e_cv2");
  check(same_bits(a.sum_e2, b.sum_e2), "sum_e2");
  check(same_bits(a.press_E, b.press_E), "press_E");
  check(same_bits(a.press_H, b.press_H), "press_H");
  check(same_bits(a.press_R, b.press_R), "press_R");
  check(a.trustworthy == b.trustworthy, "trustworthy");
  check(same_bits(a.directions, b.directions), "directions");
  check(same_bits(a.loadings, b.loadings), "loadings");
  check(same_bits(a.beta, b.beta), "beta");
  return ok;
}

enum class Copy { kSse2, kAvx2, kAvx512 };

LaneScratch make_scratch(Copy copy, int n) {
  LaneScratch scratch;
  scratch.resize(n);
  scratch.use_avx2 = copy != Copy::kSse2;
  scratch.use_avx512 = copy == Copy::kAvx512;
  return scratch;
}

LwprParams test_params(LooStart loo_start) {
  LwprParams params;
  params.update_D = false;
  params.diag_only = true;
  params.loo_start = loo_start;
  params.add_proj = true;
  params.init_n_reg = 1;
  params.init_lambda = 0.99;  // the add-projection test passes after ~70 samples, not 500
  params.final_lambda = 0.995;
  params.tau_lambda = 0.99;
  params.add_threshold = 0.9;
  return params;
}

// One field's n_out copies (output o's with o % 3 extra projections), updated sample by sample
// per output by update_receptive_field() and in lane form by update_lane_field(), compared
// every few samples and at the end. Returns the lanes' total projections added.
int check_against_per_output(Copy copy, LooStart loo_start, int n, int n_out, int samples, unsigned seed) {
  SCOPED_TRACE("n " + std::to_string(n) + ", n_out " + std::to_string(n_out) + ", seed " + std::to_string(seed));
  const LwprParams params = test_params(loo_start);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 0.4);
  const Eigen::MatrixXd D = Eigen::MatrixXd::Identity(n, n) * (2.0 / n);
  Eigen::VectorXd centre(n);
  for (int i = 0; i < n; ++i) centre(i) = 0.1 * g(rng);
  std::vector<ReceptiveField> copies(n_out, make_receptive_field(params, centre, D));
  for (int o = 0; o < n_out; ++o) {
    for (int k = 0; k < o % 3 && copies[o].n_reg() < n; ++k) add_projection(params, copies[o]);
  }
  std::vector<const ReceptiveField*> pointers;
  for (const ReceptiveField& c : copies) pointers.push_back(&c);
  LaneField field = pack_lane_field(pointers);
  int start_reg = 0;
  for (const ReceptiveField& c : copies) start_reg += c.n_reg();
  FieldScratch field_scratch;
  field_scratch.resize(n, true);
  LaneScratch scratch = make_scratch(copy, n);
  const double trust_n_data = 2.0 * n;
  std::vector<double> y(n_out);
  for (int t = 0; t < samples; ++t) {
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x(i) = centre(i) + g(rng);
    const double w = std::exp(-0.5 * (x - centre).squaredNorm() * (2.0 / n));
    for (int o = 0; o < n_out; ++o) {
      y[o] = std::sin(x(0) * (o + 1)) + 0.3 * (n > 1 ? x(1) : 0.0) * o + 0.05 * g(rng) +
             (n > 2 ? x(2) * x(n - 1) : 0.0);
      update_receptive_field(params, trust_n_data, x, y[o], w, copies[o], field_scratch);
    }
    update_lane_field(params, trust_n_data, x, y.data(), w, field, scratch);
    if (t % 37 == 0 || t + 1 == samples) {
      for (int o = 0; o < n_out; ++o) {
        SCOPED_TRACE("sample " + std::to_string(t) + ", output " + std::to_string(o));
        if (!expect_same_field(unpack_lane_field(field, o), copies[o])) return -1;
      }
    }
  }
  int end_reg = 0;
  for (const ReceptiveField& c : copies) end_reg += c.n_reg();
  return end_reg - start_reg;
}

bool skip_copy(Copy copy) {
  return (copy != Copy::kSse2 && !has_avx2()) || (copy == Copy::kAvx512 && !has_avx512());
}
const char* copy_name(Copy copy) { return copy == Copy::kSse2 ? "SSE2" : copy == Copy::kAvx2 ? "AVX2" : "AVX-512"; }

void check_copy(Copy copy) {
  for (const LooStart loo_start : {LooStart::kEarly, LooStart::kLibrary}) {
    for (const int n : {1, 2, 5, 13, 21}) {
      for (const int n_out : {1, 2, 7, 9}) {
        SCOPED_TRACE(std::string(copy_name(copy)) + (loo_start == LooStart::kEarly ? ", early" : ", library"));
        const int added = check_against_per_output(copy, loo_start, n, n_out, n == 21 ? 1500 : 1000, 17u * n + n_out);
        ASSERT_GE(added, 0);
        if (n >= 5 && n_out >= 7) {
          EXPECT_GT(added, 0) << "no projection added: the test does not cover the growth";
        }
      }
    }
  }
}

TEST(LaneFieldUpdate, MatchesEachOutputsUpdateBitForBitOnSse2) { check_copy(Copy::kSse2); }

TEST(LaneFieldUpdate, MatchesEachOutputsUpdateBitForBitOnAvx2) {
  if (skip_copy(Copy::kAvx2)) {
    GTEST_SKIP() << "this CPU has no AVX2: the AVX2 copy is not run";
  }
  check_copy(Copy::kAvx2);
}

TEST(LaneFieldUpdate, MatchesEachOutputsUpdateBitForBitOnAvx512) {
  if (skip_copy(Copy::kAvx512)) {
    GTEST_SKIP() << "this CPU has no AVX-512 F/VL/DQ: the AVX-512 copy is not run";
  }
  check_copy(Copy::kAvx512);
}

// The pair against one field at a time: two fields (different centres, so different activations;
// different projection counts per lane, so their runs end at different projections).
TEST(LaneFieldUpdate, PairMatchesOneAtATimeBitForBit) {
  const LwprParams params = test_params(LooStart::kEarly);
  for (const Copy copy : {Copy::kSse2, Copy::kAvx2, Copy::kAvx512}) {
    if (skip_copy(copy)) continue;
    for (const int n : {5, 21}) {
      for (const int n_out : {2, 7, 9}) {
        std::mt19937 rng(5u + n + n_out);
        std::normal_distribution<double> g(0.0, 0.4);
        const Eigen::MatrixXd D = Eigen::MatrixXd::Identity(n, n) * (2.0 / n);
        Eigen::VectorXd ca = Eigen::VectorXd::Zero(n), cb = Eigen::VectorXd::Constant(n, 0.1);
        std::vector<ReceptiveField> a(n_out, make_receptive_field(params, ca, D));
        std::vector<ReceptiveField> b(n_out, make_receptive_field(params, cb, D));
        std::vector<const ReceptiveField*> pa, pb;
        for (int o = 0; o < n_out; ++o) {
          for (int k = 0; k < o % 3; ++k) add_projection(params, a[o]);
          for (int k = 0; k < (o + 1) % 3; ++k) add_projection(params, b[o]);
          pa.push_back(&a[o]);
          pb.push_back(&b[o]);
        }
        LaneField one_a = pack_lane_field(pa), one_b = pack_lane_field(pb);
        LaneField pair_a = one_a, pair_b = one_b;
        LaneScratch s1 = make_scratch(copy, n), s2 = make_scratch(copy, n), s3 = make_scratch(copy, n);
        std::vector<double> y(n_out);
        for (int t = 0; t < 600; ++t) {
          Eigen::VectorXd x(n);
          for (int i = 0; i < n; ++i) x(i) = g(rng);
          const double wa = std::exp(-0.5 * (x - ca).squaredNorm() * (2.0 / n));
          const double wb = std::exp(-0.5 * (x - cb).squaredNorm() * (2.0 / n));
          for (int o = 0; o < n_out; ++o) y[o] = std::cos(x(0) * (o + 1)) + 0.01 * g(rng);
          update_lane_field(params, 2.0 * n, x, y.data(), wa, one_a, s1);
          update_lane_field(params, 2.0 * n, x, y.data(), wb, one_b, s1);
          update_lane_field_pair(params, 2.0 * n, x, y.data(), wa, pair_a, wb, pair_b, s2, s3);
        }
        for (int o = 0; o < n_out; ++o) {
          SCOPED_TRACE(std::string(copy_name(copy)) + ", n " + std::to_string(n) + ", output " + std::to_string(o));
          ASSERT_TRUE(expect_same_field(unpack_lane_field(pair_a, o), unpack_lane_field(one_a, o)));
          ASSERT_TRUE(expect_same_field(unpack_lane_field(pair_b, o), unpack_lane_field(one_b, o)));
        }
      }
    }
  }
}

}  // namespace
}  // namespace armfarm::lwpr
