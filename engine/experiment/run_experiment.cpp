#include "engine/experiment/run_experiment.hpp"

#include "engine/control/composite_controller.hpp"
#include "engine/control/pd_gains.hpp"
#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/nominal_inverse_dynamics.hpp"
#include "engine/experiment/series_recorder.hpp"
#include "engine/experiment/signal_statistics.hpp"
#include "engine/lwpr/lwpr_model.hpp"
#include "engine/model/arm_reach.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/random/random_stream.hpp"
#include "engine/trajectory/trajectory.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// 1-based joint numbers → the same numbers, every movable joint for an empty list (validate()
/// checked them).
std::vector<int> resolve_joint_numbers(const ArmModel& model, const std::vector<int>& numbers) {
  if (!numbers.empty()) return numbers;
  std::vector<int> result;
  for (int i = 1; i <= static_cast<int>(model.movable_joints().size()); ++i) result.push_back(i);
  return result;
}

Eigen::VectorXd concat(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& c) {
  Eigen::VectorXd x(a.size() + b.size() + c.size());
  x << a, b, c;
  return x;
}

struct Sample {
  Eigen::VectorXd x;  ///< q, q̇, q̈ (measured) at the start of a tick
  Eigen::VectorXd y;  ///< the torque applied during the tick
};

/// Statistics of one loop or reach of the evaluation pass (figure 6.7, the TRIAL series).
struct SegmentStatistics {
  double start_time = 0.0;
  long ticks = 0;
  double feedback_abs_sum = 0.0;      ///< summed over joints and ticks
  double feed_forward_abs_sum = 0.0;
  double squared_error_sum = 0.0;     ///< rad², summed over joints and ticks
  std::size_t receptive_fields = 0;   ///< at the segment's end
};

enum class PassKind { collect, evaluate };

class ExperimentRun {
 public:
  ExperimentRun(const ArmModel& model, const JobConfig& config, const std::function<bool()>& should_stop)
      : model_(model),
        config_(config),
        should_stop_(should_stop),
        joint_numbers_(resolve_joint_numbers(model, config.active_joints)),
        active_indices_(make_indices(joint_numbers_)),
        nominal_(model, active_indices_),
        n_(nominal_.dof()) {
    trajectory_ = build_trajectory(config.trajectory, nominal_, config.simulation.dt, config.seed);
    if (trajectory_.size() < 2) throw std::invalid_argument("trajectory: needs at least 2 samples");
    gains_ = make_pd_gains(config.control, nominal_);
    if (config.mismatch.payload.mass > 0.0) {
      true_dynamics_ = std::make_unique<ArmDynamics>(model, active_indices_, config.mismatch.payload);
    }
    nominal_viscous_ = nominal_.viscous_damping();
    nominal_coulomb_ = nominal_.coulomb_friction();
    true_viscous_ = config.mismatch.viscous.size() ? expand_per_joint(config.mismatch.viscous, n_, 0.0, "mismatch.viscous")
                                                   : nominal_.viscous_damping();
    true_coulomb_ = config.mismatch.coulomb.size() ? expand_per_joint(config.mismatch.coulomb, n_, 0.0, "mismatch.coulomb")
                                                   : nominal_.coulomb_friction();
    if (uses_learner()) make_learner();
    reach_ = calc_reach(model);
    recorder_ = std::make_unique<SeriesRecorder>(config.recording.series, joint_numbers_);
  }

