// LwprModel: accuracy on the published cross-function benchmark (2-D and with 18 redundant and
// irrelevant inputs), a 1-D function, forgetting, determinism, memory count, NaN rejection, field
// cap, trust.
#include "engine/lwpr/lwpr_model.hpp"
#include "engine/lwpr/lwpr_model_file.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <numeric>
#include <random>
#include <sstream>
#include <vector>

namespace armfarm::lwpr {
namespace {

double cross(double x1, double x2) {
  return std::max({std::exp(-10.0 * x1 * x1), std::exp(-50.0 * x2 * x2),
                   1.25 * std::exp(-5.0 * (x1 * x1 + x2 * x2))});
}

struct Data {
  std::vector<Eigen::VectorXd> x;
  std::vector<double> y;
};

// Raw 2-D cross inputs, targets with N(0, 0.1²) noise.
Data make_cross_training(std::mt19937_64& rng, int n) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.1);
  Data data;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd x(2);
    x << uniform(rng), uniform(rng);
    data.x.push_back(x);
    data.y.push_back(cross(x(0), x(1)) + noise(rng));
  }
  return data;
}

Data make_cross_grid() {
  Data data;
  for (int i = 0; i < 41; ++i) {
    for (int j = 0; j < 41; ++j) {
      Eigen::VectorXd x(2);
      x << -1.0 + 0.05 * i, -1.0 + 0.05 * j;
      data.x.push_back(x);
      data.y.push_back(cross(x(0), x(1)));
    }
  }
  return data;
}

// 20-D version (Vijayakumar et al. 2005, section 4.1): x1, x2, 8 linear combinations of them plus
// N(0, 0.05²) noise, and 10 irrelevant N(0, 0.05²) inputs.
struct Embedding {
  Eigen::MatrixXd mix;  // 8×2
  Eigen::VectorXd embed(const Eigen::VectorXd& x2d, std::mt19937_64& rng) const {
    std::normal_distribution<double> noise(0.0, 0.05);
    Eigen::VectorXd x(20);
    x.head(2) = x2d;
    for (int k = 0; k < 8; ++k) x(2 + k) = mix.row(k).dot(x2d) + noise(rng);
    for (int k = 0; k < 10; ++k) x(10 + k) = noise(rng);
    return x;
  }
};

// The published benchmark's setting: init_D = 25·I, init_alpha = 250, w_gen = 0.2, full D, meta.
// In 20-D the redundant inputs multiply the effective metric, so a wider diagonal init_D = 10·I.
LwprParams cross_params(int n_in) {
  LwprParams p;
  p.init_D = Eigen::MatrixXd::Constant(1, 1, n_in == 2 ? 25.0 : 10.0);
  p.init_alpha = 250.0;
  p.w_gen = 0.2;
  p.diag_only = n_in > 2;
  p.meta = true;
  return p;
}

double calc_nmse(const LwprModel& model, const Data& test) {
  auto workspace = model.make_workspace();
  const double mean = std::accumulate(test.y.begin(), test.y.end(), 0.0) / test.y.size();
  double variance = 0.0, error = 0.0;
  for (std::size_t i = 0; i < test.x.size(); ++i) {
    const Prediction p = model.predict(test.x[i], *workspace);
    error += (p.value(0) - test.y[i]) * (p.value(0) - test.y[i]);
    variance += (test.y[i] - mean) * (test.y[i] - mean);
  }
  return error / variance;
}

void train(LwprModel& model, const Data& data, int epochs, std::mt19937_64& rng) {
  std::vector<std::size_t> order(data.x.size());
  std::iota(order.begin(), order.end(), 0);
  Eigen::VectorXd y(1);
  for (int epoch = 0; epoch < epochs; ++epoch) {
    std::shuffle(order.begin(), order.end(), rng);
    for (std::size_t i : order) {
      y(0) = data.y[i];
      model.update(data.x[i], y);
    }
  }
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

TEST(LwprModel, CrossFunctionMatchesPublishedAccuracy) {
  // Published library: nMSE 0.038 (0.033–0.045 over seeds) with about 43 fields.
  const Data grid = make_cross_grid();
  std::vector<double> nmse;
  for (int seed = 1; seed <= 5; ++seed) {
    std::mt19937_64 rng(seed);
    const Data training = make_cross_training(rng, 500);
    LwprModel model(2, 1, cross_params(2));
    train(model, training, 20, rng);
    nmse.push_back(calc_nmse(model, grid));
    RecordProperty("nmse_seed_" + std::to_string(seed), std::to_string(nmse.back()));
    std::printf("cross seed %d: nMSE %.4f, %zu fields, %.2f projections\n", seed, nmse.back(), model.size(),
                model.calc_mean_projections());
  }
  EXPECT_LE(median(nmse), 0.040);
}

TEST(LwprModel, CrossFunctionWithRedundantAndIrrelevantInputs) {
  std::vector<double> nmse;
  for (int seed = 1; seed <= 3; ++seed) {
    std::mt19937_64 rng(seed);
    Embedding embedding;
    embedding.mix = Eigen::MatrixXd(8, 2);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int i = 0; i < 8; ++i) embedding.mix.row(i) << uniform(rng), uniform(rng);
    Data training = make_cross_training(rng, 500);
    for (auto& x : training.x) x = embedding.embed(x, rng);
    Data grid = make_cross_grid();
    for (auto& x : grid.x) x = embedding.embed(x, rng);
    LwprModel model(20, 1, cross_params(20));
    train(model, training, 20, rng);
    nmse.push_back(calc_nmse(model, grid));
    std::printf("cross 20-D seed %d: nMSE %.4f, %zu fields, %.2f projections\n", seed, nmse.back(), model.size(),
                model.calc_mean_projections());
  }
  EXPECT_LE(median(nmse), 0.06);
}

Data make_sine(std::mt19937_64& rng, int n, double phase) {
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  Data data;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd x(1);
    x << uniform(rng);
    data.x.push_back(x);
    data.y.push_back(std::sin(2.0 * x(0) + phase) + noise(rng));
  }
  return data;
}

