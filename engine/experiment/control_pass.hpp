#pragma once
// One pass of the plant over a desired trajectory under a controller, tick by tick — the
// stages every phase of a job shares (collection, learning, evaluation, held-out evaluation):
//   measure → check divergence → feed-forward at the desired state → command → statistics and
//   recording → step the plant → measured acceleration → collect the sample / learn it.
// Which stages do anything is the caller's choice through PassOptions.
#include "engine/control/composite_controller.hpp"
#include "engine/experiment/experiment_metrics.hpp"
#include "engine/experiment/feed_forward_source.hpp"
#include "engine/experiment/job_outcome.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/experiment/pass_statistics.hpp"
#include "engine/experiment/series_recorder.hpp"
#include "engine/learner/learner.hpp"
#include "engine/random/random_stream.hpp"
#include "engine/trajectory/trajectory.hpp"

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace armfarm {

/// One learning sample: x = (q, q̇, q̈) measured at the start of a tick (q̈ the backward
/// difference of the measured velocity over the tick), y = the torque applied during it.
struct Sample {
  Eigen::VectorXd x;
  Eigen::VectorXd y;
};

/// Wall time of the stages of a pass's control ticks (tick_us_* metrics, job_report.hpp): where a
/// tick goes. Seconds summed over `ticks`; a stage a pass does not run stays 0.
struct TickClock {
  double physics = 0.0;        ///< stepping the plant over the tick (integrator)
  double feed_forward = 0.0;   ///< the feed-forward term (learner prediction or nominal inverse dynamics)
  double control = 0.0;        ///< the controller's command and the divergence check
  double true_dynamics = 0.0;  ///< the true plant's inverse dynamics at the desired state (id_nmse)
  double statistics = 0.0;     ///< tracking statistics (end-effector position) and series recording
  double learning = 0.0;       ///< the learner's update (and sample collection)
  long ticks = 0;
  double total() const { return physics + feed_forward + control + true_dynamics + statistics + learning; }
};

/// How a pass ended: done, or the job ends (diverged, timeout) at end_time for `message`.
struct PassResult {
  JobStatus status = JobStatus::done;
  double end_time = 0.0;
  std::string message;
  double simulated_seconds = 0.0;  ///< plant time advanced by the pass
  bool ok() const { return status == JobStatus::done; }
};

struct PassOptions {
  const CompositeController* controller = nullptr;  ///< required
  FeedForwardProvider* feed_forward = nullptr;      ///< null: no feed-forward
  Learner* learner = nullptr;        ///< learns every tick when set; null: nothing learns
  const Learner* observed = nullptr; ///< whose size the statistics and RF series report (may be null)
  LearnerClock* clock = nullptr;
  TickClock* tick_clock = nullptr;  ///< accumulates the stages' wall time when set
  std::vector<Sample>* samples = nullptr;  ///< appends every tick's sample when set
  PassStatistics* statistics = nullptr;
  SeriesRecorder* recorder = nullptr;      ///< records every `record_every` ticks when set
  int record_every = 1;
  /// The mismatch appears config.mismatch.start_time into the pass (evaluation and held-out
  /// passes); otherwise the plant keeps what it has (collection passes).
  bool schedule_mismatch = false;
  Eigen::VectorXd start_offset;   ///< rad, added to the first desired angles at the start (empty: none)
  RandomStream* noise = nullptr;  ///< sensor noise stream; with noise_q/noise_qd > 0
  double noise_q = 0.0;           ///< rad, std of the noise on the measured angles
  double noise_qd = 0.0;          ///< rad/s, std of the noise on the measured velocities
  /// Called after each completed segment with the number completed (1, 2, ..., the last at the
  /// end of the pass); a result that is not ok ends the pass with it (learning checkpoints).
  std::function<PassResult(int completed_segments)> on_segment_end;
  std::function<bool()> should_stop;
};

/// Runs the pass from the trajectory's first sample (plus start_offset) at its first velocity.
PassResult run_control_pass(JobSetup& setup, ArmSimulation& plant, const JointTrajectory& trajectory, const PassOptions& options);

}  // namespace armfarm
