#include "engine/trajectory/task_space_path.hpp"

#include "engine/kinematics/inverse_kinematics.hpp"
#include "engine/kinematics/serial_chain.hpp"
#include "engine/model/arm_reach.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/random/random_stream.hpp"
#include "engine/trajectory/trajectory_differentiation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm {
namespace {

constexpr double kMaxTargetError = 1e-3;  // m; the bound on the end-effector error

/// Position profile p(s), p'(s), p''(s) on s ∈ [0, 1], from 0 to 1.
Eigen::Vector3d calc_profile(ReachProfile profile, double steepness, double s) {
  if (profile == ReachProfile::minimum_jerk) {
    return {s * s * s * (10.0 - 15.0 * s + 6.0 * s * s), 30.0 * s * s * (1.0 - 2.0 * s + s * s),
            60.0 * s * (1.0 - 3.0 * s + 2.0 * s * s)};
  }
  auto sigma = [steepness](double u) { return 1.0 / (1.0 + std::exp(-steepness * (u - 0.5))); };
  const double low = sigma(0.0), range = sigma(1.0) - low, value = sigma(s);
  return {(value - low) / range, steepness * value * (1.0 - value) / range,
          steepness * steepness * value * (1.0 - value) * (1.0 - 2.0 * value) / range};
}

}  // namespace

Eigen::MatrixXd calc_joint_path(const SerialChain& chain, const Eigen::MatrixXd& targets, const Eigen::VectorXd& initial,
                                const char* what) {
  const Eigen::VectorXd& rest = chain.start_positions();
  Eigen::MatrixXd path(targets.rows(), chain.dof());
  Eigen::VectorXd q = initial;
  for (Eigen::Index i = 0; i < targets.rows(); ++i) {
    const InverseKinematicsResult solution = solve_inverse_kinematics(chain, targets.row(i).transpose(), q, rest);
    if (!(solution.error <= kMaxTargetError)) {
      throw std::runtime_error(std::string(what) + ": sample " + std::to_string(i) + " at (" + std::to_string(targets(i, 0)) +
                               ", " + std::to_string(targets(i, 1)) + ", " + std::to_string(targets(i, 2)) +
                               ") m is out of reach (inverse kinematics misses it by " + std::to_string(solution.error) + " m)");
    }
    q = solution.q;
    path.row(i) = q.transpose();
  }
  return path;
}

Eigen::MatrixXd calc_joint_path(const ArmDynamics& dynamics, const Eigen::MatrixXd& targets, const Eigen::VectorXd& initial,
                                const char* what) {
  return calc_joint_path(make_end_effector_chain(dynamics), targets, initial, what);
}

JointTrajectory build_figure_eight(const FigureEightConfig& config, Differentiation method, ArmDynamics& dynamics, double dt) {
  if (config.points_per_loop < 4) throw std::invalid_argument("trajectory.figure_eight.points_per_loop: must be at least 4");
  if (config.loops < 1) throw std::invalid_argument("trajectory.figure_eight.loops: must be at least 1");
  if (!(config.scale > 0.0)) throw std::invalid_argument("trajectory.figure_eight.scale: must be positive");
  const int points = config.points_per_loop;
  const SerialChain chain = make_end_effector_chain(dynamics);
  FigureEightShape shape = calc_figure_eight_shape(config, calc_reach(dynamics.model()));
  const auto make_targets = [&](const FigureEightShape& figure) {
    Eigen::MatrixXd targets(points, 3);
    for (int i = 0; i < points; ++i) {
      const double s = 2.0 * i / points;  // one loop: s ∈ [0, 2)
      targets.row(i) << figure.centre.x(), figure.centre.y() + config.scale * figure.a * std::sin(M_PI * s),
          figure.centre.z() + config.scale * figure.b * std::sin(2.0 * M_PI * s);
    }
    return targets;
  };
  // Start from the rest posture; repeat the loop until its joint path closes (the IK converges
  // to a function of the target, so one repeat normally suffices).
  const auto solve_loop = [&](const Eigen::MatrixXd& targets) {
    Eigen::VectorXd start = chain.start_positions();
    Eigen::MatrixXd loop;
    for (int attempt = 0; attempt < 10; ++attempt) {
      loop = calc_joint_path(chain, targets, start, "trajectory.figure_eight");
      const Eigen::MatrixXd next_start = calc_joint_path(chain, targets.topRows(1), loop.bottomRows(1).transpose(), "trajectory.figure_eight");
      const double gap = (next_start.row(0) - loop.row(0)).cwiseAbs().maxCoeff();
      start = next_start.row(0).transpose();
      if (gap < 1e-6) break;
    }
    return loop;
  };
  Eigen::MatrixXd loop_targets = make_targets(shape), loop;
  try {
    loop = solve_loop(loop_targets);
  } catch (const std::runtime_error&) {
    // An "auto" centre the arm cannot follow the figure around moves to where the end effector
    // is at the start posture (reachable by construction), the size kept.
    if (config.centre) throw;
    shape.centre = chain.calc_position(chain.start_positions());
    loop_targets = make_targets(shape);
    loop = solve_loop(loop_targets);
  }
  JointTrajectory trajectory;
  trajectory.dt = dt;
  trajectory.q = loop.replicate(config.loops, 1);
  trajectory.task_position = loop_targets.replicate(config.loops, 1);
  for (int k = 0; k < config.loops; ++k) trajectory.segment_starts.push_back(k * points);
  fill_derivatives(trajectory, method, /*periodic=*/true, 15, 3);
  // The IK path must stay within the velocity limits (a figure near a singularity would not).
  const Eigen::VectorXd limits = dynamics.velocity_limits();
  const std::vector<int> movable = dynamics.model().movable_joints();
  for (Eigen::Index j = 0; j < trajectory.qd.cols(); ++j) {
    const double speed = trajectory.qd.col(j).cwiseAbs().maxCoeff();
    if (std::isfinite(limits[j]) && speed > limits[j]) {
      const int slower = static_cast<int>(std::ceil(points * speed / (0.8 * limits[j])));
      const int index = dynamics.active_joint_indices()[static_cast<std::size_t>(j)];
      const auto number = std::find(movable.begin(), movable.end(), index) - movable.begin() + 1;  // 1-based, as users count
      throw std::invalid_argument("trajectory.figure_eight: joint " + std::to_string(number) + " needs " + std::to_string(speed) +
                                  " rad/s, above its velocity limit " + std::to_string(limits[j]) +
                                  " rad/s (points_per_loop " + std::to_string(slower) + " keeps it at 80 % of it, or a smaller scale)");
    }
  }
  return trajectory;
}