Data make_sine_grid(double phase) {
  Data data;
  for (int i = 0; i <= 200; ++i) {
    Eigen::VectorXd x(1);
    x << -2.8 + 5.6 * i / 200.0;
    data.x.push_back(x);
    data.y.push_back(std::sin(2.0 * x(0) + phase));
  }
  return data;
}

TEST(LwprModel, LearnsOneDimensionalFunction) {
  std::mt19937_64 rng(3);
  LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 10.0);
  LwprModel model(1, 1, params);
  train(model, make_sine(rng, 500, 0.0), 10, rng);
  const double nmse = calc_nmse(model, make_sine_grid(0.0));
  EXPECT_LT(nmse, 0.01) << model.size() << " fields";
  EXPECT_GT(model.size(), 2u);
}

TEST(LwprModel, ForgettingAdaptsToAChangedFunction) {
  std::mt19937_64 rng(4);
  LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 10.0);
  params.init_lambda = 0.99;
  params.final_lambda = 0.995;
  LwprModel model(1, 1, params);
  train(model, make_sine(rng, 500, 0.0), 10, rng);
  const double before = calc_nmse(model, make_sine_grid(1.0));  // the new function, not learnt yet
  train(model, make_sine(rng, 500, 1.0), 10, rng);
  const double after = calc_nmse(model, make_sine_grid(1.0));
  EXPECT_GT(before, 0.3);
  EXPECT_LT(after, 0.02);
}

TEST(LwprModel, SameDataGivesIdenticalModel) {
  std::mt19937_64 rng_a(9), rng_b(9);
  LwprModel a(2, 1, cross_params(2)), b(2, 1, cross_params(2));
  train(a, make_cross_training(rng_a, 200), 3, rng_a);
  train(b, make_cross_training(rng_b, 200), 3, rng_b);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.fields(0).size(); ++i) {
    EXPECT_EQ(a.fields(0)[i].metric, b.fields(0)[i].metric);
    EXPECT_EQ(a.fields(0)[i].beta, b.fields(0)[i].beta);
  }
  auto wa = a.make_workspace();
  auto wb = b.make_workspace();
  const Eigen::Vector2d x(0.3, -0.2);
  EXPECT_EQ(a.predict(x, *wa).value(0), b.predict(x, *wb).value(0));
}

// calc_memory_bytes (the learner_memory_bytes metric) against a count by hand of the numbers
// one new receptive field with a diagonal metric stores.
TEST(LwprModel, CalcMemoryBytesCountsEachNewFieldsNumbers) {
  const int n = 3, outputs = 2;
  LwprParams params;
  params.diag_only = true;
  LwprModel model(n, outputs, params);
  const std::size_t empty = model.calc_memory_bytes();
  model.update(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector2d(1.0, -1.0));
  ASSERT_EQ(model.size(), 2u);
  const std::size_t R = static_cast<std::size_t>(model.fields(0).at(0).n_reg());
  ASSERT_EQ(model.fields(1).at(0).n_reg(), model.fields(0).at(0).n_reg());
  // Per field: c, M, D, log α, IDBD trace, x₀ (n each); Σw, n_data, ss2, sys, Σe_cv², PRESS H and
  // R, β (R each); sxy, sxs, directions, loadings (n×R each); λ, β₀, Σe², PRESS E, trust (5);
  // in the scan: centre and metric diagonal padded to 8 doubles, and one trust byte.
  const std::size_t per_field = 8 * (6 * n + 8 * R + 4 * n * R + 5) + 8 * (2 * 8) + 1;
  EXPECT_EQ(model.calc_memory_bytes() - empty, outputs * per_field);
}

// Without update_D one activation scan serves every output (LwprModel::shared_scan_). Each output
// of a 3-output model must then be the same bits as a 1-output model learning that output alone
// (which scans its own fields), in its fields and its predictions; and a model restored from
// fields that differ between outputs must scan each output's own.
TEST(LwprModel, OutputsSharingOneScanMatchSingleOutputModels) {
  LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 4.0);
  params.update_D = false;
  params.w_gen = 0.2;
  params.norm_out = Eigen::Vector3d(1.0, 0.5, 2.0);
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::VectorXd> xs, ys;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    xs.push_back(x);
    ys.push_back(Eigen::Vector3d(std::sin(2.0 * x(0)) + x(1), x(1) * x(2), std::cos(x(0) + x(2))));
  }
  LwprModel joint(3, 3, params);
  for (std::size_t i = 0; i < xs.size(); ++i) joint.update(xs[i], ys[i]);
  ASSERT_GT(joint.fields(0).size(), 10u);
  auto wj = joint.make_workspace();
  for (int o = 0; o < 3; ++o) {
    LwprParams single_params = params;
    single_params.norm_out = Eigen::VectorXd::Constant(1, params.norm_out(o));
    LwprModel single(3, 1, single_params);
    for (std::size_t i = 0; i < xs.size(); ++i) single.update(xs[i], ys[i].segment(o, 1));
    ASSERT_EQ(single.fields(0).size(), joint.fields(o).size()) << "output " << o;
    for (std::size_t f = 0; f < single.fields(0).size(); ++f) {
      EXPECT_EQ(single.fields(0)[f].center, joint.fields(o)[f].center);
      EXPECT_EQ(single.fields(0)[f].beta, joint.fields(o)[f].beta);
      EXPECT_EQ(single.fields(0)[f].sum_e_cv2, joint.fields(o)[f].sum_e_cv2);
    }
    auto ws = single.make_workspace();
    for (std::size_t i = 0; i < 200; ++i) {
      const Prediction a = single.predict(xs[i], *ws);
      const Prediction b = joint.predict(xs[i], *wj);
      EXPECT_EQ(a.value(0), b.value(o));
      EXPECT_EQ(a.confidence(0), b.confidence(o));
    }
  }
  // Restored with output 1's fields replaced by output 2's: no longer identical across outputs.
  std::vector<std::vector<ReceptiveField>> fields = {joint.fields(0), joint.fields(2), joint.fields(2)};
  fields[1].pop_back();
  const LwprModel mixed(3, 3, params, fields, joint.n_updates());
  LwprParams p2 = params;
  p2.norm_out = Eigen::VectorXd::Constant(1, params.norm_out(1));
  const LwprModel lone(3, 1, p2, {fields[1]}, joint.n_updates());
  auto wm = mixed.make_workspace();
  auto wl = lone.make_workspace();
  for (std::size_t i = 0; i < 200; ++i) {
    EXPECT_EQ(mixed.predict(xs[i], *wm).value(1), lone.predict(xs[i], *wl).value(0));
  }
}

