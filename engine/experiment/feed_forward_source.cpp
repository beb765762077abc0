#include "engine/experiment/feed_forward_source.hpp"

#include <chrono>
#include <stdexcept>

namespace armfarm {
namespace {

Eigen::VectorXd concat(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& c) {
  Eigen::VectorXd x(a.size() + b.size() + c.size());
  x << a, b, c;
  return x;
}

}  // namespace

FeedForwardProvider::FeedForwardProvider(const ControlConfig& control, ArmDynamics& nominal, const Learner* learner,
                                     LearnerClock* clock)
    : control_(control),
      nominal_(nominal),
      learner_(learner),
      clock_(clock),
      active_(control.mode != ControlMode::feedback && control.feed_forward != FeedForwardSource::none) {
  if (active_ && control.feed_forward == FeedForwardSource::learner) {
    if (!learner_) throw std::invalid_argument("control.feed_forward: is \"learner\" but the job has no learner");
    workspace_ = learner_->make_workspace();
  }
}

FeedForwardTerm FeedForwardProvider::calc(const Eigen::VectorXd& q_desired, const Eigen::VectorXd& qd_desired,
                                        const Eigen::VectorXd& qdd_desired) {
  FeedForwardTerm term;
  term.torque = Eigen::VectorXd::Zero(q_desired.size());
  if (!active_) return term;
  if (control_.feed_forward == FeedForwardSource::analytic) {
    term.torque = nominal_.calc_inverse_dynamics(q_desired, qd_desired, qdd_desired);
    return term;
  }
  const auto start = std::chrono::steady_clock::now();
  const Prediction prediction = learner_->predict(concat(q_desired, qd_desired, qdd_desired), *workspace_);
  if (clock_) {
    clock_->predict_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++clock_->predictions;
  }
  term.from_learner = true;
  term.trusted = prediction.trustworthy;
  if (prediction.trustworthy) term.torque = prediction.value;
  return term;
}

}  // namespace armfarm
