// One model-file layer for every learner: bytes → learner → the same bytes, recognised by magic.
#include "engine/learning/learner_model_file.hpp"
#include "engine/lwpr/lwpr_model.hpp"
#include "engine/ssgpr/ssgpr_fitting_learner.hpp"
#include "engine/ssgpr/ssgpr_model.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace armfarm {
namespace {

template <typename Model>
void train_on_sine(Model& model) {
  for (int i = 0; i < 300; ++i) {
    Eigen::VectorXd x(2);
    x << std::sin(0.05 * i), std::cos(0.031 * i);
    Eigen::VectorXd y(1);
    y << std::sin(2 * x(0)) + 0.5 * x(1);
    model.update(x, y);
  }
}

void expect_same_predictions(const Learner& a, const Learner& b) {
  auto wa = a.make_workspace(), wb = b.make_workspace();
  for (int i = 0; i < 20; ++i) {
    Eigen::VectorXd x(2);
    x << -0.9 + 0.09 * i, 0.4 - 0.03 * i;
    const Prediction pa = a.predict(x, *wa), pb = b.predict(x, *wb);
    EXPECT_EQ(pa.value(0), pb.value(0)) << i;
    EXPECT_EQ(pa.confidence(0), pb.confidence(0)) << i;
  }
}

TEST(LearnerModelFile, LwprAndSsgprRoundTripBitExactlyAndAreRecognisedByMagic) {
  lwpr::LwprParams lp;
  lp.init_D = Eigen::MatrixXd::Constant(1, 1, 4.0);
  lwpr::LwprModel lwpr(2, 1, lp);
  train_on_sine(lwpr);
  ssgpr::SsgprParams sp;
  sp.features = 40;
  ssgpr::SsgprModel ssgpr(2, 1, sp);
  train_on_sine(ssgpr);
  for (const Learner* learner : {static_cast<const Learner*>(&lwpr), static_cast<const Learner*>(&ssgpr)}) {
    const std::string bytes = encode_learner_model(*learner);
    const auto loaded = decode_learner_model(bytes);
    EXPECT_EQ(loaded->n_updates(), learner->n_updates());
    EXPECT_EQ(loaded->size(), learner->size());
    EXPECT_EQ(encode_learner_model(*loaded), bytes);
    expect_same_predictions(*learner, *loaded);
  }
  EXPECT_EQ(find_learner_model_kind(encode_learner_model(lwpr)), "lwpr");
  EXPECT_EQ(find_learner_model_kind(encode_learner_model(ssgpr)), "ssgpr");
  EXPECT_EQ(find_learner_model_kind("not a model"), "");
  try {
    decode_learner_model("PK\x03\x04 a zip file");
    FAIL() << "decoded a zip file";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("byte 0"), std::string::npos) << error.what();
  }
}

// An SSGPR learner that fits its hyperparameters stores the model it fitted (failed on main before
// the dispatch became one visit: "this kind of learner has no model file format").
TEST(LearnerModelFile, AFittingSsgprLearnerStoresItsFittedModelAndRefusesBeforeItsFit) {
  ssgpr::SsgprParams start;
  start.features = 30;
  ssgpr::SsgprFitConfig fit;
  fit.iterations = 10;
  ssgpr::SsgprFittingLearner unfitted(2, 1, start, 400, fit);
  train_on_sine(unfitted);  // 300 of 400 samples: no fit yet
  ASSERT_FALSE(unfitted.fitted());
  try {
    encode_learner_model(unfitted);
    FAIL() << "encoded an unfitted learner";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("300 of its 400 samples"), std::string::npos) << error.what();
  }

  ssgpr::SsgprFittingLearner fitting(2, 1, start, 100, fit);
  train_on_sine(fitting);
  ASSERT_TRUE(fitting.fitted());
  const std::string bytes = encode_learner_model(fitting);
  EXPECT_EQ(find_learner_model_kind(bytes), "ssgpr");
  EXPECT_EQ(bytes, encode_learner_model(fitting.model()));
  const auto loaded = decode_learner_model(bytes);
  EXPECT_EQ(loaded->n_updates(), 300u);
  expect_same_predictions(fitting, *loaded);
  EXPECT_EQ(find_ssgpr_model(fitting), &fitting.model());
  EXPECT_EQ(find_ssgpr_model(unfitted), nullptr);
  EXPECT_EQ(find_lwpr_model(fitting), nullptr);
}

}  // namespace
}  // namespace armfarm
