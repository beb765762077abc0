// FeedForwardProvider with a learner: the term it returns on every call equals the learner's own
// predict() at (q, q̇, q̈) with each untrusted output zeroed (calc_trusted_part), bit for bit, and
// its trust flags are is_output_trusted's, although the provider keeps one input vector and one
// Prediction across calls (predict_into) and the learner changes between calls.
#include "engine/experiment/feed_forward_source.hpp"
#include "engine/learning/learner_factory.hpp"
#include "engine/learning/learning_config.hpp"
#include "engine/random/random_stream.hpp"
#include "support/test_arms.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(FeedForwardProvider, EachCallEqualsAFreshPredictionWithUntrustedOutputsZeroed) {
  const ArmModel model = testing::load_lwr3();
  ArmDynamics nominal(model, {0, 1, 3});
  const int n = nominal.dof();
  LearningConfig learning;
  learning.lwpr.init_D = Eigen::MatrixXd::Constant(1, 1, 2.0);
  const auto learner = make_learner(learning, 3 * n, n, Eigen::VectorXd::Ones(3 * n));
  ControlConfig control;  // composite, learner feed-forward
  FeedForwardProvider provider(control, nominal, learner.get(), nullptr);
  ASSERT_TRUE(provider.active());
  const auto reference_workspace = learner->make_workspace();
  RandomStream random(26, "test.feed_forward_source");
  const auto draw = [&](double scale) {
    Eigen::VectorXd v(n);
    for (int j = 0; j < n; ++j) v[j] = scale * (2.0 * random.uniform() - 1.0);
    return v;
  };
  int untrusted = 0, trusted = 0;
  for (int call = 0; call < 300; ++call) {
    // Learn near the origin only, so that far states leave some outputs untrusted.
    if (call < 200) {
      const Eigen::VectorXd x = make_learner_input(draw(0.3), draw(0.3), draw(0.3));
      learner->update(x, Eigen::VectorXd::Constant(n, x.sum()) + x.head(n));
    }
    const double scale = call % 3 == 0 ? 3.0 : 0.3;
    const Eigen::VectorXd q = draw(scale), qd = draw(scale), qdd = draw(scale);
    const FeedForwardTerm term = provider.calc(q, qd, qdd);
    const Prediction expected = learner->predict(make_learner_input(q, qd, qdd), *reference_workspace);
    const Eigen::VectorXd expected_torque = calc_trusted_part(expected);
    ASSERT_TRUE(term.from_learner);
    ASSERT_EQ(term.torque.size(), n);
    ASSERT_EQ(term.output_trusted.size(), static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
      EXPECT_EQ(term.torque[j], expected_torque[j]) << "call " << call << ", joint " << j + 1;
      const bool flag = is_output_trusted(expected, j);
      EXPECT_EQ(term.output_trusted[static_cast<std::size_t>(j)], flag) << "call " << call << ", joint " << j + 1;
      if (!flag) {
        EXPECT_EQ(term.torque[j], 0.0);
        ++untrusted;
      } else {
        ++trusted;
      }
    }
  }
  // Both kinds of output occurred, so both branches were compared.
  EXPECT_GT(untrusted, 0);
  EXPECT_GT(trusted, 0);
}

}  // namespace
}  // namespace armfarm