  JobOutcome run() {
    wall_start_ = Clock::now();
    ArmSimulationOptions options;
    options.active_joints = active_indices_;
    options.integrator = config_.simulation.integrator;
    options.accuracy = config_.simulation.integrator_accuracy;
    const bool mismatch_from_start = config_.mismatch.start_time <= 0.0;
    if (mismatch_from_start) apply_mismatch(options);
    ArmSimulation plant(model_, options);

    if (config_.learning.mode == LearningMode::batch) {
      const CompositeController collector(ControlMode::feedback, gains_, config_.learning.collect_gain_scale,
                                          nominal_.effort_limits(), config_.control.limit_torque);
      std::vector<Sample> samples;
      for (int repeat = 0; repeat < config_.learning.collect_repeats; ++repeat) {
        if (!run_pass(plant, collector, PassKind::collect, &samples)) return finish();
      }
      train_in_batch(samples);
    }

    const CompositeController controller(config_.control.mode, gains_, config_.control.gain_scale, nominal_.effort_limits(),
                                         config_.control.limit_torque);
    if (!run_pass(plant, controller, PassKind::evaluate, nullptr)) return finish();
    write_evaluation_metrics();
    return finish();
  }

 private:
  static std::vector<int> make_indices(const std::vector<int>& numbers) {
    std::vector<int> indices;
    for (int number : numbers) indices.push_back(number - 1);
    return indices;
  }

  bool uses_learner() const {
    return config_.learning.mode != LearningMode::none ||
           (config_.control.feed_forward == FeedForwardSource::learner && config_.control.mode != ControlMode::feedback);
  }

  void make_learner() {
    lwpr::LwprParams params = config_.learning.lwpr;
    if (config_.learning.normalize_inputs) {
      Eigen::VectorXd scale(3 * n_);
      for (int block = 0; block < 3; ++block) {
        const Eigen::MatrixXd& signal = block == 0 ? trajectory_.q : block == 1 ? trajectory_.qd : trajectory_.qdd;
        for (int j = 0; j < n_; ++j) {
          const Eigen::VectorXd column = signal.col(j);
          const double mean = column.mean();
          const double deviation = std::sqrt((column.array() - mean).square().mean());
          scale[block * n_ + j] = deviation > 1e-6 ? deviation : 1.0;
        }
      }
      params.norm_in = scale;
    }
    try {
      learner_ = std::make_unique<lwpr::LwprModel>(3 * n_, n_, params);
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument(std::string("learning.lwpr: ") + error.what());
    }
    workspace_ = learner_->make_workspace();
  }

  void apply_mismatch(ArmSimulationOptions& options) const {
    options.payload = config_.mismatch.payload;
    if (config_.mismatch.viscous.size()) options.friction_override.viscous = true_viscous_;
    if (config_.mismatch.coulomb.size()) options.friction_override.coulomb = true_coulomb_;
  }

  void apply_mismatch(ArmSimulation& plant) const {
    plant.set_payload(config_.mismatch.payload);
    JointFrictionOverride friction;
    if (config_.mismatch.viscous.size()) friction.viscous = true_viscous_;
    if (config_.mismatch.coulomb.size()) friction.coulomb = true_coulomb_;
    plant.set_friction_override(friction);
  }