// The activation scan's AVX2 copy against the portable one: the same active fields, activations
// and predictions, bit for bit, for diagonal metrics over two scan blocks (n = 9: the 3-DOF jobs'
// inputs) and for full metrics (n = 2 and 5).
TEST(LwprModel, Avx2ScanMatchesThePortableScanBitForBit) {
  if (!has_avx2()) GTEST_SKIP() << "this CPU has no AVX2";
  for (const auto& [size, diagonal] : {std::pair{9, true}, std::pair{2, false}, std::pair{5, false}}) {
    const int n = size;  // a lambda may capture a variable, not a structured binding (C++17; clang refuses)
    LwprParams params;
    params.diag_only = diagonal;
    params.init_D = Eigen::MatrixXd::Constant(1, 1, 3.0);
    params.w_gen = 0.3;
    LwprModel model(n, 2, params);
    std::mt19937_64 rng(static_cast<unsigned>(31 + n));
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    auto draw = [&] { return Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); })); };
    for (int i = 0; i < 2000; ++i) {
      const Eigen::VectorXd x = draw();
      model.update(x, Eigen::Vector2d(std::sin(2.0 * x(0)) + x(n - 1), x(0) * x(1)));
    }
    ASSERT_GT(model.fields(0).size(), 10u) << "n = " << n;
    auto portable = model.make_workspace(), avx2 = model.make_workspace();
    static_cast<LwprWorkspace&>(*portable).scratch.use_avx2 = false;
    static_cast<LwprWorkspace&>(*avx2).scratch.use_avx2 = true;
    int trusted = 0;
    for (int i = 0; i < 500; ++i) {
      const Eigen::VectorXd x = draw();
      LwprPredictionDetail detail_a, detail_b;
      const Prediction a = model.predict(x, *portable, detail_a);
      const Prediction b = model.predict(x, *avx2, detail_b);
      for (int o = 0; o < 2; ++o) {
        EXPECT_EQ(std::memcmp(&a.value(o), &b.value(o), sizeof(double)), 0) << "n = " << n << ", sample " << i;
        EXPECT_EQ(std::memcmp(&a.confidence(o), &b.confidence(o), sizeof(double)), 0) << "n = " << n;
        EXPECT_EQ(detail_a.max_activation(o), detail_b.max_activation(o)) << "n = " << n;
        trusted += detail_a.trustworthy[o] ? 1 : 0;
      }
    }
    EXPECT_GT(trusted, 500) << "n = " << n << ": too few predictions had a trustworthy field";
  }
}

// predict_into() writes the same bits as predict() into a caller's Prediction, whatever it held
// (other sizes, stale flags), and reuses its vectors: their storage stays put from the second call on.
TEST(LwprModel, PredictIntoMatchesPredictAndReusesTheVectors) {
  LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 6.0);
  params.w_gen = 0.3;
  LwprModel model(3, 2, params);
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int i = 0; i < 1500; ++i) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    model.update(x, Eigen::Vector2d(std::sin(2.0 * x(0)) + x(2), x(0) * x(1)));
  }
  auto ws_a = model.make_workspace(), ws_b = model.make_workspace();
  Prediction reused;
  reused.value = Eigen::VectorXd::Constant(5, 7.0);
  reused.confidence = Eigen::VectorXd::Constant(1, -1.0);
  reused.output_trusted.assign(4, true);
  reused.max_activation = 9.0;
  const double* value_storage = nullptr;
  const double* confidence_storage = nullptr;
  int untrusted = 0;
  for (int i = 0; i < 300; ++i) {
    // Every tenth point far outside the data: no trustworthy field, value 0 and confidence +inf.
    const double scale = i % 10 == 0 ? 40.0 : 1.0;
    const Eigen::Vector3d x(scale * uniform(rng), uniform(rng), uniform(rng));
    const Prediction expected = model.predict(x, *ws_a);
    model.predict_into(x, *ws_b, reused);
    ASSERT_EQ(reused.value.size(), 2);
    ASSERT_EQ(reused.confidence.size(), 2);
    for (int o = 0; o < 2; ++o) {
      EXPECT_EQ(std::memcmp(&expected.value(o), &reused.value(o), sizeof(double)), 0) << "sample " << i;
      EXPECT_EQ(std::memcmp(&expected.confidence(o), &reused.confidence(o), sizeof(double)), 0) << "sample " << i;
    }
    EXPECT_EQ(expected.output_trusted, reused.output_trusted) << "sample " << i;
    EXPECT_EQ(expected.trustworthy, reused.trustworthy) << "sample " << i;
    EXPECT_EQ(expected.max_activation, reused.max_activation) << "sample " << i;
    untrusted += expected.trustworthy ? 0 : 1;
    if (i == 0) {
      value_storage = reused.value.data();
      confidence_storage = reused.confidence.data();
    }
    EXPECT_EQ(reused.value.data(), value_storage) << "sample " << i << ": the value vector was reallocated";
    EXPECT_EQ(reused.confidence.data(), confidence_storage) << "sample " << i;
  }
  EXPECT_GE(untrusted, 25);  // the far points
  EXPECT_LT(untrusted, 100);
}

