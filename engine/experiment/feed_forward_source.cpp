#include "engine/experiment/feed_forward_source.hpp"

#include "engine/experiment/nominal_inverse_dynamics.hpp"

#include <chrono>
#include <stdexcept>

namespace armfarm {

Eigen::VectorXd make_learner_input(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
  Eigen::VectorXd x(q.size() + qd.size() + qdd.size());
  x << q, qd, qdd;
  return x;
}

bool is_output_trusted(const Prediction& prediction, int output) {
  return static_cast<std::size_t>(output) < prediction.output_trusted.size() ? prediction.output_trusted[static_cast<std::size_t>(output)]
                                                                               : prediction.trustworthy;
}

Eigen::VectorXd calc_trusted_part(const Prediction& prediction) {
  Eigen::VectorXd value = Eigen::VectorXd::Zero(prediction.value.size());
  for (Eigen::Index j = 0; j < value.size(); ++j) {
    if (is_output_trusted(prediction, static_cast<int>(j))) value[j] = prediction.value[j];
  }
  return value;
}

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
    term.torque = calc_nominal_inverse_dynamics(nominal_, q_desired, qd_desired, qdd_desired, ArmSimulationOptions{}.coulomb_velocity_scale);
    return term;
  }
  const auto start = std::chrono::steady_clock::now();
  input_.resize(q_desired.size() + qd_desired.size() + qdd_desired.size());
  input_ << q_desired, qd_desired, qdd_desired;  // make_learner_input's (q, q̇, q̈), into the kept vector
  learner_->predict_into(input_, *workspace_, prediction_);
  const Prediction& prediction = prediction_;
  if (clock_) {
    clock_->predict_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++clock_->predictions;
  }
  term.from_learner = true;
  // calc_trusted_part's values (an untrusted output's torque is 0), with the flags beside them.
  term.torque.resize(prediction.value.size());
  term.torque.setZero();
  term.output_trusted.resize(static_cast<std::size_t>(prediction.value.size()));
  for (Eigen::Index j = 0; j < prediction.value.size(); ++j) {
    const bool trusted = is_output_trusted(prediction, static_cast<int>(j));
    term.output_trusted[static_cast<std::size_t>(j)] = trusted;
    if (trusted) term.torque[j] = prediction.value[j];
  }
  return term;
}

}  // namespace armfarm
