#pragma once
// Desired motions of a job, sampled at the control rate: the thesis's sinusoidal joint-space
// trajectories (appendix D's SINE lines), the task-space figure-eight (section 5.5), random
// reaches (section 5.5.2, sigmoid or minimum-jerk profile) and recorded motions read from CSV
// (section 6.2.3), smoothed before differentiation.
//
// The configuration structs: trajectory_config.hpp.
//
// Units: SI and radians; task-space points in the world frame. Joint vectors have one entry
// per active joint, in the order of the job's active joints.
#include "engine/trajectory/trajectory_config.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace armfarm {

class ArmDynamics;

/// A desired joint-space motion sampled every dt seconds: sample k is the target at t = k·dt.
struct JointTrajectory {
  double dt = 0.01;
  Eigen::MatrixXd q, qd, qdd;       ///< n_samples × n_active
  Eigen::MatrixXd task_position;    ///< n_samples × 3: the desired end-effector point (FK of q for joint-space kinds)
  std::vector<int> segment_starts;  ///< first sample of each loop or reach (starts with 0)

  int size() const { return static_cast<int>(q.rows()); }
};

/// `sine` with every vector expanded to n entries and every empty one replaced by its default
/// (`start_positions` for the offset); throws std::invalid_argument naming a wrong-sized field.
SineTrajectoryConfig resolve_sine_defaults(const SineTrajectoryConfig& sine, int n, const Eigen::VectorXd& start_positions);

/// Builds the trajectory for the active joints of `dynamics` (which supplies start angles,
/// limits, kinematics and the IK). `seed` draws the reaching targets. Throws
/// std::invalid_argument naming the field for unusable settings and std::runtime_error when a
/// target cannot be reached. Task-space kinds get their velocities and accelerations from the
/// inverse-kinematics samples (analytic = central differences, which are exact to O(dt²) on
/// the smooth joint path; smoothed = Savitzky–Golay derivatives; backward = the thesis's).
JointTrajectory build_trajectory(const TrajectoryConfig& config, ArmDynamics& dynamics, double dt, std::uint64_t seed);

}  // namespace armfarm