// predict_values_into() gives predict()'s values, trust flags and max_activation, bit for bit,
// with an empty confidence, from a stale Prediction on, reusing its value vector; blended (n = 3,
// the portable field prediction) and winner-take-all (n = 6, AVX2's where the CPU has it).
TEST(LwprModel, PredictValuesIntoMatchesPredictWithoutTheBounds) {
  for (const bool blend : {true, false}) {
    const int n = blend ? 3 : 6;
    LwprParams params;
    params.init_D = Eigen::MatrixXd::Constant(1, 1, 6.0 / n * 3.0);
    params.w_gen = 0.3;
    params.blend = blend;
    LwprModel model(n, 2, params);
    std::mt19937_64 rng(43 + n);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    auto draw = [&] { return Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); })); };
    for (int i = 0; i < 2000; ++i) {
      const Eigen::VectorXd x = draw();
      model.update(x, Eigen::Vector2d(std::sin(2.0 * x(0)) + x(n - 1), x(0) * x(1)));
    }
    auto ws_a = model.make_workspace(), ws_b = model.make_workspace();
    Prediction reused;
    reused.value = Eigen::VectorXd::Constant(5, 7.0);
    reused.confidence = Eigen::VectorXd::Constant(2, -1.0);
    reused.output_trusted.assign(4, true);
    reused.max_activation = 9.0;
    const double* value_storage = nullptr;
    int untrusted = 0, trusted_outputs = 0;
    for (int i = 0; i < 300; ++i) {
      Eigen::VectorXd x = draw();
      if (i % 10 == 0) x(0) *= 40.0;  // far outside the data: no trustworthy field
      const Prediction expected = model.predict(x, *ws_a);
      model.predict_values_into(x, *ws_b, reused);
      ASSERT_EQ(reused.value.size(), 2);
      EXPECT_EQ(reused.confidence.size(), 0) << "sample " << i;
      for (int o = 0; o < 2; ++o) {
        EXPECT_EQ(std::memcmp(&expected.value(o), &reused.value(o), sizeof(double)), 0)
            << "blend " << blend << ", sample " << i;
        trusted_outputs += expected.output_trusted[o] ? 1 : 0;
      }
      EXPECT_EQ(expected.output_trusted, reused.output_trusted) << "sample " << i;
      EXPECT_EQ(expected.trustworthy, reused.trustworthy) << "sample " << i;
      EXPECT_EQ(std::memcmp(&expected.max_activation, &reused.max_activation, sizeof(double)), 0) << "sample " << i;
      untrusted += expected.trustworthy ? 0 : 1;
      if (i == 0) value_storage = reused.value.data();
      EXPECT_EQ(reused.value.data(), value_storage) << "sample " << i << ": the value vector was reallocated";
    }
    EXPECT_GE(untrusted, 25) << "blend " << blend;  // the far points
    EXPECT_GT(trusted_outputs, 400) << "blend " << blend;
  }
}

// Without update_D the PRESS memory terms (press_E, press_H, press_R) and Σλw e² feed nothing: the
// metric never moves, so the field update leaves them at 0, and a model restored with arbitrary
// values there learns and predicts the same bits as one restored without. With update_D the same
// change of those terms changes the predictions (so the comparison can see a term that is read).
TEST(LwprModel, PressTermsAreReadOnlyWithUpdateD) {
  for (const bool update_d : {false, true}) {
    LwprParams params;
    params.init_D = Eigen::MatrixXd::Constant(1, 1, 4.0);
    params.update_D = update_d;
    params.w_gen = 0.2;
    params.init_lambda = 0.99;  // the leave-one-out statistics start after 10 samples
    std::mt19937_64 rng(43);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    auto sample = [&](Eigen::VectorXd& x, Eigen::VectorXd& y) {
      x = Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
      y = Eigen::Vector2d(std::sin(2.0 * x(0)) + x(1) * x(2), std::cos(x(0) + x(2)));
    };
    LwprModel model(3, 2, params);
    Eigen::VectorXd x, y;
    for (int i = 0; i < 2000; ++i) {
      sample(x, y);
      model.update(x, y);
    }
    std::vector<std::vector<ReceptiveField>> fields = {model.fields(0), model.fields(1)}, changed = fields;
    double largest_press = 0.0;
    for (auto& list : changed) {
      for (ReceptiveField& rf : list) {
        largest_press = std::max({largest_press, std::abs(rf.press_E), std::abs(rf.sum_e2),
                                  rf.press_H.cwiseAbs().maxCoeff(), rf.press_R.cwiseAbs().maxCoeff()});
        rf.press_E = 3.0;
        rf.sum_e2 = 0.5;
        rf.press_H.setConstant(-2.0);
        rf.press_R.setConstant(5.0);
      }
    }
    if (update_d) {
      EXPECT_GT(largest_press, 0.0);
    } else {
      EXPECT_EQ(largest_press, 0.0);
    }
    LwprModel a(3, 2, params, fields, model.n_updates()), b(3, 2, params, changed, model.n_updates());
    for (int i = 0; i < 1000; ++i) {
      sample(x, y);
      a.update(x, y);
      b.update(x, y);
    }
    auto wa = a.make_workspace(), wb = b.make_workspace();
    int differ = 0;
    for (int i = 0; i < 300; ++i) {
      sample(x, y);
      const Prediction pa = a.predict(x, *wa), pb = b.predict(x, *wb);
      for (int o = 0; o < 2; ++o) {
        differ += std::memcmp(&pa.value(o), &pb.value(o), sizeof(double)) != 0 ? 1 : 0;
        differ += std::memcmp(&pa.confidence(o), &pb.confidence(o), sizeof(double)) != 0 ? 1 : 0;
      }
    }
    if (update_d) {
      EXPECT_GT(differ, 0) << "with update_D the PRESS terms must change the metric steps";
    } else {
      EXPECT_EQ(differ, 0) << "without update_D the PRESS terms must not be read";
    }
  }
}

TEST(LwprModel, RejectsNonFiniteSamplesAndLeavesModelUnchanged) {
  std::mt19937_64 rng(5);
  LwprModel model(2, 1, cross_params(2));
  train(model, make_cross_training(rng, 200), 2, rng);
  const std::size_t fields = model.size();
  const std::uint64_t updates = model.n_updates();
  auto workspace = model.make_workspace();
  const Eigen::Vector2d probe(0.1, 0.1);
  const double before = model.predict(probe, *workspace).value(0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(model.update(Eigen::Vector2d(nan, 0.0), Eigen::VectorXd::Ones(1)), std::invalid_argument);
  EXPECT_THROW(model.update(Eigen::Vector2d(0.1, 0.1), Eigen::VectorXd::Constant(1, inf)), std::invalid_argument);
  EXPECT_THROW(model.update(Eigen::Vector3d(0.1, 0.1, 0.1), Eigen::VectorXd::Ones(1)), std::invalid_argument);
  EXPECT_EQ(model.size(), fields);
  EXPECT_EQ(model.n_updates(), updates);
  EXPECT_EQ(model.predict(probe, *workspace).value(0), before);
  for (const ReceptiveField& rf : model.fields(0)) EXPECT_TRUE(rf.metric.allFinite());
}

TEST(LwprModel, FieldCapIsRespected) {
  std::mt19937_64 rng(6);
  LwprParams params = cross_params(2);
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 400.0);  // narrow: would make hundreds of fields
  params.max_fields = 20;
  LwprModel model(2, 1, params);
  train(model, make_cross_training(rng, 300), 2, rng);
  EXPECT_EQ(model.size(), 20u);
}

