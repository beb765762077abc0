#pragma once
// The feed-forward torque of the composite controller, at the desired state: the learner's
// prediction (a const learner: predicting never changes it; an untrusted output zeroes only its
// own joint), the nominal model's full inverse dynamics (rigid body plus its joint damping and
// friction, nominal_inverse_dynamics.hpp), or none.
#include "engine/experiment/job_config.hpp"
#include "engine/learner/learner.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace armfarm {

/// Wall time spent in the learner (for learner_us_per_update / _per_predict).
struct LearnerClock {
  double update_seconds = 0.0, predict_seconds = 0.0;
  long updates = 0, predictions = 0;
};

struct FeedForwardTerm {
  Eigen::VectorXd torque;     ///< N·m, n; zero on a joint whose output no trustworthy local model predicts
  bool from_learner = false;  ///< the term is the learner's prediction (scored by id_nmse)
  std::vector<bool> output_trusted{};  ///< learner: per joint, whether its output was trusted
};

/// The prediction with each untrusted output replaced by 0: an untrusted output zeroes only
/// its own joint's feed-forward.
Eigen::VectorXd calc_trusted_part(const Prediction& prediction);
/// The learner's input for a state: (q, q̇, q̈) stacked, 3·n_active × 1.
Eigen::VectorXd make_learner_input(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd);
/// Whether output `output` of the prediction was trusted.
bool is_output_trusted(const Prediction& prediction, int output);

class FeedForwardProvider {
 public:
  /// `learner` may be null unless control.feed_forward is learner; `clock` may be null.
  FeedForwardProvider(const ControlConfig& control, ArmDynamics& nominal, const Learner* learner, LearnerClock* clock);

  /// Whether the controller uses a feed-forward at all (not feedback mode, not source none).
  bool active() const { return active_; }
  FeedForwardTerm calc(const Eigen::VectorXd& q_desired, const Eigen::VectorXd& qd_desired, const Eigen::VectorXd& qdd_desired);

 private:
  const ControlConfig& control_;
  ArmDynamics& nominal_;
  const Learner* learner_;
  LearnerClock* clock_;
  std::unique_ptr<PredictionWorkspace> workspace_;
  /// The learner's input and its prediction, kept across ticks: predict_into reuses their
  /// vectors, so a learner feed-forward allocates nothing of its own per tick.
  Eigen::VectorXd input_;
  Prediction prediction_;
  bool active_;
};

}  // namespace armfarm
