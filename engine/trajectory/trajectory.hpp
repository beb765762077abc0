#pragma once
// Desired motions of a job, sampled at the control rate: the thesis's sinusoidal joint-space
// trajectories (appendix D's SINE lines), the task-space figure-eight (section 5.5), random
// reaches (section 5.5.2, sigmoid or minimum-jerk profile) and recorded motions read from CSV
// (section 6.2.3), smoothed before differentiation.
//
// Units: SI and radians; task-space points in the world frame. Joint vectors have one entry
// per active joint, in the order of the job's active joints.
#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace armfarm {

class ArmDynamics;

/// How desired velocities and accelerations are obtained from sampled positions.
enum class Differentiation {
  backward_difference,  ///< the thesis's: v_k = (q_k − q_{k−1})/dt, a_k likewise from v
  smoothed,             ///< central differences of Savitzky–Golay smoothed samples
  analytic,             ///< exact derivatives where the trajectory has a closed form (sine, reaching profiles)
};

enum class ReachProfile { sigmoid, minimum_jerk };

/// Per active joint: q_d = offset + amplitude·sin(2π·frequency·t + phase). Empty vectors take
/// the defaults (offset = the joint's start angle, amplitude 0.3 rad, 0.25 Hz, phase 0);
/// a 1-element vector applies to every joint.
struct SineTrajectoryConfig {
  Eigen::VectorXd amplitude;  ///< rad
  Eigen::VectorXd frequency;  ///< Hz
  Eigen::VectorXd phase;      ///< rad
  Eigen::VectorXd offset;     ///< rad
  double duration = 20.0;     ///< s
};

/// x = centre.x, y = centre.y + scale·a·sin(πs), z = centre.z + scale·b·sin(2πs) for s in
/// [0, 2) per loop, sampled at points_per_loop points (one per control tick), loops times,
/// converted to joint space by inverse kinematics.
struct FigureEightConfig {
  Eigen::Vector3d centre = Eigen::Vector3d(0.45, 0.0, 0.6);  ///< m, world frame
  double a = 0.15;                ///< m, half-width along y
  double b = 0.10;                ///< m, half-height along z
  double scale = 1.0;             ///< the thesis's trajScaling
  int points_per_loop = 750;
  int loops = 3;
};

/// N reaches between random targets drawn uniformly in a task-space box, each sampled at
/// points_per_reach points with the chosen profile, converted by inverse kinematics.
struct ReachingConfig {
  Eigen::Vector3d box_min = Eigen::Vector3d(0.20, 0.20, 0.00);  ///< m (the thesis's region)
  Eigen::Vector3d box_max = Eigen::Vector3d(0.70, 0.70, 0.50);  ///< m
  ReachProfile profile = ReachProfile::minimum_jerk;
  double sigmoid_steepness = 12.0;  ///< the sigmoid 1/(1+exp(−k(s−½))) rescaled to [0,1], s ∈ [0,1]
  int points_per_reach = 100;
  int reaches = 20;
};

/// Recorded samples (read from a CSV by the runner: the engine does no file I/O): either joint
/// angles (one column per active joint) or task-space x, y, z, at sample_rate Hz, resampled to
/// the control rate, smoothed with a Savitzky–Golay filter (window, polynomial order) or a
/// first-order low-pass (cutoff) before differentiation.
struct RecordedTrajectoryConfig {
  std::string file;            ///< where the samples came from (for messages)
  Eigen::MatrixXd samples;     ///< n_rows × (3 or n_active)
  bool task_space = true;      ///< columns are x, y, z (m) rather than joint angles (rad)
  double sample_rate = 100.0;  ///< Hz of the file's rows
  std::string filter = "savitzky_golay";  ///< "savitzky_golay", "low_pass" or "none"
  int window = 15;             ///< Savitzky–Golay window (odd, samples at the control rate)
  int polynomial_order = 3;
  double cutoff = 5.0;         ///< Hz, low-pass
  int loops = 1;               ///< how many times the recording is replayed
};

enum class TrajectoryKind { sine, figure_eight, reaching, recorded };

struct TrajectoryConfig {
  TrajectoryKind kind = TrajectoryKind::sine;
  Differentiation differentiation = Differentiation::analytic;
  SineTrajectoryConfig sine;
  FigureEightConfig figure_eight;
  ReachingConfig reaching;
  RecordedTrajectoryConfig recorded;
};

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