// The contiguous scan data must follow every create, metric update and prune: the largest
// activation a prediction reports equals the brute-force maximum of calc_activation over the
// output's trustworthy fields, with pruning active, for diagonal metrics (padded diagonals in the
// scan) and full ones (the factor's upper triangle in the scan, with meta learning).
void check_scan_data_follows_fields(bool diag_only) {
  std::mt19937_64 rng(9);
  LwprParams params;
  params.diag_only = diag_only;
  params.meta = !diag_only;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 30.0);
  params.w_prune = 0.15;
  params.norm_in = Eigen::Vector3d(1.0, 2.0, 0.5);
  LwprModel model(3, 2, params);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  int prunes = 0;  // an update prunes or creates in an output, never both (w_prune > w_gen)
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    const std::size_t before[2] = {model.fields(0).size(), model.fields(1).size()};
    model.update(x, Eigen::Vector2d(std::sin(3.0 * x(0)) * x(1), x(2) * x(2)));
    for (int o = 0; o < 2; ++o) prunes += model.fields(o).size() < before[o] ? 1 : 0;
  }
  ASSERT_GT(prunes, 0) << "no field was pruned";
  auto workspace = model.make_workspace();
  FieldScratch scratch;
  scratch.resize(3, diag_only);
  int active = 0;
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    const Eigen::VectorXd xn = x.cwiseQuotient(params.norm_in);
    LwprPredictionDetail detail;
    model.predict(x, *workspace, detail);
    for (int o = 0; o < 2; ++o) {
      double best = 0.0;
      for (const ReceptiveField& rf : model.fields(o)) {
        if (!rf.trustworthy) continue;
        const double w = calc_activation(rf, params.kernel, xn, params.cutoff, scratch);
        if (w > params.cutoff) best = std::max(best, w);
      }
      EXPECT_NEAR(detail.max_activation(o), best, 1e-12 * std::max(1.0, best)) << "output " << o;
      active += best > 0.0 ? 1 : 0;
    }
  }
  EXPECT_GT(active, 300);
}

TEST(LwprModel, ScanDataFollowsFieldsThroughUpdatesAndPruning) { check_scan_data_follows_fields(true); }
TEST(LwprModel, ScanDataFollowsFullMetricFieldsThroughUpdatesAndPruning) { check_scan_data_follows_fields(false); }

// The scan's group layout (four fields per vector, LwprModel::ScanData) after creates and prunes
// that cross group boundaries must hold what appending the surviving fields afresh gives: a model
// restored from the trained model's fields (its scan built by appends only) predicts the same
// bits, with the same per-output largest activations, on both the portable and the AVX2 scan.
void check_pruned_scan_matches_restored_model(bool diag_only, int n) {
  std::mt19937_64 rng(static_cast<unsigned>(17 + n));
  LwprParams params;
  params.diag_only = diag_only;
  params.update_D = true;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 60.0 / n);  // narrow enough to create, wide enough to prune
  params.w_prune = 0.2;
  LwprModel model(n, 2, params);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  auto draw = [&] { return Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); })); };
  int prunes = 0, odd_sizes = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::VectorXd x = draw();
    const std::size_t before = model.fields(0).size();
    model.update(x, Eigen::Vector2d(std::sin(3.0 * x(0)) * x(n - 1), x(0) * x(0)));
    prunes += model.fields(0).size() < before ? 1 : 0;
    odd_sizes += model.fields(0).size() % 4 != 0 ? 1 : 0;
  }
  ASSERT_GT(prunes, 10) << "n = " << n;
  ASSERT_GT(odd_sizes, 10) << "n = " << n;
  const LwprModel restored(n, 2, params, {model.fields(0), model.fields(1)}, model.n_updates());
  for (const bool avx2 : {false, true}) {
    if (avx2 && !has_avx2()) continue;
    auto wa = model.make_workspace(), wb = restored.make_workspace();
    static_cast<LwprWorkspace&>(*wa).scratch.use_avx2 = avx2;
    static_cast<LwprWorkspace&>(*wb).scratch.use_avx2 = avx2;
    int trusted = 0;
    for (int k = 0; k < 400; ++k) {
      const Eigen::VectorXd x = draw();
      LwprPredictionDetail da, db;
      const Prediction a = model.predict(x, *wa, da);
      const Prediction b = restored.predict(x, *wb, db);
      for (int o = 0; o < 2; ++o) {
        EXPECT_EQ(std::memcmp(&a.value(o), &b.value(o), sizeof(double)), 0) << "n = " << n << ", point " << k;
        EXPECT_EQ(std::memcmp(&da.max_activation(o), &db.max_activation(o), sizeof(double)), 0) << "n = " << n;
        trusted += da.trustworthy[o] ? 1 : 0;
      }
    }
    EXPECT_GT(trusted, 400) << "n = " << n;
  }
}

TEST(LwprModel, PrunedGroupScanMatchesARestoredModelBitForBit) {
  check_pruned_scan_matches_restored_model(true, 3);
  check_pruned_scan_matches_restored_model(true, 9);
  check_pruned_scan_matches_restored_model(false, 2);
  check_pruned_scan_matches_restored_model(false, 3);
  check_pruned_scan_matches_restored_model(false, 5);
}

