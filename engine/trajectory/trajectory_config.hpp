#pragma once
// The configuration of a job's desired motion: which kind (sinusoid, figure-eight, reaches,
// recorded) with each kind's parameters, the only copy of their defaults, and one key table per
// struct (engine/config/config_key.hpp). The motions themselves: trajectory.hpp.
//
// Units: SI and radians; task-space points in the world frame. Joint vectors have one entry
// per active joint (in the order of the job's active joints) or one for all.
#include "engine/config/config_key.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// How desired velocities and accelerations are obtained from sampled positions.
enum class Differentiation {
  backward_difference,  ///< the thesis's: v_k = (q_k − q_{k−1})/dt, a_k likewise from v
  smoothed,             ///< central differences of Savitzky–Golay smoothed samples
  analytic,             ///< exact derivatives where the trajectory has a closed form (sine, reaching profiles)
};
const EnumNames& differentiation_names();

enum class ReachProfile { sigmoid, minimum_jerk };
const EnumNames& reach_profile_names();

/// Smoothing of a recorded motion before differentiation.
enum class RecordedFilter { savitzky_golay, low_pass, none };
const EnumNames& recorded_filter_names();

enum class TrajectoryKind { sine, figure_eight, reaching, recorded };
const EnumNames& trajectory_kind_names();

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
const std::vector<ConfigKey<SineTrajectoryConfig>>& sine_trajectory_config_keys();

/// The arm task-space defaults are written for: the DLR LWR III's reach (m; calc_reach of
/// models/dlr_lwr3.urdf). A default figure-eight or reaching box on another arm is the thesis's
/// one scaled about the world origin by that arm's reach / kReferenceReach (exactly the thesis's
/// numbers on the LWR III).
inline constexpr double kReferenceReach = 1.018;

/// x = centre.x, y = centre.y + scale·a·sin(πs), z = centre.z + scale·b·sin(2πs) for s in
/// [0, 2) per loop, sampled at points_per_loop points (one per control tick), loops times,
/// converted to joint space by inverse kinematics. Empty centre, a, b ("auto"): the thesis's
/// (0.45, 0, 0.6) m, 0.15 m and 0.10 m scaled by reach / kReferenceReach; an "auto" centre
/// the arm cannot follow the figure around moves to the end effector's start position.
struct FigureEightConfig {
  std::optional<Eigen::Vector3d> centre;  ///< m, world frame
  std::optional<double> a;  ///< m, half-width along y
  std::optional<double> b;  ///< m, half-height along z
  double scale = 1.0;       ///< the thesis's trajScaling
  int points_per_loop = 750;
  int loops = 3;
};

/// The figure-eight's centre (m) and half-width and half-height (m, before `scale`) on an arm of
/// `reach` (m): the configured values, the defaults scaled to the reach where "auto".
struct FigureEightShape {
  Eigen::Vector3d centre;
  double a = 0.0, b = 0.0;
};
FigureEightShape calc_figure_eight_shape(const FigureEightConfig& config, double reach);
const std::vector<ConfigKey<FigureEightConfig>>& figure_eight_config_keys();

/// N reaches between random targets drawn uniformly in a task-space box, each sampled at
/// points_per_reach points with the chosen profile, converted by inverse kinematics. Empty box
/// corners ("auto"): the thesis's region (0.2, 0.2, 0) – (0.7, 0.7, 0.5) m scaled by
/// reach / kReferenceReach.
struct ReachingConfig {
  std::optional<Eigen::Vector3d> box_min;  ///< m
  std::optional<Eigen::Vector3d> box_max;  ///< m
  ReachProfile profile = ReachProfile::minimum_jerk;
  double sigmoid_steepness = 12.0;  ///< the sigmoid 1/(1+exp(−k(s−½))) rescaled to [0,1], s ∈ [0,1]
  int points_per_reach = 100;
  int reaches = 20;
};

/// The box's corners (m) on an arm of `reach` (m): as configured, the defaults scaled where "auto".
struct ReachingBox {
  Eigen::Vector3d min, max;
};
ReachingBox calc_reaching_box(const ReachingConfig& config, double reach);
const std::vector<ConfigKey<ReachingConfig>>& reaching_config_keys();

/// Recorded samples (read from a CSV by the runner: the engine does no file I/O): either joint
/// angles (one column per active joint) or task-space x, y, z, at sample_rate Hz, resampled to
/// the control rate, smoothed with a Savitzky–Golay filter (window, polynomial order) or a
/// first-order low-pass (cutoff) before differentiation.
struct RecordedTrajectoryConfig {
  std::string file;            ///< where the samples came from (for messages)
  Eigen::MatrixXd samples;     ///< n_rows × (3 or n_active); not a key: the runner reads `file`
  std::vector<int> sample_lines;  ///< the file line of each row of `samples` (for messages); may be empty
  bool task_space = true;      ///< columns are x, y, z (m) rather than joint angles (rad)
  double sample_rate = 100.0;  ///< Hz of the file's rows
  RecordedFilter filter = RecordedFilter::savitzky_golay;
  int window = 15;             ///< Savitzky–Golay window (odd, samples at the control rate)
  int polynomial_order = 3;
  double cutoff = 5.0;         ///< Hz, low-pass
  int loops = 1;               ///< how many times the recording is replayed
};
const std::vector<ConfigKey<RecordedTrajectoryConfig>>& recorded_trajectory_config_keys();

/// Control ticks one replay of `recorded` lasts once resampled to the control period `dt` (s):
/// floor((rows − 1) / sample_rate / dt) + 1; 0 with fewer than 2 rows or a non-positive rate or dt.
int calc_recorded_ticks(const RecordedTrajectoryConfig& recorded, double dt);

/// "" when the resampled recording is long enough for its filter (a Savitzky–Golay window needs
/// at least `window` ticks), else the problem, naming the file, its rows and the window. One
/// check for validation (before any job runs) and for building the trajectory.
std::string check_recorded_length(const RecordedTrajectoryConfig& recorded, double dt);

struct TrajectoryConfig {
  TrajectoryKind kind = TrajectoryKind::sine;
  Differentiation differentiation = Differentiation::analytic;
  /// Task-space kinds (figure_eight, reaching, recorded with task_space): std (rad) of seeded
  /// white noise (stream "trajectory.ik_noise") added to every desired joint angle the IK
  /// solved, a model of the thesis's IK "zig-zag" (section 6.2.1); q̇ and q̈ then come from
  /// differentiation (analytic: central differences) of the noisy angles. 0 = the exact IK path.
  double ik_noise = 0.0;
  SineTrajectoryConfig sine;
  FigureEightConfig figure_eight;
  ReachingConfig reaching;
  RecordedTrajectoryConfig recorded;
};
/// kind and differentiation; the kinds' tables are composed under sine., figure_eight., ...
const std::vector<ConfigKey<TrajectoryConfig>>& trajectory_config_keys();

}  // namespace armfarm
