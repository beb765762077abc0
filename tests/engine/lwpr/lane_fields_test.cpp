// Lane fields: packing and unpacking, projections and prediction bit for bit against the
// per-output representation (receptive_field.hpp) on copies trained as a model trains them.
#include "engine/lwpr/lane_fields.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

namespace armfarm::lwpr {
namespace {

template <class A>
bool same_bits(const A& a, const A& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every member of two fields, bit for bit.
void expect_same_field(const ReceptiveField& a, const ReceptiveField& b, int output) {
  SCOPED_TRACE("output " + std::to_string(output));
  EXPECT_TRUE(same_bits(a.center, b.center));
  EXPECT_TRUE(same_bits(a.metric_factor, b.metric_factor));
  EXPECT_TRUE(same_bits(a.metric, b.metric));
  EXPECT_TRUE(same_bits(a.log_alpha, b.log_alpha));
  EXPECT_TRUE(same_bits(a.meta_trace, b.meta_trace));
  EXPECT_TRUE(same_bits(a.lambda, b.lambda));
  EXPECT_TRUE(same_bits(a.mean_x, b.mean_x));
  EXPECT_TRUE(same_bits(a.beta0, b.beta0));
  EXPECT_TRUE(same_bits(a.sum_w, b.sum_w));
  EXPECT_TRUE(same_bits(a.n_data, b.n_data));
  EXPECT_TRUE(same_bits(a.sxy, b.sxy));
  EXPECT_TRUE(same_bits(a.sxs, b.sxs));
  EXPECT_TRUE(same_bits(a.ss2, b.ss2));
  EXPECT_TRUE(same_bits(a.sys, b.sys));
  EXPECT_TRUE(same_bits(a.sum_e_cv2, b.sum_e_cv2));
  EXPECT_TRUE(same_bits(a.sum_e2, b.sum_e2));
  EXPECT_TRUE(same_bits(a.press_E, b.press_E));
  EXPECT_TRUE(same_bits(a.press_H, b.press_H));
  EXPECT_TRUE(same_bits(a.press_R, b.press_R));
  EXPECT_EQ(a.trustworthy, b.trustworthy);
  EXPECT_TRUE(same_bits(a.directions, b.directions));
  EXPECT_TRUE(same_bits(a.loadings, b.loadings));
  EXPECT_TRUE(same_bits(a.beta, b.beta));
}

// n_out copies of one field at the origin trained on the same inputs and activations with
// different outputs, output o's copy with 1 + o % 3 extra projections (so the lanes' projection
// counts differ), as an LwprModel without update_D holds them.
std::vector<ReceptiveField> train_copies(const LwprParams& params, int n, int n_out, int samples, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 0.3);
  const Eigen::MatrixXd D = Eigen::MatrixXd::Identity(n, n) * 2.0;
  std::vector<ReceptiveField> copies(n_out, make_receptive_field(params, Eigen::VectorXd::Zero(n), D));
  for (int o = 0; o < n_out; ++o) {
    for (int k = 0; k < o % 3 && copies[o].n_reg() < n; ++k) add_projection(params, copies[o]);
  }
  FieldScratch scratch;
  scratch.resize(n, params.diag_only);
  for (int t = 0; t < samples; ++t) {
    Eigen::VectorXd x(n);
    for (int i = 0; i < n; ++i) x(i) = g(rng);
    const double w = std::exp(-x.squaredNorm());
    for (int o = 0; o < n_out; ++o) {
      const double y = std::sin(x(0) * (o + 1)) + 0.1 * (n > 1 ? x(1) : 0.0) * o + 0.01 * g(rng);
      update_receptive_field(params, 2.0 * n, x, y, w, copies[o], scratch);
    }
  }
  return copies;
}

std::vector<const ReceptiveField*> pointers(const std::vector<ReceptiveField>& copies) {
  std::vector<const ReceptiveField*> p;
  for (const ReceptiveField& c : copies) p.push_back(&c);
  return p;
}

TEST(LaneFields, PackUnpackAndProjectionsKeepEveryBit) {
  LwprParams params;
  params.update_D = false;
  params.init_S2 = 1e-8;
  std::mt19937 rng(7);
  for (int n : {1, 5, 21}) {
    for (int n_out : {1, 2, 7, 9}) {
      SCOPED_TRACE("n " + std::to_string(n) + ", n_out " + std::to_string(n_out));
      std::vector<ReceptiveField> copies = train_copies(params, n, n_out, 60, rng);
      ASSERT_TRUE(lane_copies_agree(pointers(copies)));
      LaneField lanes = pack_lane_field(pointers(copies));
      ASSERT_EQ(lanes.blocks.size(), static_cast<std::size_t>((n_out + 7) / 8));
      std::size_t doubles = 0;
      for (int o = 0; o < n_out; ++o) {
        expect_same_field(unpack_lane_field(lanes, o), copies[o], o);
        EXPECT_TRUE(same_bits(calc_lane_noise_variance(lanes, o), calc_field_noise_variance(copies[o])));
        const ReceptiveField& c = copies[o];
        doubles += static_cast<std::size_t>(c.center.size() + c.metric_factor.size() + c.metric.size() +
                                            c.log_alpha.size() + c.meta_trace.size() + c.mean_x.size() +
                                            c.sum_w.size() + c.n_data.size() + c.sxy.size() + c.sxs.size() +
                                            c.ss2.size() + c.sys.size() + c.sum_e_cv2.size() + c.press_H.size() +
                                            c.press_R.size() + c.directions.size() + c.loadings.size() +
                                            c.beta.size()) + 5;
      }
      EXPECT_EQ(count_lane_field_doubles(lanes), doubles);
      // A projection added to the last output's copy (which may grow the block's arrays).
      const int last = n_out - 1;
      if (copies[last].n_reg() < n) {
        add_projection(params, copies[last]);
        add_lane_projection(params, lanes, last);
        for (int o = 0; o < n_out; ++o) expect_same_field(unpack_lane_field(lanes, o), copies[o], o);
      }
    }
  }
}

TEST(LaneFields, CopiesThatDisagreeOnASharedMemberAreNotPacked) {
  LwprParams params;
  params.update_D = false;
  std::mt19937 rng(3);
  std::vector<ReceptiveField> copies = train_copies(params, 4, 3, 20, rng);
  ASSERT_TRUE(lane_copies_agree(pointers(copies)));
  std::vector<ReceptiveField> other = copies;
  other[2].lambda = std::nextafter(other[2].lambda, 1.0);
  EXPECT_FALSE(lane_copies_agree(pointers(other)));
  other = copies;
  other[1].mean_x(3) = -other[1].mean_x(3);
  EXPECT_FALSE(lane_copies_agree(pointers(other)));
  other = copies;
  other[1].n_data(0) += 1.0;
  EXPECT_FALSE(lane_copies_agree(pointers(other)));
  other = copies;
  other[0].trustworthy = !other[0].trustworthy;
  EXPECT_FALSE(lane_copies_agree(pointers(other)));
}

TEST(LaneFields, PredictionMatchesEachCopysPredictionBitForBitOnEveryCopyOfTheCode) {
  LwprParams params;
  params.update_D = false;
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 0.4);
  struct Path {
    const char* name;
    bool avx2, avx512;
  };
  for (const Path& path : {Path{"sse2", false, false}, Path{"avx2", true, false}, Path{"avx512", true, true}}) {
    if (path.avx2 && !has_avx2()) continue;
    if (path.avx512 && !has_avx512()) continue;
    for (int n : {1, 5, 21}) {
      for (int n_out : {2, 7, 9}) {
        SCOPED_TRACE(std::string(path.name) + ", n " + std::to_string(n) + ", n_out " + std::to_string(n_out));
        const std::vector<ReceptiveField> copies = train_copies(params, n, n_out, 80, rng);
        const LaneField lanes = pack_lane_field(pointers(copies));
        LaneScratch scratch;
        scratch.resize(n);
        scratch.use_avx2 = path.avx2;
        scratch.use_avx512 = path.avx512;
        FieldScratch field_scratch;
        field_scratch.resize(n, params.diag_only);
        std::vector<double> y(n_out), leverage(n_out), y_only(n_out);
        for (int t = 0; t < 20; ++t) {
          Eigen::VectorXd x(n);
          for (int i = 0; i < n; ++i) x(i) = g(rng);
          predict_lane_field(lanes, x, y.data(), leverage.data(), scratch);
          predict_lane_field(lanes, x, y_only.data(), nullptr, scratch);
          for (int o = 0; o < n_out; ++o) {
            double expected_leverage = 0.0;
            const double expected = predict_receptive_field(copies[o], x, expected_leverage, field_scratch);
            ASSERT_TRUE(same_bits(y[o], expected)) << "output " << o << ": " << y[o] << " vs " << expected;
            ASSERT_TRUE(same_bits(leverage[o], expected_leverage)) << "output " << o;
            ASSERT_TRUE(same_bits(y_only[o], expected)) << "output " << o;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace armfarm::lwpr