// The activation a field gets from the scan, written as a plain loop over the field's own
// numbers with the scan's operations in their order: for a diagonal metric, blocks of eight
// elements (zero past n) whose products d·(x−c)·(x−c) are summed in a fixed tree, the blocks in
// order, out once q ≥ q_limit at the end of a block; for a full one, q = |M(x − c)|² row by row,
// each row's product in ascending column order, out once q ≥ q_limit at the end of a row. 0 when
// out or at or below the cutoff.
double calc_plain_scan_activation(const ReceptiveField& rf, const LwprParams& params, const Eigen::VectorXd& xn) {
  const int n = rf.input_dim();
  const double q_limit = calc_q_limit(params.kernel, params.cutoff);
  double q = 0.0;
  if (rf.diagonal()) {
    for (int b = 0; b < n; b += 8) {
      double part[8];
      for (int k = 0; k < 8; ++k) {
        const double d = b + k < n ? rf.metric(b + k, 0) : 0.0;
        const double diff = b + k < n ? xn(b + k) - rf.center(b + k) : 0.0 - 0.0;
        part[k] = d * diff * diff;
      }
      q += ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7]));
      if (q >= q_limit) return 0.0;
    }
  } else {
    std::vector<double> diff(n);
    for (int k = 0; k < n; ++k) diff[k] = xn(k) - rf.center(k);
    for (int r = 0; r < n; ++r) {
      double v = rf.metric_factor(r, r) * diff[r];
      for (int k = r + 1; k < n; ++k) v += rf.metric_factor(r, k) * diff[k];
      q += v * v;
      if (q >= q_limit) return 0.0;
    }
  }
  const double w = calc_kernel(params.kernel, q);
  return w <= params.cutoff || !(w > 0.0) ? 0.0 : w;
}

// The group scan (four fields per vector lane, diagonal and full metrics, with the per-group trust
// lanes) gives each field the plain loop's activation bit for bit, through creates, metric
// updates, trust changes and prunes across group boundaries:
// - update's scan (every field): before each update the plain loop gives each field's w; after
//   it, a field with w > 0 has Σλw = λ·Σλw_before + w (the first thing its update does), the
//   bits of that sum, and a field with w = 0 is untouched;
// - predict's scan (trustworthy fields only), portable and AVX2: the largest activation per
//   output and the blended value equal the plain loop's over the trustworthy fields in order.
void check_scan_matches_plain_loop(bool diag_only, int n, bool meta) {
  std::mt19937_64 rng(static_cast<unsigned>(57 + n));
  LwprParams params;
  params.diag_only = diag_only;
  params.update_D = true;
  params.meta = meta;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 60.0 / n);  // narrow enough to create, wide enough to prune
  params.w_prune = 0.2;
  params.norm_in = Eigen::VectorXd::LinSpaced(n, 0.5, 1.5);
  LwprModel model(n, 2, params);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  auto draw = [&] { return Eigen::VectorXd(Eigen::VectorXd::NullaryExpr(n, [&] { return uniform(rng); })); };
  int prunes = 0, odd_sizes = 0, updated = 0, skipped = 0, untrusted = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::VectorXd x = draw();
    const Eigen::VectorXd xn = x.cwiseQuotient(params.norm_in);
    // Per output and field: the plain loop's w and the Σλw expected after the update.
    std::vector<std::vector<std::pair<double, double>>> expected(2);
    for (int o = 0; o < 2; ++o) {
      for (const ReceptiveField& rf : model.fields(o)) {
        untrusted += rf.trustworthy ? 0 : 1;
        const double w = calc_plain_scan_activation(rf, params, xn);
        expected[o].emplace_back(w, w > 0.0 ? rf.lambda * rf.sum_w(0) + w : rf.sum_w(0));
      }
    }
    model.update(x, Eigen::Vector2d(std::sin(3.0 * x(0)) * x(n - 1), x(0) * x(0)));
    for (int o = 0; o < 2; ++o) {
      const std::vector<ReceptiveField>& after = model.fields(o);
      if (after.size() < expected[o].size()) {  // pruned: the indices moved
        ++prunes;
        continue;
      }
      odd_sizes += after.size() % 4 != 0 ? 1 : 0;
      for (std::size_t f = 0; f < expected[o].size(); ++f) {
        const auto [w, sum_w] = expected[o][f];
        ASSERT_EQ(std::memcmp(&sum_w, &after[f].sum_w(0), sizeof sum_w), 0)
            << "n = " << n << ", sample " << i << ", output " << o << ", field " << f << ", w = " << w;
        (w > 0.0 ? updated : skipped) += 1;
      }
    }
  }
  EXPECT_GT(prunes, 10) << "n = " << n;
  EXPECT_GT(odd_sizes, 100) << "n = " << n;
  EXPECT_GT(updated, 3000) << "n = " << n;
  EXPECT_GT(skipped, 3000) << "n = " << n;
  EXPECT_GT(untrusted, 100) << "n = " << n;
  FieldScratch scratch;
  scratch.resize(n, diag_only);
  for (const bool avx2 : {false, true}) {
    if (avx2 && !has_avx2()) continue;
    auto workspace = model.make_workspace();
    static_cast<LwprWorkspace&>(*workspace).scratch.use_avx2 = avx2;
    scratch.use_avx2 = avx2;
    int trusted = 0;
    for (int k = 0; k < 400; ++k) {
      const Eigen::VectorXd x = draw();
      const Eigen::VectorXd xn = x.cwiseQuotient(params.norm_in);
      LwprPredictionDetail detail;
      Prediction p;
      model.predict_values_into(x, *workspace, p);
      model.predict(x, *workspace, detail);
      for (int o = 0; o < 2; ++o) {
        double w_max = 0.0, sum_w = 0.0, sum_wy = 0.0;
        for (const ReceptiveField& rf : model.fields(o)) {
          if (!rf.trustworthy) continue;
          const double w = calc_plain_scan_activation(rf, params, xn);
          if (w <= 0.0) continue;
          const double y = predict_receptive_field_value(rf, xn, scratch);
          sum_w += w;
          sum_wy += w * y;
          w_max = std::max(w_max, w);
        }
        EXPECT_EQ(std::memcmp(&w_max, &detail.max_activation(o), sizeof w_max), 0)
            << "n = " << n << ", point " << k << ", output " << o << (avx2 ? ", AVX2" : ", portable");
        ASSERT_EQ(p.output_trusted[o], w_max > 0.0) << "n = " << n << ", point " << k;
        const double value = w_max > 0.0 ? sum_wy / sum_w : 0.0;
        EXPECT_EQ(std::memcmp(&value, &p.value(o), sizeof value), 0)
            << "n = " << n << ", point " << k << ", output " << o << (avx2 ? ", AVX2" : ", portable");
        trusted += w_max > 0.0 ? 1 : 0;
      }
    }
    EXPECT_GT(trusted, 400) << "n = " << n;
  }
}