namespace {

/// The box the reaching targets are drawn from (m, world frame), each maximum checked to exceed its minimum.
ReachingBox make_checked_reaching_box(const ReachingConfig& config, const ArmModel& model) {
  const ReachingBox box = calc_reaching_box(config, calc_reach(model));
  for (int axis = 0; axis < 3; ++axis) {
    if (!(box.min[axis] < box.max[axis])) {
      throw std::invalid_argument("trajectory.reaching.box_max[" + std::to_string(axis) + "]: must exceed box_min (" +
                                  std::to_string(box.max[axis]) + " m against " + std::to_string(box.min[axis]) + " m)");
    }
  }
  return box;
}

/// One reach as planned: its points + 1 task-space targets and joint angles (the last row is the
/// next reach's start), and the target it ends at.
struct PlannedReach {
  Eigen::MatrixXd targets, joints;
  Eigen::Vector3d to;
};

/// Plans build_reaching's reaches: targets drawn uniformly in the box from one seeded stream (a
/// target counts when the IK reaches it from the rest posture), each reach's joint path by the
/// warm-started IK along its profile, kept only within 80 % of the joint velocity limits.
class ReachPlanner {
 public:
  ReachPlanner(const ReachingConfig& config, const ReachingBox& box, ArmDynamics& dynamics, double dt, std::uint64_t seed)
      : config_(config),
        box_(box),
        dt_(dt),
        draws_(seed, "trajectory.reaching.targets"),
        chain_(make_end_effector_chain(dynamics)),
        speed_limit_(0.8 * dynamics.velocity_limits()) {}

  const SerialChain& chain() const { return chain_; }

  /// The next reachable target of the stream, for reach `index` (its error message's number).
  Eigen::Vector3d draw_target(int index) {
    const Eigen::VectorXd& rest = chain_.start_positions();
    for (int attempt = 0; attempt < 100; ++attempt) {
      Eigen::Vector3d target;
      for (int axis = 0; axis < 3; ++axis) {
        target[axis] = draws_.uniform(box_.min[axis], box_.max[axis]);
      }
      if (solve_inverse_kinematics(chain_, target, rest, rest).error <= kMaxTargetError * 0.1) return target;
    }
    throw std::runtime_error("trajectory.reaching: no reachable target found in the box for reach " + std::to_string(index) +
                             " after 100 draws");
  }

