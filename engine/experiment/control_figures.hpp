#pragma once
// What a job puts on each active joint before it runs, from the model and the configuration
// alone: the mass-matrix diagonal (armature included, after simulation.armature_scale) at the
// start posture and the PD gains after control.gain_scale — the figures a stability criterion
// reads. `armfarm model info` prints them for the default job (runner/cli/cmd_model_info.cpp).
// Units: kg·m² (kg for sliders), N·m/rad, N·m·s/rad.
#include "engine/experiment/job_config.hpp"
#include "engine/model/arm_model.hpp"

#include <vector>

namespace armfarm {

struct JointControlFigures {
  int number = 0;              ///< 1-based joint number
  double start_position = 0;   ///< rad or m, where the job starts the joint
  double mass_diagonal = 0;    ///< M_jj + armature at the start posture (the other joints there too)
  double kp = 0;               ///< N·m/rad, after control.gain_scale
  double kd = 0;               ///< N·m·s/rad, after control.gain_scale (√ when keep_damping_ratio)
  // The stability criterion (issue 22: the dt, pd_substeps and integrator steps that "auto"
  // picks) adds its per-joint figures here, and model info prints them beside these.
};

/// One entry per active joint of `config` (all movable joints when active_joints is empty).
/// `model` is the job's (make_job_model: its start posture); its end effector is not read.
/// `config` must have passed validate(). Throws std::invalid_argument as make_pd_gains does.
std::vector<JointControlFigures> calc_joint_control_figures(const ArmModel& model, const JobConfig& config);

}  // namespace armfarm