TEST(LwprModel, FullMetricGroupScanMatchesAPlainLoopBitForBit) {
  check_scan_matches_plain_loop(false, 2, true);
  check_scan_matches_plain_loop(false, 3, false);
  check_scan_matches_plain_loop(false, 5, false);
}

TEST(LwprModel, DiagonalGroupScanMatchesAPlainLoopBitForBit) {
  check_scan_matches_plain_loop(true, 3, false);
  check_scan_matches_plain_loop(true, 9, true);
}

// predict(), predict_into() and predict_values_into() refuse a wrong size, a non-finite element
// and a workspace of another class with these messages, checked in this order, and update()
// refuses bad x and y in its order with the model unchanged; a workspace made by a model of
// another input size predicts the same bits as the model's own.
TEST(LwprModel, RefusesBadInputsInOrderAndPredictsWithAnotherModelsWorkspace) {
  struct ForeignWorkspace final : PredictionWorkspace {};
  LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 6.0);
  params.w_gen = 0.3;
  LwprModel model(3, 2, params);
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int i = 0; i < 800; ++i) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    model.update(x, Eigen::Vector2d(std::sin(2.0 * x(0)) + x(2), x(0) * x(1)));
  }
  auto own = model.make_workspace();
  ForeignWorkspace foreign;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd wrong_size = Eigen::Vector2d(0.1, 0.2);
  const Eigen::VectorXd not_finite = Eigen::Vector3d(0.1, nan, std::numeric_limits<double>::infinity());
  const Eigen::VectorXd good = Eigen::Vector3d(0.1, 0.2, 0.3);
  auto message = [&](const Eigen::VectorXd& x, PredictionWorkspace& ws, int call) {
    Prediction out;
    try {
      if (call == 0) model.predict(x, ws);
      if (call == 1) model.predict_into(x, ws, out);
      if (call == 2) model.predict_values_into(x, ws, out);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  for (int call = 0; call < 3; ++call) {
    EXPECT_EQ(message(wrong_size, *own, call), "LWPR: x has 2 elements, expected 3");
    EXPECT_EQ(message(wrong_size, foreign, call), "LWPR: x has 2 elements, expected 3");
    EXPECT_EQ(message(not_finite, *own, call), "LWPR: x[1] is not finite");
    EXPECT_EQ(message(not_finite, foreign, call), "LWPR: x[1] is not finite");
    EXPECT_EQ(message(good, foreign, call), "LWPR: predict() needs a workspace from make_workspace()");
    EXPECT_EQ(message(good, *own, call), "no error");
  }
  // update() in the same order (x's size, x's elements, y's size, y's elements), model unchanged.
  auto update_message = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
    try {
      model.update(x, y);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const Eigen::VectorXd y_good = Eigen::Vector2d(0.5, -0.5);
  const Eigen::VectorXd y_wrong_size = Eigen::Vector3d(0.5, -0.5, 0.0);
  const Eigen::VectorXd y_not_finite = Eigen::Vector2d(0.5, -nan);
  const Prediction before = model.predict(good, *own);
  const std::uint64_t updates = model.n_updates();
  EXPECT_EQ(update_message(wrong_size, y_good), "LWPR: x has 2 elements, expected 3");
  EXPECT_EQ(update_message(wrong_size, y_wrong_size), "LWPR: x has 2 elements, expected 3");
  EXPECT_EQ(update_message(not_finite, y_wrong_size), "LWPR: x[1] is not finite");
  EXPECT_EQ(update_message(good, y_wrong_size), "LWPR: y has 3 elements, expected 2");
  EXPECT_EQ(update_message(good, y_not_finite), "LWPR: y[1] is not finite");
  EXPECT_EQ(model.n_updates(), updates);
  const Prediction after = model.predict(good, *own);
  for (int o = 0; o < 2; ++o) EXPECT_EQ(std::memcmp(&before.value(o), &after.value(o), sizeof(double)), 0);

  const LwprModel other(9, 1, params);
  auto borrowed = other.make_workspace();
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    const Prediction a = model.predict(x, *own);
    const Prediction b = model.predict(x, *borrowed);
    for (int o = 0; o < 2; ++o) {
      EXPECT_EQ(std::memcmp(&a.value(o), &b.value(o), sizeof(double)), 0) << "point " << i;
      EXPECT_EQ(std::memcmp(&a.confidence(o), &b.confidence(o), sizeof(double)), 0) << "point " << i;
    }
    EXPECT_EQ(a.output_trusted, b.output_trusted);
  }
}

TEST(LwprModel, FlagsPredictionsWithoutTrustworthyFields) {
  LwprModel model(2, 2, cross_params(2));
  auto workspace = model.make_workspace();
  Prediction empty = model.predict(Eigen::Vector2d(0.0, 0.0), *workspace);
  EXPECT_FALSE(empty.trustworthy);
  EXPECT_EQ(empty.output_trusted, (std::vector<bool>{false, false}));
  EXPECT_TRUE(std::isinf(empty.confidence(0)));
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> uniform(-0.2, 0.2);
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector2d x(uniform(rng), uniform(rng));
    model.update(x, Eigen::Vector2d(x(0) + 2.0 * x(1), 1.0 - x(0)));
  }
  LwprPredictionDetail detail;
  const Prediction near = model.predict(Eigen::Vector2d(0.05, -0.05), *workspace, detail);
  EXPECT_TRUE(near.trustworthy);
  EXPECT_EQ(near.output_trusted, (std::vector<bool>{true, true}));
  EXPECT_NEAR(near.value(0), 0.05 - 0.1, 5e-3);  // a plane, up to the lag of the forgetting PLS
  EXPECT_NEAR(near.value(1), 0.95, 5e-3);
  EXPECT_GT(near.max_activation, 0.5);
  const Prediction far = model.predict(Eigen::Vector2d(5.0, 5.0), *workspace);
  EXPECT_FALSE(far.trustworthy);
  EXPECT_EQ(far.value(0), 0.0);
}

}  // namespace
}  // namespace armfarm::lwpr

