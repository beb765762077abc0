#include "engine/model/model_validation.hpp"

#include "engine/model/model_loading.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <sstream>

namespace armfarm {
namespace {

class Reporter {
 public:
  Reporter(const ArmModel& model, const ModelSourceLines& lines) : model_(model), lines_(lines) {}

  [[noreturn]] void link(int index, const std::string& what) const {
    const std::string& name = model_.links[index].name;
    fail(lines_.links, name, "link '" + name + "'", what);
  }
  [[noreturn]] void joint(int index, const std::string& what) const {
    const std::string& name = model_.joints[index].name;
    fail(lines_.joints, name, "joint '" + name + "'", what);
  }
  [[noreturn]] void model(const std::string& what) const { throw ModelError(model_.source_file + ": " + what); }

 private:
  [[noreturn]] void fail(const std::map<std::string, int>& where, const std::string& name, const std::string& element,
                         const std::string& what) const {
    const auto it = where.find(name);
    const std::string place = it == where.end() ? "" : std::to_string(it->second) + ":";
    throw ModelError(model_.source_file + ":" + place + " " + element + ": " + what);
  }
  const ArmModel& model_;
  const ModelSourceLines& lines_;
};

bool finite(const Eigen::MatrixXd& m) { return m.allFinite(); }

std::string format(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void validate_inertial(const Link& link, int index, bool may_be_massless, const Reporter& report) {
  const Inertial& in = link.inertial;
  if (!std::isfinite(in.mass) || !finite(in.com) || !finite(in.inertia)) report.link(index, "NaN or Inf in its mass properties");
  if (in.mass < 0.0) report.link(index, "negative mass " + format(in.mass) + " kg");
  if (in.mass == 0.0) {
    if (may_be_massless) return;
    report.link(index, "zero mass on a link that a joint moves (give it an <inertial> with a positive mass)");
  }
  const Eigen::Matrix3d& I = in.inertia;
  const double scale = I.cwiseAbs().maxCoeff();
  if (scale == 0.0) report.link(index, "zero inertia tensor");
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) report.link(index, "inertia tensor is not symmetric");
  const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();  // ascending
  if (moments(0) <= 1e-12 * scale) {
    report.link(index, "inertia tensor is not positive definite (principal moments " + format(moments(0)) + ", " +
                           format(moments(1)) + ", " + format(moments(2)) + " kg·m²)");
  }
  if (moments(0) + moments(1) < moments(2) * (1.0 - 1e-9)) {
    report.link(index, "inertia violates the triangle inequality (principal moments " + format(moments(0)) + " + " +
                           format(moments(1)) + " < " + format(moments(2)) + " kg·m²)");
  }
}

void validate_joint(const Joint& joint, int index, const Reporter& report) {
  if (!finite(joint.origin.matrix()) || !finite(joint.child_offset.matrix())) report.joint(index, "NaN or Inf in its placement");
  if (!finite(joint.axis)) report.joint(index, "NaN or Inf in its axis");
  if (joint.type != JointType::fixed) {
    const double norm = joint.axis.norm();
    if (norm < 1e-9) report.joint(index, "zero axis");
    if (std::abs(norm - 1.0) > 1e-6) report.joint(index, "axis is not a unit vector (norm " + format(norm) + ")");
  }
  const double numbers[] = {joint.lower, joint.upper, joint.damping, joint.friction, joint.armature, joint.start_position};
  for (double value : numbers) {
    if (!std::isfinite(value)) report.joint(index, "NaN or Inf in its limits, dynamics, armature or start position");
  }
  if (std::isnan(joint.effort_limit) || std::isnan(joint.velocity_limit)) report.joint(index, "NaN effort or velocity limit");
  if (joint.effort_limit <= 0.0) report.joint(index, "effort limit must be positive (got " + format(joint.effort_limit) + ")");
  if (joint.velocity_limit <= 0.0) {
    report.joint(index, "velocity limit must be positive (got " + format(joint.velocity_limit) + ")");
  }
  if (joint.damping < 0.0) report.joint(index, "negative damping " + format(joint.damping));
  if (joint.friction < 0.0) report.joint(index, "negative friction " + format(joint.friction));
  if (joint.armature < 0.0) report.joint(index, "negative armature " + format(joint.armature));
  if (joint.has_position_limits) {
    if (joint.lower > joint.upper) {
      report.joint(index, "lower limit " + format(joint.lower) + " > upper limit " + format(joint.upper));
    }
    if (joint.start_position < joint.lower || joint.start_position > joint.upper) {
      report.joint(index, "start position " + format(joint.start_position) + " outside the limits [" + format(joint.lower) +
                              ", " + format(joint.upper) + "]");
    }
  }
}

}  // namespace

void validate_arm_model(const ArmModel& model, const ModelSourceLines& lines) {
  const Reporter report(model, lines);
  const int n_links = static_cast<int>(model.links.size());
  const int n_joints = static_cast<int>(model.joints.size());
  if (n_links == 0) report.model("no links");
  if (model.root_link < 0 || model.root_link >= n_links) report.model("root link index out of range");

  // Structure: every link but the root has exactly one parent joint, and joints appear in
  // tree order (a joint's parent is the root or the child of an earlier joint). Together these
  // rule out cycles and links disconnected from the root.
  std::vector<int> parent_joint(n_links, -1);
  std::vector<bool> reached(n_links, false);
  reached[model.root_link] = true;
  for (int j = 0; j < n_joints; ++j) {
    const Joint& joint = model.joints[j];
    if (joint.parent_link < 0 || joint.parent_link >= n_links) report.joint(j, "unknown parent link");
    if (joint.child_link < 0 || joint.child_link >= n_links) report.joint(j, "unknown child link");
    if (joint.child_link == model.root_link) {
      report.joint(j, "its child is the root link '" + model.links[model.root_link].name + "' (a cycle)");
    }
    if (parent_joint[joint.child_link] >= 0) {
      report.joint(j, "link '" + model.links[joint.child_link].name + "' has several parents (also joint '" +
                          model.joints[parent_joint[joint.child_link]].name + "')");
    }
    parent_joint[joint.child_link] = j;
    if (!reached[joint.parent_link]) {
      report.joint(j, "parent link '" + model.links[joint.parent_link].name +
                          "' is not connected to the root before this joint (a cycle, or joints out of tree order)");
    }
    reached[joint.child_link] = true;
  }
  for (int l = 0; l < n_links; ++l) {
    if (!reached[l]) {
      report.link(l, "not connected to the root link '" + model.links[model.root_link].name + "' by any joint");
    }
  }

  for (int l = 0; l < n_links; ++l) {
    const Link& link = model.links[l];
    const bool welded = parent_joint[l] >= 0 && model.joints[parent_joint[l]].type == JointType::fixed;
    validate_inertial(link, l, link.fixed_to_world || l == model.root_link || welded, report);
  }
  for (int j = 0; j < n_joints; ++j) validate_joint(model.joints[j], j, report);

  // -1: not chosen yet (load_arm_model_file on a file with several leaves); choose_end_effector sets it.
  if (model.end_effector.link < -1 || model.end_effector.link >= n_links) report.model("end effector link is out of range");
  if (!finite(model.end_effector.offset)) report.model("NaN or Inf in the end effector offset");
}

}  // namespace armfarm
