#pragma once
// Held-out evaluation: the learner, frozen, scored on data it never trained on.
//
// The held-out set is a different realisation of the job's trajectory (build_job_trajectories):
//  - sine: amplitudes × learning.heldout_amplitude_scale and the i-th joint's phase shifted by
//    (i − 1)·learning.heldout_phase_step, so the joint-space path differs, not only its start;
//  - figure-eight: the figure scaled by heldout_amplitude_scale about the same centre;
//  - reaching: a separate set of reaches, its targets drawn from the stream "heldout.reaching"
//    of the job seed (the training reaches come from "trajectory.reaching.targets");
//  - recorded: the last learning.heldout_recorded_fraction of the recording, which the
//    learning pass never replays.
// From it come (1) held-out test samples, collected once under PD feedback at
// learning.collect_gain_scale (streams "heldout.*"), on which the learner's prediction is
// scored (heldout_test_nmse), and (2) a control pass with the job's controller and the frozen
// learner's feed-forward (heldout_tracking_nmse, heldout_ff_fb_ratio_avg, heldout_id_nmse, ...).
// Every metric carries the checkpoint. The `heldout_` names of recording.series
// (series_recorder.hpp) record their signal over each held-out control pass, stored as
// heldout_<NAME>_c<checkpoint> with time measured from the pass's start (every
// recording.every ticks, as the job's own passes). The learner is taken by const reference: evaluating
// cannot change it (its n_updates() is reported as heldout_learner_updates).
#include "engine/experiment/control_pass.hpp"
#include "engine/learner/learner.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

struct JobTrajectories {
  JointTrajectory training;                ///< what the job collects, learns and is evaluated on
  std::optional<JointTrajectory> heldout;  ///< the held-out variant (when the job learns and heldout is on)
};

/// Builds the training trajectory and, when the job has a learner and learning.heldout is on,
/// its held-out variant (see above). Throws as build_trajectory does; recorded motion too
/// short to split throws std::invalid_argument naming learning.heldout_recorded_fraction.
JobTrajectories build_job_trajectories(const JobConfig& config, ArmDynamics& dynamics);

/// Whether the configuration key at `path` (a job_config_keys() path, e.g. "trajectory.sine.duration")
/// is read by build_job_trajectories: with the model's content, these keys determine a job's
/// trajectories, so jobs equal on them can share one build (the runner's trajectory cache).
bool is_trajectory_input(const std::string& path);

class HeldoutEvaluation {
 public:
  /// Owns the held-out trajectory and its own plant (the learning pass's plant is never touched).
  HeldoutEvaluation(JobSetup& setup, JointTrajectory trajectory, std::function<bool()> should_stop);

  /// Collects the held-out test samples (one pass); not ok only when should_stop fired or the
  /// feedback pass itself diverged (then the job ends with that status).
  PassResult collect_test_samples();

  /// Scores `learner` at `checkpoint` and appends the heldout_* metrics to `metrics`. A held-out
  /// control pass that diverges is reported (heldout_diverged = 1, figures over the ticks run)
  /// and does not end the job; only should_stop does (the result is then not ok).
  PassResult evaluate(const Learner& learner, int checkpoint, std::vector<Metric>& metrics);

  /// The series recorded in the held-out passes so far (heldout_F_c200, …), handed over once.
  std::vector<Series> take_series() { return std::move(series_); }

  const JointTrajectory& trajectory() const { return trajectory_; }
  const std::vector<Sample>& test_samples() const { return samples_; }
  double simulated_seconds() const { return simulated_seconds_; }

 private:
  JobSetup& setup_;
  JointTrajectory trajectory_;
  std::function<bool()> should_stop_;
  ArmSimulation plant_;
  std::vector<Sample> samples_;
  std::vector<Series> series_;
  double simulated_seconds_ = 0.0;
};

}  // namespace armfarm
