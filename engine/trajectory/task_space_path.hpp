#pragma once
// Task-space paths (figure-eight, reaches) turned into joint paths by inverse kinematics.
// Units: m, rad; world frame.
#include "engine/trajectory/trajectory.hpp"

#include <Eigen/Core>

#include <cstdint>

namespace armfarm {

class SerialChain;

/// Solves the IK of `chain`'s point for every row of `targets` (n × 3), warm-starting each
/// sample from the previous one, with the null space pulled towards the chain's start posture.
/// Throws std::runtime_error naming the sample when a target is missed by more than 1 mm.
Eigen::MatrixXd calc_joint_path(const SerialChain& chain, const Eigen::MatrixXd& targets, const Eigen::VectorXd& initial,
                                const char* what);
/// The same for the end effector of `dynamics`'s model and active joints.
Eigen::MatrixXd calc_joint_path(const ArmDynamics& dynamics, const Eigen::MatrixXd& targets, const Eigen::VectorXd& initial,
                                const char* what);

/// The figure-eight, its loop solved until the joint path closes on itself (< 1e-6 rad), then
/// repeated `loops` times so that every loop starts where the previous one ended.
JointTrajectory build_figure_eight(const FigureEightConfig& config, Differentiation method, ArmDynamics& dynamics, double dt);

/// Reaches between random targets in the box, deterministic in `seed`. A target is redrawn when
/// the IK misses it or its joint path exceeds 80 % of a velocity limit (up to 100 draws); when
/// every draw for a reach fails, the previous reach is taken back and redrawn from the same
/// stream (at most 100 take-backs), so a posture that stalls does not fail the job. A seed
/// that never stalls gives the same reaches as before the rule existed.
JointTrajectory build_reaching(const ReachingConfig& config, Differentiation method, ArmDynamics& dynamics, double dt,
                               std::uint64_t seed);

}  // namespace armfarm
