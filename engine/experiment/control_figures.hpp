#pragma once
// What a job puts on each active joint before it runs, from the model and the configuration
// alone: the mass-matrix diagonal (armature included, after simulation.armature_scale) at the
// start posture, the PD gains after control.gain_scale, and the PD period and RK4 steps the
// job runs with ("auto" resolved by the step-stability criterion, job_steps.hpp) with the
// criterion's one-joint ratios at them. `armfarm model info` prints them for the default job
// (runner/cli/cmd_model_info.cpp). Units: kg·m² (kg for sliders), N·m/rad, N·m·s/rad, s.
#include "engine/control/step_stability.hpp"
#include "engine/experiment/job_config.hpp"
#include "engine/model/arm_model.hpp"

#include <string>
#include <vector>

namespace armfarm {

struct JointControlFigures {
  int number = 0;              ///< 1-based joint number
  double start_position = 0;   ///< rad or m, where the job starts the joint
  double mass_diagonal = 0;    ///< M_jj + armature at the start posture (the other joints there too)
  double kp = 0;               ///< N·m/rad, after control.gain_scale
  double kd = 0;               ///< N·m·s/rad, after control.gain_scale (√ when keep_damping_ratio)
  double damping = 0;          ///< b, the joint's viscous damping, N·m·s/rad
  /// The one-joint closed form's ratios (engine/README.md, "Stable by construction") at the
  /// steps the job runs with (JobStepFigures::run: PD period h = dt / P, RK4 step h_i = h / S):
  double kd_ratio = 0;         ///< kd·h/M_jj (bound 2)
  double kp_ratio = 0;         ///< kp·h²/M_jj (bound 2·kd·h/M_jj)
  double damping_ratio = 0;    ///< b·h_i/M_jj (bound kRk4RealBound); NaN for an adaptive integrator
};

/// The steps a job runs with and the criterion's view of them at the start posture.
struct JobStepFigures {
  double dt = 0.0;      ///< s, the control tick
  bool fixed_step = true;  ///< runge_kutta_4 (S counts); false: an adaptive integrator
  /// What the job runs with: "auto" resolved as run_experiment resolves it, over the start posture
  /// and kStepPostures postures along each of its trajectories (explicit values as set).
  StepChoice run;
  StepChoice at_start;  ///< "auto" judged at the start posture alone (what validate() judges)
  /// Why `run` is `at_start`: the job's trajectories could not be built ("" when they were).
  std::string trajectory_problem;
  /// At the start posture and `run`'s steps, under the job's own controller (the collection's
  /// when it runs open loop): the fastest coupled mode's kd·h/M (λ_max(M⁻¹Kd)·h, bound 2) and the
  /// error's growth per PD period ρ(F) (≤ 1: stable).
  double modal_kd_ratio = 0.0;
  double spectral_radius = 0.0;
};

/// A job's figures: one entry per active joint and its steps.
struct ControlFigures {
  std::vector<JointControlFigures> joints;
  JobStepFigures steps;
};

/// The figures of a job of `config` on `model`, entries per active joint of `config` (all
/// movable joints when active_joints is empty). `model` is the job's (make_job_model: its start
/// posture); without a chosen end effector the steps are judged at the start posture only.
/// `config` must have passed validate(). Throws std::invalid_argument as make_pd_gains does.
ControlFigures calc_control_figures(const ArmModel& model, const JobConfig& config);

}  // namespace armfarm
