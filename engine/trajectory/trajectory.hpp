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

/// What a default sine keeps within, per active joint (n each; ±inf where a joint has no limit).
struct JointRanges {
  Eigen::VectorXd lower, upper;  ///< position limits, rad or m
  Eigen::VectorXd velocity;      ///< velocity limits, rad/s or m/s
};

/// Shares of the room a default sine amplitude may take: of the distance from its offset to the
/// nearer position limit, and of the velocity limit at its frequency.
inline constexpr double kSineRangeShare = 0.9;
inline constexpr double kSineVelocityShare = 0.8;

/// `sine` with every vector expanded to n entries and every empty one replaced by its default
/// (`start_positions` for the offset). The default amplitude is 0.3 rad, or less where `ranges`
/// (when given) leave less: at most kSineRangeShare of the distance from the offset to the
/// nearer position limit and kSineVelocityShare of the velocity limit (amplitude·2π·frequency).
/// Throws std::invalid_argument naming a wrong-sized field.
SineTrajectoryConfig resolve_sine_defaults(const SineTrajectoryConfig& sine, int n, const Eigen::VectorXd& start_positions,
                                           const JointRanges* ranges = nullptr);

/// Builds the trajectory for the active joints of `dynamics` (which supplies start angles,
/// limits, kinematics and the IK). `seed` draws the reaching targets. Throws
/// std::invalid_argument naming the field for unusable settings and std::runtime_error when a
/// target cannot be reached. Task-space kinds get their velocities and accelerations from the
/// inverse-kinematics samples (analytic = central differences, which are exact to O(dt²) on
/// the smooth joint path; smoothed = Savitzky–Golay derivatives; backward = the thesis's).
JointTrajectory build_trajectory(const TrajectoryConfig& config, ArmDynamics& dynamics, double dt, std::uint64_t seed);

}  // namespace armfarm