  /// The torque the true plant needs for (q, q̇, q̈): rigid body (with payload once present)
  /// plus its joint friction, the ground truth a learned model is scored against.
  Eigen::VectorXd calc_true_torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                   bool mismatch_present) {
    ArmDynamics& dynamics = (mismatch_present && true_dynamics_) ? *true_dynamics_ : nominal_;
    return calc_inverse_dynamics_with_friction(dynamics, q, qd, qdd, mismatch_present ? true_viscous_ : nominal_viscous_,
                                               mismatch_present ? true_coulomb_ : nominal_coulomb_,
                                               ArmSimulationOptions{}.coulomb_velocity_scale);
  }

  static bool is_output_trusted(const Prediction& prediction, int output) {
    return static_cast<std::size_t>(output) < prediction.output_trusted.size() ? prediction.output_trusted[output]
                                                                                 : prediction.trustworthy;
  }
  /// The prediction with each untrusted output replaced by 0 (no feed-forward for that joint only).
  Eigen::VectorXd calc_trusted_part(const Prediction& prediction) const {
    Eigen::VectorXd value = Eigen::VectorXd::Zero(n_);
    for (int j = 0; j < n_; ++j) {
      if (is_output_trusted(prediction, j)) value[j] = prediction.value[j];
    }
    return value;
  }

  Prediction predict(const Eigen::VectorXd& x) {
    const auto start = Clock::now();
    Prediction prediction = learner_->predict(x, *workspace_);
    predict_seconds_ += seconds_since(start);
    ++predictions_;
    return prediction;
  }

  void update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
    const auto start = Clock::now();
    learner_->update(x, y);
    update_seconds_ += seconds_since(start);
    ++updates_;
  }

  bool stop(JobStatus status, double time, std::string message) {
    outcome_.status = status;
    outcome_.end_time = time;
    outcome_.message = std::move(message);
    return false;
  }

  /// One pass over the trajectory. Returns false when the job ended (diverged or stopped).
  bool run_pass(ArmSimulation& plant, const CompositeController& controller, PassKind kind, std::vector<Sample>* collected) {
    const bool evaluate = kind == PassKind::evaluate;
    const double dt = config_.simulation.dt;
    const double pass_start = plant.time();
    plant.set_state(pass_start, trajectory_.q.row(0).transpose(), trajectory_.qd.row(0).transpose());
    const bool mismatch_later = config_.mismatch.start_time > 0.0;
    bool mismatch_present = !mismatch_later;
    const Eigen::VectorXd velocity_limits = nominal_.velocity_limits() * config_.divergence.velocity_limit_factor;
    double over_bound_since = -1.0;
    const int ticks = trajectory_.size();
    std::size_t segment = 0;
    if (evaluate) {
      tracking_ = NmseAccumulator(n_);
      task_tracking_ = NmseAccumulator(3);
      model_accuracy_ = NmseAccumulator(n_);
      share_ = FeedForwardShareAccumulator(n_);
      saturated_ticks_ = Eigen::VectorXd::Zero(n_);
      untrusted_ticks_ = Eigen::VectorXd::Zero(n_);
      segments_.assign(1, SegmentStatistics{pass_start});
    }

    for (int k = 0; k < ticks; ++k) {
      const double t = plant.time();
      const double elapsed = t - pass_start;
      if (should_stop_ && should_stop_()) return stop(JobStatus::timeout, t, "stopped before the end of the run");
      if (evaluate && mismatch_later && !mismatch_present && elapsed >= config_.mismatch.start_time - 1e-12) {
        apply_mismatch(plant);
        mismatch_present = true;
      }
      if (evaluate && segment + 1 < trajectory_.segment_starts.size() &&
          k == trajectory_.segment_starts[segment + 1]) {
        segments_.back().receptive_fields = learner_ ? learner_->size() : 0;
        segments_.push_back(SegmentStatistics{t});
        ++segment;
      }
      const Eigen::VectorXd q_desired = trajectory_.q.row(k).transpose();
      const Eigen::VectorXd qd_desired = trajectory_.qd.row(k).transpose();
      const Eigen::VectorXd qdd_desired = trajectory_.qdd.row(k).transpose();
      const Eigen::VectorXd q = plant.q();
      const Eigen::VectorXd qd = plant.qd();

      // Divergence (figure 4.4 of the thesis: gains too high tear the arm apart).
      if (!q.allFinite() || !qd.allFinite()) return stop(JobStatus::diverged, t, "the state became NaN or Inf");
      for (int j = 0; j < n_; ++j) {
        if (std::fabs(qd[j]) > velocity_limits[j]) {
          return stop(JobStatus::diverged, t,
                      "joint " + std::to_string(joint_numbers_[j]) + " velocity " + std::to_string(qd[j]) +
                          " rad/s exceeds its limit " + std::to_string(velocity_limits[j]) + " rad/s");
        }
      }
      const Eigen::VectorXd error = q_desired - q;
      if (error.cwiseAbs().maxCoeff() > config_.divergence.max_tracking_error) {
        if (over_bound_since < 0.0) over_bound_since = t;
        if (t - over_bound_since > config_.divergence.max_error_duration) {
          return stop(JobStatus::diverged, t,
                      "tracking error above " + std::to_string(config_.divergence.max_tracking_error) + " rad for more than " +
                          std::to_string(config_.divergence.max_error_duration) + " s");
        }
      } else {
        over_bound_since = -1.0;
      }

      // Feed-forward at the desired state.
      Eigen::VectorXd feed_forward = Eigen::VectorXd::Zero(n_);
      const bool wants_feed_forward = evaluate && config_.control.mode != ControlMode::feedback;
      if (wants_feed_forward && config_.control.feed_forward == FeedForwardSource::analytic) {
        feed_forward = calc_nominal_inverse_dynamics(nominal_, q_desired, qd_desired, qdd_desired,
                                                     ArmSimulationOptions{}.coulomb_velocity_scale);
      } else if (wants_feed_forward && config_.control.feed_forward == FeedForwardSource::learner) {
        const Prediction prediction = predict(concat(q_desired, qd_desired, qdd_desired));
        feed_forward = calc_trusted_part(prediction);
        for (int j = 0; j < n_; ++j) untrusted_ticks_[j] += is_output_trusted(prediction, j) ? 0.0 : 1.0;
        model_accuracy_.add(calc_true_torque(q_desired, qd_desired, qdd_desired, mismatch_present), feed_forward);
      }
      const ControlCommand command = controller.calc_command(q_desired, qd_desired, q, qd, feed_forward);

      if (evaluate) {
        tracking_.add(q_desired, q);
        const Eigen::Vector3d position = nominal_.calc_end_effector_position(q);
        const Eigen::Vector3d position_desired = trajectory_.task_position.row(k).transpose();
        task_tracking_.add(position_desired, position);
        share_.add(command.feed_forward, command.feedback);
        for (int j = 0; j < n_; ++j) saturated_ticks_[j] += command.saturated[j] ? 1.0 : 0.0;
        SegmentStatistics& stats = segments_.back();
        ++stats.ticks;
        stats.feedback_abs_sum += command.feedback.cwiseAbs().sum();
        stats.feed_forward_abs_sum += command.feed_forward.cwiseAbs().sum();
        stats.squared_error_sum += error.squaredNorm();
        if (k % config_.recording.every == 0) record(t, q, qd, q_desired, qd_desired, qdd_desired, position, position_desired, command);
      }

      try {
        plant.step(command.torque, dt);
      } catch (const std::exception& failure) {
        return stop(JobStatus::diverged, t, std::string("integrator failed: ") + failure.what());
      }
      simulated_seconds_ += dt;
      const Eigen::VectorXd qdd_measured = (plant.qd() - qd) / dt;  // the thesis's backward difference
      if (!qdd_measured.allFinite()) return stop(JobStatus::diverged, plant.time(), "the state became NaN or Inf");
      if (evaluate) last_acceleration_ = qdd_measured;
      if (collected) collected->push_back(Sample{concat(q, qd, qdd_measured), command.torque});
      const bool learn_now = learner_ && ((evaluate && config_.learning.mode == LearningMode::online) ||
                                          (evaluate && config_.learning.mode == LearningMode::batch &&
                                           config_.learning.learn_during_evaluation));
      if (learn_now) update(concat(q, qd, qdd_measured), command.torque);
    }
    if (evaluate) {
      segments_.back().receptive_fields = learner_ ? learner_->size() : 0;
      end_time_ = plant.time();
    }
    return true;
  }

  void record(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& q_desired,
              const Eigen::VectorXd& qd_desired, const Eigen::VectorXd& qdd_desired, const Eigen::Vector3d& position,
              const Eigen::Vector3d& position_desired, const ControlCommand& command) {
    SeriesRecorder& recorder = *recorder_;
    recorder.add("POS", t, position);
    recorder.add("POS_D", t, position_desired);
    recorder.add("PHI", t, q);
    recorder.add("PHI_D", t, q_desired);
    recorder.add("VEL", t, qd);
    recorder.add("VEL_D", t, qd_desired);
    if (recorder.wants("ACC")) recorder.add("ACC", t, last_acceleration_.size() ? last_acceleration_ : Eigen::VectorXd::Zero(n_));
    recorder.add("ACC_D", t, qdd_desired);
    recorder.add("TOR", t, command.torque);
    recorder.add("F", t, command.feedback);
    recorder.add("FF", t, command.feed_forward);
    if (recorder.wants("RF")) {
      recorder.add("RF", t, Eigen::VectorXd::Constant(1, learner_ ? static_cast<double>(learner_->size()) : 0.0));
    }
  }

  void train_in_batch(std::vector<Sample>& samples) {
    RandomStream generator(config_.seed, "learning.batch.shuffle");
    std::vector<std::size_t> order(samples.size());
    std::iota(order.begin(), order.end(), 0);
    generator.shuffle(order.begin(), order.end());
    const auto n_train = static_cast<std::size_t>(std::llround(config_.learning.train_fraction * static_cast<double>(samples.size())));
    std::vector<std::size_t> train(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n_train));
    const std::vector<std::size_t> test(order.begin() + static_cast<std::ptrdiff_t>(n_train), order.end());
    for (int epoch = 0; epoch < config_.learning.epochs; ++epoch) {
      if (epoch > 0) generator.shuffle(train.begin(), train.end());
      for (std::size_t index : train) update(samples[index].x, samples[index].y);
    }
    training_samples_ = static_cast<long>(n_train);
    if (test.empty()) return;
    test_accuracy_ = NmseAccumulator(n_);
    for (std::size_t index : test) {
      const Prediction prediction = predict(samples[index].x);
      test_accuracy_.add(samples[index].y, calc_trusted_part(prediction));
    }
  }

  static Metric make_metric(const std::string& name, std::optional<int> joint, double value, std::string reason) {
    Metric metric{name, joint, std::nullopt, std::nullopt, std::move(reason)};
    if (std::isfinite(value)) {
      metric.value = value;
    } else if (metric.reason.empty()) {
      metric.reason = std::isnan(value) ? "undefined (nothing to average)" : "infinite";
    }
    return metric;
  }
  void add_metric(const std::string& name, double value, std::string reason = {}) {
    outcome_.metrics.push_back(make_metric(name, std::nullopt, value, std::move(reason)));
  }
  void add_joint_metrics(const std::string& name, const Eigen::VectorXd& values, const std::string& reason_if_undefined = {}) {
    for (int j = 0; j < n_; ++j) {
      outcome_.metrics.push_back(
          make_metric(name, joint_numbers_[j], values[j], std::isfinite(values[j]) ? std::string() : reason_if_undefined));
    }
  }
  /// Per joint nMSE (undefined below the floor) and RMSE, then the job rows: the nMSE mean over
  /// the joints where it is defined (its reason says which), the RMSE over every joint's ticks.
  void add_joint_error_metrics(const std::string& nmse_name, const std::string& rmse_name, const NmseAccumulator& errors,
                               const Eigen::VectorXd& std_floor, const std::string& unit) {
    const std::vector<NormalisedError> per_joint = errors.calc_errors(std_floor, unit);
    double sum = 0.0;
    int defined = 0;
    std::string left_out;
    for (int j = 0; j < n_; ++j) {
      const NormalisedError& error = per_joint[static_cast<std::size_t>(j)];
      outcome_.metrics.push_back(Metric{nmse_name, joint_numbers_[j], std::nullopt, error.nmse, error.reason});
      outcome_.metrics.push_back(make_metric(rmse_name, joint_numbers_[j], error.rmse, {}));
      if (error.nmse) {
        sum += *error.nmse;
        ++defined;
      } else {
        left_out += (left_out.empty() ? "" : ", ") + std::to_string(joint_numbers_[j]);
      }
    }
    std::string note = "mean over " + std::to_string(defined) + " of " + std::to_string(n_) + " joints";
    if (!left_out.empty()) note += "; left out (nMSE undefined): joint " + left_out;
    add_metric(nmse_name, defined ? sum / defined : std::nan(""), note);
    add_metric(rmse_name, std::sqrt(errors.calc_mse().mean()));
  }

  /// nMSE floors (see kNmseStdFloorFraction): a fraction of each joint's position range (2π
  /// for an unlimited joint), of its torque range 2·effort limit, of the end effector's 2·reach.
  Eigen::VectorXd calc_angle_std_floor() const {
    Eigen::VectorXd floor(n_);
    const Eigen::VectorXd lower = nominal_.lower_limits(), upper = nominal_.upper_limits();
    for (int j = 0; j < n_; ++j) {
      const double range = std::isfinite(upper[j] - lower[j]) ? upper[j] - lower[j] : 2.0 * M_PI;
      floor[j] = kNmseStdFloorFraction * range;
    }
    return floor;
  }
  Eigen::VectorXd calc_torque_std_floor() const {
    Eigen::VectorXd floor(n_);
    const Eigen::VectorXd limits = nominal_.effort_limits();
    for (int j = 0; j < n_; ++j) {
      // Without an effort limit only exact constancy (numerical noise) is undefined.
      floor[j] = std::isfinite(limits[j]) && limits[j] > 0.0 ? kNmseStdFloorFraction * 2.0 * limits[j] : 1e-12;
    }
    return floor;
  }

  void write_evaluation_metrics() {
    namespace m = metric_names;
    add_joint_error_metrics(m::tracking_nmse, m::tracking_rmse, tracking_, calc_angle_std_floor(), "rad");
    const std::vector<NormalisedError> task =
        task_tracking_.calc_errors(Eigen::Vector3d::Constant(kNmseStdFloorFraction * 2.0 * reach_), "m");
    const std::string* task_nmse[3] = {&m::tracking_nmse_x, &m::tracking_nmse_y, &m::tracking_nmse_z};
    const std::string* task_rmse[3] = {&m::tracking_rmse_x, &m::tracking_rmse_y, &m::tracking_rmse_z};
    for (int axis = 0; axis < 3; ++axis) {
      outcome_.metrics.push_back(Metric{*task_nmse[axis], std::nullopt, std::nullopt, task[axis].nmse, task[axis].reason});
      add_metric(*task_rmse[axis], task[axis].rmse);
    }
    add_metric(m::task_rmse, std::sqrt(task_tracking_.calc_mse().sum()));
    add_joint_metrics(m::ff_fb_ratio_avg, share_.calc_ratio_mean(), "no tick with nonzero torque");
    add_joint_metrics(m::ff_fb_ratio_var, share_.calc_ratio_variance(), "no tick with nonzero torque");
    add_joint_metrics(m::ff_abs_avg, share_.calc_feed_forward_abs_mean());
    add_joint_metrics(m::fb_abs_avg, share_.calc_feedback_abs_mean());
    add_joint_metrics(m::torque_saturation_fraction,
                      saturated_ticks_ / static_cast<double>(std::max<long>(1, tracking_.count())));
    if (test_accuracy_.count() > 0) {
      add_joint_error_metrics(m::test_nmse, m::test_rmse, test_accuracy_, calc_torque_std_floor(), "N·m");
    }
    if (training_samples_ > 0) add_metric(m::n_training_samples, static_cast<double>(training_samples_));
    if (model_accuracy_.count() > 0) {
      add_joint_error_metrics(m::id_nmse, m::id_rmse, model_accuracy_, calc_torque_std_floor(), "N·m");
      const Eigen::VectorXd untrusted = untrusted_ticks_ / static_cast<double>(model_accuracy_.count());
      add_joint_metrics(m::ff_untrusted_fraction, untrusted);
      add_metric(m::ff_untrusted_fraction, untrusted.mean(), "mean over " + std::to_string(n_) + " joints");
    }
    if (learner_) {
      add_metric(m::n_receptive_fields, static_cast<double>(learner_->size()));
      add_metric(m::learner_us_per_update, updates_ ? 1e6 * update_seconds_ / static_cast<double>(updates_) : std::nan(""));
      add_metric(m::learner_us_per_predict, predictions_ ? 1e6 * predict_seconds_ / static_cast<double>(predictions_) : std::nan(""));
    }
    const auto segment_feedback = [this](const SegmentStatistics& stats) {
      return stats.ticks ? stats.feedback_abs_sum / static_cast<double>(stats.ticks * n_) : std::nan("");
    };
    add_metric(m::n_segments, static_cast<double>(segments_.size()));
    add_metric(m::fb_abs_avg_first_segment, segment_feedback(segments_.front()));
    add_metric(m::fb_abs_avg_last_segment, segment_feedback(segments_.back()));
    const auto segment_rmse = [this](const SegmentStatistics& stats) {
      return stats.ticks ? std::sqrt(stats.squared_error_sum / static_cast<double>(stats.ticks * n_)) : std::nan("");
    };
    add_metric(m::tracking_rmse_first_segment, segment_rmse(segments_.front()));
    add_metric(m::tracking_rmse_last_segment, segment_rmse(segments_.back()));
    for (std::size_t s = 0; s < segments_.size(); ++s) {
      const SegmentStatistics& stats = segments_[s];
      const double ticks = static_cast<double>(std::max<long>(1, stats.ticks));
      Eigen::VectorXd row(6);
      row << static_cast<double>(s + 1), stats.start_time, segment_feedback(stats), stats.feed_forward_abs_sum / (ticks * n_),
          std::sqrt(stats.squared_error_sum / (ticks * n_)), static_cast<double>(stats.receptive_fields);
      recorder_->add_row("TRIAL", {"segment", "t", "fb_abs_avg", "ff_abs_avg", "tracking_rmse", "n_receptive_fields"}, row);
    }
  }

  JobOutcome finish() {
    if (outcome_.status == JobStatus::done) outcome_.end_time = end_time_;
    const double wall = seconds_since(wall_start_);
    add_metric(metric_names::simulated_seconds, simulated_seconds_);
    add_metric(metric_names::sim_seconds_per_wall_second, wall > 0.0 ? simulated_seconds_ / wall : std::nan(""));
    outcome_.series = recorder_->take_series();
    return std::move(outcome_);
  }

  const ArmModel& model_;
  const JobConfig& config_;
  const std::function<bool()>& should_stop_;
  std::vector<int> joint_numbers_;
  std::vector<int> active_indices_;
  ArmDynamics nominal_;
  int n_;
  JointTrajectory trajectory_;
  PdGains gains_;
  std::unique_ptr<ArmDynamics> true_dynamics_;
  Eigen::VectorXd true_viscous_, true_coulomb_, nominal_viscous_, nominal_coulomb_;
  std::unique_ptr<lwpr::LwprModel> learner_;
  std::unique_ptr<PredictionWorkspace> workspace_;
  std::unique_ptr<SeriesRecorder> recorder_;

  NmseAccumulator tracking_, task_tracking_, model_accuracy_;
  FeedForwardShareAccumulator share_;
  Eigen::VectorXd saturated_ticks_;
  NmseAccumulator test_accuracy_;
  Eigen::VectorXd untrusted_ticks_;  ///< per joint, ticks whose output was not trusted
  double reach_ = 0.0;               ///< m, the arm's reach (task-space nMSE floor)
  Eigen::VectorXd last_acceleration_;
  std::vector<SegmentStatistics> segments_;
  long training_samples_ = 0;
  long updates_ = 0, predictions_ = 0;
  double update_seconds_ = 0.0, predict_seconds_ = 0.0;
  double simulated_seconds_ = 0.0;
  double end_time_ = 0.0;
  Clock::time_point wall_start_;
  JobOutcome outcome_;
};

}  // namespace

JobOutcome run_experiment(const ArmModel& model, const JobConfig& config, const std::function<bool()>& should_stop) {
  const std::vector<ConfigProblem> problems = validate(config, ModelFacts{static_cast<int>(model.movable_joints().size())});
  if (!problems.empty()) throw std::invalid_argument(make_problems_text(problems));
  ExperimentRun run(model, config, should_stop);
  return run.run();
}

}  // namespace armfarm
