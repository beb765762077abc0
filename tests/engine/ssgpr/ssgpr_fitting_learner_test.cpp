// SsgprFittingLearner: untrusted until its fit batch is complete; then exactly the model that the
// fit of those samples gives, trained on them (checked against building that model by hand);
// bad samples are rejected without being kept; and the job factory builds it.
#include "engine/ssgpr/ssgpr_fitting_learner.hpp"

#include "engine/learning/learner_factory.hpp"
#include "engine/random/random_stream.hpp"
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace armfarm::ssgpr {
namespace {

struct Data {
  std::vector<Eigen::VectorXd> x, y;
};

// 2 inputs → 2 outputs: a smooth function of x₁ only (x₂ is irrelevant) plus noise.
Data make_data(int n, std::uint64_t seed) {
  RandomStream stream(seed, "test.fitting");
  Data d;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd x(2), y(2);
    x << stream.uniform(-2.0, 2.0), stream.uniform(-2.0, 2.0);
    y << 3.0 * std::sin(1.5 * x(0)) + 0.05 * stream.normal(), 2.0 * std::cos(x(0)) + 0.05 * stream.normal();
    d.x.push_back(x);
    d.y.push_back(y);
  }
  return d;
}

SsgprParams make_start() {
  SsgprParams p;
  p.features = 60;
  p.lengthscales = Eigen::VectorXd::Constant(1, 1.0);
  p.trust_min_samples = 10;
  return p;
}

SsgprFitConfig make_fit() {
  SsgprFitConfig fit;
  fit.iterations = 30;
  return fit;
}

std::string save(const SsgprModel& model) {
  std::ostringstream out(std::ios::binary);
  write_ssgpr_model(model, out);
  return out.str();
}

TEST(SsgprFittingLearner, UntrustedUntilTheBatchThenTheModelFittedOnIt) {
  const Data data = make_data(120, 3);
  const std::size_t batch = 50;
  SsgprFittingLearner learner(2, 2, make_start(), batch, make_fit());
  auto workspace = learner.make_workspace();
  for (std::size_t i = 0; i + 1 < batch; ++i) learner.update(data.x[i], data.y[i]);
  EXPECT_FALSE(learner.fitted());
  EXPECT_EQ(learner.n_updates(), batch - 1);
  EXPECT_EQ(learner.calc_memory_bytes(), sizeof(double) * (batch - 1) * 4);
  const Prediction before = learner.predict(data.x[0], *workspace);
  EXPECT_FALSE(before.trustworthy);
  EXPECT_EQ(before.output_trusted, std::vector<bool>(2, false));
  EXPECT_EQ(before.value, Eigen::VectorXd::Zero(2));
  EXPECT_TRUE(std::isinf(before.confidence(0)));
  EXPECT_EQ(learner.fit_seconds(), 0.0);

  learner.update(data.x[batch - 1], data.y[batch - 1]);
  ASSERT_TRUE(learner.fitted());
  EXPECT_GT(learner.fit_seconds(), 0.0);
  EXPECT_GT(learner.fit_report().log_likelihood_end, learner.fit_report().log_likelihood_start);
  for (std::size_t i = batch; i < data.x.size(); ++i) learner.update(data.x[i], data.y[i]);
  EXPECT_EQ(learner.n_updates(), data.x.size());

  // The same by hand: fit on the first `batch` samples, build the model, learn everything.
  Eigen::MatrixXd X(batch, 2), Y(batch, 2);
  for (std::size_t i = 0; i < batch; ++i) {
    X.row(static_cast<Eigen::Index>(i)) = data.x[i].transpose();
    Y.row(static_cast<Eigen::Index>(i)) = data.y[i].transpose();
  }
  SsgprFitConfig fit = make_fit();
  fit.max_samples = batch;
  SsgprModel by_hand(2, 2, calc_fitted_params(X, Y, make_start(), fit));
  for (std::size_t i = 0; i < data.x.size(); ++i) by_hand.update(data.x[i], data.y[i]);
  EXPECT_EQ(save(learner.model()), save(by_hand));
  EXPECT_EQ(learner.calc_memory_bytes(), by_hand.calc_memory_bytes());

  // The fit found the irrelevant input: its lengthscale is the longer.
  const Eigen::VectorXd& l = learner.model().params().lengthscales;
  ASSERT_EQ(l.size(), 2);
  EXPECT_GT(l(1), 2.0 * l(0));
  // And the workspace made before the fit predicts with the fitted model.
  const Data test = make_data(50, 4);
  double error = 0.0, variance = 0.0;
  for (std::size_t i = 0; i < test.x.size(); ++i) {
    const Prediction p = learner.predict(test.x[i], *workspace);
    ASSERT_TRUE(p.trustworthy);
    error += (p.value - test.y[i]).squaredNorm();
    variance += test.y[i].squaredNorm();
  }
  EXPECT_LT(error / variance, 0.01);
}

TEST(SsgprFittingLearner, BadSamplesAreNotKept) {
  SsgprFittingLearner learner(2, 1, make_start(), 10, make_fit());
  Eigen::VectorXd x(2), y(1);
  x << 0.1, std::numeric_limits<double>::quiet_NaN();
  y << 1.0;
  EXPECT_THROW(learner.update(x, y), std::invalid_argument);
  EXPECT_THROW(learner.update(Eigen::VectorXd::Zero(3), y), std::invalid_argument);
  EXPECT_THROW(learner.update(Eigen::VectorXd::Zero(2), Eigen::VectorXd::Constant(1, INFINITY)), std::invalid_argument);
  EXPECT_EQ(learner.n_updates(), 0u);
  EXPECT_THROW(SsgprFittingLearner(2, 1, make_start(), 1, make_fit()), std::invalid_argument);
}

TEST(SsgprFittingLearner, FactoryBuildsTheJobsSsgprWithLengthscalesInInputStds) {
  LearningConfig config;
  config.learner = LearnerKind::ssgpr;
  config.ssgpr.params.features = 30;
  config.ssgpr.params.lengthscales = Eigen::VectorXd::Constant(1, 2.0);
  config.ssgpr.fit_samples = 0;
  Eigen::VectorXd scale(3);
  scale << 0.5, 1.0, 4.0;
  std::unique_ptr<Learner> learner = make_learner(config, 3, 1, scale);
  const auto* model = dynamic_cast<const SsgprModel*>(learner.get());
  ASSERT_NE(model, nullptr);
  EXPECT_EQ(model->params().lengthscales, Eigen::Vector3d(1.0, 2.0, 8.0));
  EXPECT_EQ(learner->size(), 30u);

  config.ssgpr.fit_samples = 40;
  learner = make_learner(config, 3, 1, scale);
  EXPECT_NE(dynamic_cast<const SsgprFittingLearner*>(learner.get()), nullptr);

  config.ssgpr.params.lengthscales = Eigen::VectorXd::Constant(2, 1.0);  // neither 1 nor 3
  try {
    make_learner(config, 3, 1, scale);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()), "learning.ssgpr: lengthscales has 2 elements, expected 1 or 3");
  }
}

}  // namespace
}  // namespace armfarm::ssgpr