namespace armfarm::lwpr {
namespace {

// Bit equality of two doubles (−0 and NaN included).
bool same_double_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The lane form (FieldLayout::kAuto without update_D) against one list per output, through the
// model: the same fields, predictions, confidences, sizes, memory count, projections and model
// file bytes, bit for bit; outputs whose copies add projections at different times (add_threshold
// near 1); a restored model takes the lane form again, and one whose outputs disagree does not.
TEST(LwprModel, LaneLayoutMatchesPerOutputLayoutBitForBit) {
  for (const auto& [n, n_out] : {std::pair{5, 3}, std::pair{21, 7}, std::pair{6, 9}}) {
    SCOPED_TRACE("n " + std::to_string(n) + ", n_out " + std::to_string(n_out));
    LwprParams params;
    params.update_D = false;
    params.init_D = Eigen::MatrixXd::Constant(1, 1, 1.0);
    params.w_gen = 0.3;
    params.add_threshold = 0.99;
    params.init_lambda = 0.99;  // projections are added after 0.5/(1 − λ) = 50 samples
    params.final_lambda = 0.99;
    params.norm_in = Eigen::VectorXd::Constant(n, 1.0);
    params.norm_out = Eigen::VectorXd::LinSpaced(n_out, 1.0, 2.0);
    LwprModel lanes(n, n_out, params);
    LwprModel lists(n, n_out, params, FieldLayout::kPerOutput);
    ASSERT_TRUE(lanes.lane_layout());
    ASSERT_FALSE(lists.lane_layout());
    std::mt19937_64 rng(n * 100 + n_out);
    std::normal_distribution<double> g(0.0, 0.5);
    std::vector<Eigen::VectorXd> xs;
    for (int t = 0; t < 800; ++t) {
      Eigen::VectorXd x(n), y(n_out);
      for (int i = 0; i < n; ++i) x(i) = g(rng);
      for (int o = 0; o < n_out; ++o) y(o) = std::sin((o + 1) * x(o % n)) + 0.2 * x((o + 1) % n) * o + 0.05 * g(rng);
      lanes.update(x, y);
      lists.update(x, y);
      xs.push_back(x);
    }
    ASSERT_EQ(lanes.size(), lists.size());
    ASSERT_GT(lanes.size(), static_cast<std::size_t>(4 * n_out));
    EXPECT_EQ(lanes.calc_memory_bytes(), lists.calc_memory_bytes());
    EXPECT_TRUE(same_double_bits(lanes.calc_mean_projections(), lists.calc_mean_projections()));
    bool projections_differ = false;
    const std::vector<ReceptiveField> first = lanes.fields(0);
    for (int o = 0; o < n_out; ++o) {
      const std::vector<ReceptiveField> a = lanes.fields(o), b = lists.fields(o);
      ASSERT_EQ(a.size(), b.size());
      EXPECT_EQ(lanes.field_count(o), b.size());
      for (std::size_t f = 0; f < a.size(); ++f) {
        EXPECT_EQ(a[f].n_reg(), b[f].n_reg());
        EXPECT_TRUE(a[f].sxs == b[f].sxs && a[f].directions == b[f].directions && a[f].beta == b[f].beta &&
                    a[f].sum_e_cv2 == b[f].sum_e_cv2 && a[f].mean_x == b[f].mean_x &&
                    same_double_bits(a[f].beta0, b[f].beta0) && a[f].trustworthy == b[f].trustworthy)
            << "output " << o << ", field " << f;
        projections_differ = projections_differ || a[f].n_reg() != first[f].n_reg();
      }
    }
    EXPECT_TRUE(projections_differ) << "the outputs' copies should differ in projections";
    std::ostringstream file_a, file_b;
    write_lwpr_model(lanes, file_a);
    write_lwpr_model(lists, file_b);
    EXPECT_TRUE(file_a.str() == file_b.str()) << "the model files differ";
    std::vector<std::vector<ReceptiveField>> saved;
    for (int o = 0; o < n_out; ++o) saved.push_back(lists.fields(o));
    const LwprModel restored(n, n_out, params, saved, lists.n_updates());
    EXPECT_TRUE(restored.lane_layout());
    saved[1][0].lambda = std::nextafter(saved[1][0].lambda, 0.0);
    const LwprModel mixed(n, n_out, params, saved, lists.n_updates());
    EXPECT_FALSE(mixed.lane_layout());
    auto wa = lanes.make_workspace(), wb = lists.make_workspace(), wr = restored.make_workspace();
    LwprPredictionDetail da, db;
    Prediction va, vb;
    for (std::size_t t = 0; t < 300; ++t) {
      const Eigen::VectorXd& x = xs[t * 2];
      const Prediction a = lanes.predict(x, *wa, da), b = lists.predict(x, *wb, db), r = restored.predict(x, *wr);
      lanes.predict_values_into(x, *wa, va);
      lists.predict_values_into(x, *wb, vb);
      for (int o = 0; o < n_out; ++o) {
        ASSERT_TRUE(same_double_bits(a.value(o), b.value(o))) << "t " << t << ", output " << o;
        ASSERT_TRUE(same_double_bits(a.confidence(o), b.confidence(o))) << "t " << t << ", output " << o;
        ASSERT_TRUE(same_double_bits(r.value(o), b.value(o))) << "t " << t << ", output " << o;
        ASSERT_TRUE(same_double_bits(va.value(o), vb.value(o))) << "t " << t << ", output " << o;
        ASSERT_TRUE(same_double_bits(da.max_activation(o), db.max_activation(o)));
        ASSERT_EQ(a.output_trusted[o], b.output_trusted[o]);
      }
      ASSERT_TRUE(same_double_bits(a.max_activation, b.max_activation));
    }
  }
}

}  // namespace
}  // namespace armfarm::lwpr