  /// Reach `reach` (0-based) from `from` at joint angles `q`: the first of up to 100 drawn targets
  /// whose joint path the IK finds and that stays within the speed limit; none when no draw does.
  std::optional<PlannedReach> plan(const Eigen::Vector3d& from, const Eigen::VectorXd& q, int reach) {
    const int points = config_.points_per_reach;
    PlannedReach planned{Eigen::MatrixXd(points + 1, 3), Eigen::MatrixXd(), Eigen::Vector3d::Zero()};
    for (int attempt = 0; attempt < 100; ++attempt) {
      planned.to = draw_target(reach + 1);
      for (int i = 0; i <= points; ++i) {
        const double s = static_cast<double>(i) / points;
        planned.targets.row(i) =
            (from + (planned.to - from) * calc_profile(config_.profile, config_.sigmoid_steepness, s)[0]).transpose();
      }
      try {
        planned.joints = calc_joint_path(chain_, planned.targets, q, "trajectory.reaching");
      } catch (const std::runtime_error&) {
        continue;
      }
      if (within_speed_limit(planned.joints)) return planned;
    }
    return std::nullopt;
  }

 private:
  /// Whether every step of the joint path moves each joint at most speed_limit_ · dt.
  bool within_speed_limit(const Eigen::MatrixXd& joints) const {
    for (Eigen::Index i = 0; i + 1 < joints.rows(); ++i) {
      const Eigen::VectorXd speed = (joints.row(i + 1) - joints.row(i)).transpose().cwiseAbs() / dt_;
      if (!(speed.array() <= speed_limit_.array()).all()) return false;
    }
    return true;
  }

  const ReachingConfig& config_;
  const ReachingBox box_;
  const double dt_;
  RandomStream draws_;
  const SerialChain chain_;
  const Eigen::VectorXd speed_limit_;  ///< rad/s, 80 % of the velocity limits
};

}  // namespace

JointTrajectory build_reaching(const ReachingConfig& config, Differentiation method, ArmDynamics& dynamics, double dt,
                               std::uint64_t seed) {
  if (config.points_per_reach < 2) throw std::invalid_argument("trajectory.reaching.points_per_reach: must be at least 2");
  if (config.reaches < 1) throw std::invalid_argument("trajectory.reaching.reaches: must be at least 1");
  ReachPlanner planner(config, make_checked_reaching_box(config, dynamics.model()), dynamics, dt, seed);
  const Eigen::VectorXd& rest = planner.chain().start_positions();
  const int points = config.points_per_reach;
  Eigen::MatrixXd targets(config.reaches * points, 3);
  Eigen::MatrixXd joints(config.reaches * points, dynamics.dof());
  Eigen::Vector3d from = planner.draw_target(0);
  Eigen::VectorXd q = solve_inverse_kinematics(planner.chain(), from, rest, rest).q;
  JointTrajectory trajectory;
  trajectory.dt = dt;
  // The redraw rule: when no target of 100 draws is feasible from the posture the previous reach
  // left (a stall near a limit or a singularity), that previous reach is taken back and drawn
  // again, the draws continuing the same seeded stream; at most kMaxTakeBacks times per
  // trajectory. Deterministic in the seed: the same stalls take back the same reaches.
  constexpr int kMaxTakeBacks = 100;
  int take_backs = 0;
  std::vector<Eigen::Vector3d> reach_from(static_cast<std::size_t>(config.reaches));
  std::vector<Eigen::VectorXd> reach_q(static_cast<std::size_t>(config.reaches));
  for (int reach = 0; reach < config.reaches;) {
    reach_from[static_cast<std::size_t>(reach)] = from;
    reach_q[static_cast<std::size_t>(reach)] = q;
    std::optional<PlannedReach> planned = planner.plan(from, q, reach);
    if (!planned && reach > 0 && take_backs < kMaxTakeBacks) {
      ++take_backs;
      --reach;  // take the previous reach back; its rows are overwritten when it is redrawn
      from = reach_from[static_cast<std::size_t>(reach)];
      q = reach_q[static_cast<std::size_t>(reach)];
      trajectory.segment_starts.pop_back();
      continue;
    }
    if (!planned) {
      throw std::runtime_error("trajectory.reaching: no target for reach " + std::to_string(reach + 1) +
                               " can be reached within the joint velocity limits in " + std::to_string(points * dt) +
                               " s after " + std::to_string(take_backs) +
                               " redrawn earlier reaches (raise points_per_reach or shrink the box)");
    }
    from = planned->to;
    targets.middleRows(reach * points, points) = planned->targets.topRows(points);
    joints.middleRows(reach * points, points) = planned->joints.topRows(points);
    q = planned->joints.row(points).transpose();
    trajectory.segment_starts.push_back(reach * points);
    ++reach;
  }
  trajectory.q = joints;
  trajectory.task_position = targets;
  fill_derivatives(trajectory, method, /*periodic=*/false, 15, 3);
  return trajectory;
}

}  // namespace armfarm
