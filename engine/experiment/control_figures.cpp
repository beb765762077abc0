#include "engine/experiment/control_figures.hpp"

#include "engine/control/pd_gains.hpp"
#include "engine/physics/arm_simulation.hpp"

namespace armfarm {

std::vector<JointControlFigures> calc_joint_control_figures(const ArmModel& model, const JobConfig& config) {
  std::vector<int> numbers = config.active_joints;
  if (numbers.empty()) {
    for (int i = 1; i <= static_cast<int>(model.movable_joints().size()); ++i) numbers.push_back(i);
  }
  std::vector<int> indices;
  for (int number : numbers) indices.push_back(number - 1);
  // As JobSetup builds the job's nominal model: the armature scaled.
  ArmModel scaled = model;
  for (Joint& joint : scaled.joints) joint.armature *= config.simulation.armature_scale;
  ArmDynamics dynamics(scaled, indices);
  const Eigen::VectorXd start = dynamics.start_positions();
  const Eigen::VectorXd diagonal = dynamics.calc_mass_matrix(start).diagonal();
  const PdGains gains = make_pd_gains(config.control, dynamics, numbers);
  const double kp_scale = config.control.gain_scale;
  const double kd_scale = calc_kd_scale(config.control.gain_scale, config.control.keep_damping_ratio);
  std::vector<JointControlFigures> figures;
  for (std::size_t i = 0; i < numbers.size(); ++i) {
    const auto j = static_cast<Eigen::Index>(i);
    figures.push_back({numbers[i], start[j], diagonal[j], gains.kp[j] * kp_scale, gains.kd[j] * kd_scale});
  }
  return figures;
}

}  // namespace armfarm
