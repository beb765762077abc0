// CompositeController::calc_command (engine/control/composite_controller.hpp) on its own, against
// values worked by hand: two joints, kp = (100, 50) N·m/rad, kd = (10, 5) N·m·s/rad, desired
// q = (0.5, −0.2) rad and q̇ = (1, 0) rad/s, measured q = (0.4, 0.1) rad and q̇ = (0.5, 0.2) rad/s.
// Errors e = (0.1, −0.3) rad, ė = (0.5, −0.2) rad/s, so the PD term is
//   kp·e + kd·ė = (10 + 5, −15 − 1) = (15, −16) N·m,
// and the feed-forward handed in is (2, −3) N·m.
#include "engine/control/composite_controller.hpp"
#include "engine/experiment/feed_forward_source.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace armfarm {
namespace {

Eigen::VectorXd vec(double a, double b) { return (Eigen::VectorXd(2) << a, b).finished(); }

PdGains hand_gains() { return PdGains{vec(100.0, 50.0), vec(10.0, 5.0)}; }
Eigen::VectorXd no_limits() { return Eigen::VectorXd::Constant(2, std::numeric_limits<double>::infinity()); }

const Eigen::VectorXd kQDesired = vec(0.5, -0.2), kQdDesired = vec(1.0, 0.0);
const Eigen::VectorXd kQ = vec(0.4, 0.1), kQd = vec(0.5, 0.2);
const Eigen::VectorXd kFeedForward = vec(2.0, -3.0);

ControlCommand command_of(const CompositeController& controller, const Eigen::VectorXd& feed_forward = kFeedForward) {
  return controller.calc_command(kQDesired, kQdDesired, kQ, kQd, feed_forward);
}

void expect_vector(const Eigen::VectorXd& actual, double a, double b, const char* what) {
  ASSERT_EQ(actual.size(), 2) << what;
  EXPECT_NEAR(actual[0], a, 1e-12) << what << " joint 1";
  EXPECT_NEAR(actual[1], b, 1e-12) << what << " joint 2";
}

TEST(CompositeController, FeedbackModeAppliesThePdTermOnly) {
  const CompositeController controller(ControlMode::feedback, hand_gains(), 1.0, no_limits(), true);
  const ControlCommand command = command_of(controller);
  expect_vector(command.feedback, 15.0, -16.0, "feedback");
  expect_vector(command.feed_forward, 0.0, 0.0, "feed-forward (ignored in feedback mode)");
  expect_vector(command.torque, 15.0, -16.0, "torque");
  EXPECT_FALSE(command.saturated.any());
}

TEST(CompositeController, OpenLoopModeAppliesTheFeedForwardOnly) {
  const CompositeController controller(ControlMode::open_loop, hand_gains(), 1.0, no_limits(), true);
  const ControlCommand command = command_of(controller);
  expect_vector(command.feedback, 0.0, 0.0, "feedback (off in open loop)");
  expect_vector(command.feed_forward, 2.0, -3.0, "feed-forward");
  expect_vector(command.torque, 2.0, -3.0, "torque");
}

TEST(CompositeController, CompositeModeAddsBothTerms) {
  const CompositeController controller(ControlMode::composite, hand_gains(), 1.0, no_limits(), true);
  const ControlCommand command = command_of(controller);
  expect_vector(command.feedback, 15.0, -16.0, "feedback");
  expect_vector(command.feed_forward, 2.0, -3.0, "feed-forward");
  expect_vector(command.torque, 17.0, -19.0, "torque");
}

// The learned feed-forward as the job hands it over (feed_forward_source.hpp): the learner's
// prediction with an untrusted output zeroed, so joint 2 runs on its PD term alone.
TEST(CompositeController, LearnedFeedForwardWithAnUntrustedOutputLeavesThatJointOnPd) {
  Prediction prediction;
  prediction.value = vec(2.0, -3.0);
  prediction.confidence = vec(0.1, std::numeric_limits<double>::infinity());
  prediction.output_trusted = {true, false};
  const CompositeController controller(ControlMode::composite, hand_gains(), 1.0, no_limits(), true);
  const ControlCommand command = command_of(controller, calc_trusted_part(prediction));
  expect_vector(command.feed_forward, 2.0, 0.0, "learned feed-forward");
  expect_vector(command.torque, 17.0, -16.0, "torque");
}

TEST(CompositeController, GainScaleMultipliesKpAndKdApart) {
  // kp × 0.2 = (20, 10), kd × 0.5 = (5, 2.5): PD = (2 + 2.5, −3 − 0.5).
  const CompositeController controller(ControlMode::feedback, hand_gains(), 0.2, 0.5, no_limits(), true);
  expect_vector(controller.kp(), 20.0, 10.0, "kp");
  expect_vector(controller.kd(), 5.0, 2.5, "kd");
  expect_vector(command_of(controller).torque, 4.5, -3.5, "torque");
  // The one-scale constructor scales both by the same factor.
  const CompositeController same(ControlMode::feedback, hand_gains(), 0.2, no_limits(), true);
  expect_vector(same.kd(), 2.0, 1.0, "kd at one scale");
  expect_vector(command_of(same).torque, 3.0, -3.2, "torque at one scale");
}

TEST(CompositeController, TorqueIsClippedToTheEffortLimitsWithItsSign) {
  // Composite (17, −19) against limits (20, 18): joint 2 clips to −18, joint 1 passes.
  const CompositeController controller(ControlMode::composite, hand_gains(), 1.0, vec(20.0, 18.0), true);
  const ControlCommand command = command_of(controller);
  expect_vector(command.torque, 17.0, -18.0, "torque");
  EXPECT_FALSE(command.saturated[0]);
  EXPECT_TRUE(command.saturated[1]);
  // The terms are reported as computed; only the sum the plant receives is clipped.
  expect_vector(command.feedback, 15.0, -16.0, "feedback");
  expect_vector(command.feed_forward, 2.0, -3.0, "feed-forward");

  // A positive excess clips to +limit; a command exactly at the limit is not saturated.
  const CompositeController tight(ControlMode::composite, hand_gains(), 1.0, vec(10.0, 19.0), true);
  const ControlCommand at_limit = command_of(tight);
  expect_vector(at_limit.torque, 10.0, -19.0, "torque at tight limits");
  EXPECT_TRUE(at_limit.saturated[0]);
  EXPECT_FALSE(at_limit.saturated[1]);
}

TEST(CompositeController, LimitTorqueOffPassesTheCommandUnclipped) {
  const CompositeController controller(ControlMode::composite, hand_gains(), 1.0, vec(1.0, 1.0), false);
  const ControlCommand command = command_of(controller);
  expect_vector(command.torque, 17.0, -19.0, "torque");
  EXPECT_FALSE(command.saturated.any());
}

}  // namespace
}  // namespace armfarm
