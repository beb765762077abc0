// `armfarm model info FILE [--ee LINK[:x,y,z]] [--json]`: what a model file describes — the
// link tree, the joints (numbered 1.. as in job configurations) with their limits and drive
// figures, the start posture and where it comes from, what the default job puts on each joint
// (the mass-matrix diagonal at the start posture and the PD gains), link masses, total mass,
// the leaf links, the end effector and reach. The arm is made as a job makes it
// (make_job_model, with --ee as end_effector.link). A file that loads always prints: with
// several leaves and no choice the end effector shows as not chosen. Bad files exit 2 with the
// loader's one-line message.
#include "engine/experiment/control_figures.hpp"
#include "engine/experiment/job_model.hpp"
#include "engine/model/arm_reach.hpp"
#include "engine/model/model_loading.hpp"
#include "runner/cli/subcommand.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

namespace armfarm::cli {
namespace {

constexpr double kDegreesPerRadian = 180.0 / 3.14159265358979323846;

const char* type_name(JointType type) {
  switch (type) {
    case JointType::revolute: return "revolute";
    case JointType::continuous: return "continuous";
    case JointType::prismatic: return "prismatic";
    case JointType::fixed: return "fixed";
  }
  return "?";
}

nlohmann::json vector_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// JSON has no infinity: unlimited figures are null.
nlohmann::json limit_json(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

std::string number(double value, int precision = 4) {
  if (!std::isfinite(value)) return "-";
  std::ostringstream out;
  out << std::setprecision(precision) << value;
  return out.str();
}

// The per-joint columns of the default job's figures (text; JSON writes the same fields under
// "default_job"). The stability criterion's dt / pd_substeps / integrator steps that "auto"
// picks join this list (issue 22; JointControlFigures, engine/experiment/control_figures.hpp).
struct FigureColumn {
  const char* heading;
  int width;
  std::function<std::string(const JointControlFigures&)> cell;
};

const std::vector<FigureColumn>& figure_columns() {
  static const std::vector<FigureColumn> columns = {
      {"M_jj", 12, [](const JointControlFigures& f) { return number(f.mass_diagonal); }},
      {"kp", 12, [](const JointControlFigures& f) { return number(f.kp); }},
      {"kd", 12, [](const JointControlFigures& f) { return number(f.kd); }},
  };
  return columns;
}

nlohmann::json make_json(const ArmModel& model, const std::vector<JointControlFigures>& figures, const std::string& not_chosen) {
  nlohmann::json out;
  out["name"] = model.name;
  out["file"] = model.source_file;
  out["root_link"] = model.links[model.root_link].name;
  out["links"] = nlohmann::json::array();
  for (const Link& link : model.links) {
    out["links"].push_back({{"name", link.name},
                            {"mass", link.inertial.mass},
                            {"com", vector_json(link.inertial.com)},
                            {"fixed_to_world", link.fixed_to_world}});
  }
  const std::vector<int> movable = model.movable_joints();
  out["joints"] = nlohmann::json::array();
  for (int j = 0; j < static_cast<int>(model.joints.size()); ++j) {
    const Joint& joint = model.joints[j];
    nlohmann::json entry = {{"name", joint.name},
                            {"type", type_name(joint.type)},
                            {"parent", model.links[joint.parent_link].name},
                            {"child", model.links[joint.child_link].name},
                            {"axis", vector_json(joint.axis)},
                            {"effort_limit", limit_json(joint.effort_limit)},
                            {"velocity_limit", limit_json(joint.velocity_limit)},
                            {"damping", joint.damping},
                            {"friction", joint.friction},
                            {"armature", joint.armature},
                            {"start_position", joint.start_position},
                            {"start_position_from_file", joint.start_position_from_file}};
    const auto index = std::find(movable.begin(), movable.end(), j);
    entry["number"] = index == movable.end() ? nlohmann::json(nullptr) : nlohmann::json(index - movable.begin() + 1);
    if (index != movable.end() && static_cast<std::size_t>(index - movable.begin()) < figures.size()) {
      const JointControlFigures& f = figures[index - movable.begin()];
      entry["default_job"] = {{"mass_diagonal", f.mass_diagonal}, {"kp", f.kp}, {"kd", f.kd}};
    }
    if (joint.has_position_limits) {
      entry["lower"] = joint.lower;
      entry["upper"] = joint.upper;
    } else {
      entry["lower"] = nullptr;
      entry["upper"] = nullptr;
    }
    out["joints"].push_back(entry);
  }
  out["degrees_of_freedom"] = movable.size();
  out["total_mass"] = model.total_mass();
  out["warnings"] = model.warnings;
  out["leaf_links"] = nlohmann::json::array();
  for (int leaf : find_leaf_links(model)) out["leaf_links"].push_back(model.links[leaf].name);
  if (model.end_effector.link >= 0) {
    out["reach"] = calc_reach(model);
    out["end_effector"] = {{"link", model.links[model.end_effector.link].name},
                           {"offset", vector_json(model.end_effector.offset)}};
  } else {
    out["reach"] = nullptr;
    out["end_effector"] = nullptr;  // not chosen: several leaves (--ee chooses)
    out["end_effector_problem"] = not_chosen;
  }
  return out;
}

void print_text(const ArmModel& model, const std::vector<JointControlFigures>& figures, std::ostream& out) {
  out << "model " << model.name << " (" << model.source_file << ")\n\ntree (parent -> child):\n";
  for (const Joint& joint : model.joints) {
    out << "  " << model.links[joint.parent_link].name << " -> " << model.links[joint.child_link].name << "  ["
        << joint.name << ", " << type_name(joint.type) << "]\n";
  }
  out << "\njoints (numbered 1.. over the movable joints in tree order, as in active_joints):\n";
  const std::vector<int> movable = model.movable_joints();
  std::size_t name_width = 4;
  for (int index : movable) name_width = std::max(name_width, model.joints[index].name.size());
  const int name_column = static_cast<int>(name_width) + 2;
  out << "  " << std::left << std::setw(3) << "#" << std::setw(name_column) << "name"
      << "type        axis               lower..upper deg      lower..upper rad    effort  velocity  armature  damping  start\n";
  for (std::size_t n = 0; n < movable.size(); ++n) {
    const Joint& joint = model.joints[movable[n]];
    std::ostringstream axis, deg, rad;
    axis << number(joint.axis.x(), 3) << " " << number(joint.axis.y(), 3) << " " << number(joint.axis.z(), 3);
    const bool angular = joint.type != JointType::prismatic;
    if (joint.has_position_limits) {
      deg << (angular ? number(joint.lower * kDegreesPerRadian) + " .. " + number(joint.upper * kDegreesPerRadian) : "(m)");
      rad << number(joint.lower) << " .. " << number(joint.upper);
    } else {
      deg << "unlimited";
      rad << "unlimited";
    }
    out << "  " << std::left << std::setw(3) << n + 1 << std::setw(name_column) << joint.name << std::setw(12) << type_name(joint.type)
        << std::setw(19) << axis.str() << std::setw(22) << deg.str() << std::setw(20) << rad.str() << std::setw(8)
        << number(joint.effort_limit) << std::setw(10) << number(joint.velocity_limit) << std::setw(10)
        << number(joint.armature) << std::setw(9) << number(joint.damping) << number(joint.start_position)
        << (joint.start_position_from_file ? "" : " (default)") << "\n";
  }
  out << "  (effort N·m or N, velocity rad/s or m/s, armature kg·m², damping N·m·s/rad, start rad or m; - = unlimited;\n"
         "   start (default): the file gives none, so 0 clamped into the middle half of the range; a job's start_posture replaces it)\n";
  if (!figures.empty()) {
    out << "\nthe default job on each joint (only \"model\" set; M_jj + armature at the start posture, gains after gain_scale):\n";
    out << "  " << std::left << std::setw(3) << "#" << std::setw(name_column) << "name";
    for (const FigureColumn& column : figure_columns()) out << std::setw(column.width) << column.heading;
    out << "\n";
    for (const JointControlFigures& f : figures) {
      out << "  " << std::left << std::setw(3) << f.number << std::setw(name_column) << model.joints[movable[f.number - 1]].name;
      for (const FigureColumn& column : figure_columns()) out << std::setw(column.width) << column.cell(f);
      out << "\n";
    }
    out << "  (M_jj kg·m² or kg, kp N·m/rad, kd N·m·s/rad)\n";
  }
  out << "\nlinks:\n";
  for (const Link& link : model.links) {
    out << "  " << std::left << std::setw(12) << link.name << std::right << std::setw(9) << std::fixed << std::setprecision(4)
        << link.inertial.mass << " kg" << std::defaultfloat << (link.fixed_to_world ? "  (fixed to the world)" : "") << "\n";
  }
  std::string leaves;
  for (int leaf : find_leaf_links(model)) leaves += (leaves.empty() ? "" : ", ") + model.links[leaf].name;
  out << std::fixed << std::setprecision(4) << "\ndegrees of freedom: " << movable.size()
      << "\ntotal mass: " << model.total_mass() << " kg (links not fixed to the world)"
      << "\nleaf links: " << leaves;
  if (model.end_effector.link >= 0) {
    const Link& tip = model.links[model.end_effector.link];
    out << "\nreach: " << calc_reach(model) << " m (joint-origin path from the first joint to the end effector)"
        << "\nend effector: " << tip.name << " + (" << model.end_effector.offset.transpose() << ") m\n";
  } else {
    out << "\nend effector: not chosen (several leaf links; choose with --ee LINK[:x,y,z], or end_effector.link in a job or a spec)\n";
  }
  out << std::defaultfloat;
}

}  // namespace

RunFunction setup_model_info(CLI::App& model) {
  CLI::App* info = model.add_subcommand("info", "Show a model's tree, joints, limits, masses, total mass and reach");
  auto file = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  info->add_option("FILE", *file, "Model file (.urdf or .dcg)")->required();
  info->add_flag("--json", *json, "Print JSON (stable keys) instead of text");
  auto ee = std::make_shared<std::string>();
  info->add_option("--ee", *ee, "End effector LINK[:x,y,z] (offset in m, in the link's frame)");
  auto strict = std::make_shared<bool>(false);
  info->add_flag("--strict", *strict, "Refuse non-URDF elements inside <link>/<joint> (by default skipped with a warning)");
  return [file, json, ee, strict] {
    const ArmModel file_model = load_arm_model_file(*file);
    if (*strict) check_strict_model(file_model);
    for (const std::string& warning : file_model.warnings) std::cerr << "armfarm: warning: " << warning << " (skipped; --strict refuses it)\n";
    // The default job's configuration, with --ee as its end_effector.link.
    JobConfig job;
    if (!ee->empty()) job.end_effector = parse_end_effector_text(*ee);
    ArmModel arm = file_model;
    std::string not_chosen;
    try {
      arm = make_job_model(file_model, job);
    } catch (const ModelError& error) {
      if (!ee->empty()) throw;  // a wrong --ee is an error; several leaves without one are shown
      not_chosen = error.what();
    }
    const std::vector<JointControlFigures> figures =
        arm.movable_joints().empty() ? std::vector<JointControlFigures>() : calc_joint_control_figures(arm, job);
    if (*json) {
      std::cout << make_json(arm, figures, not_chosen).dump(2) << "\n";
    } else {
      print_text(arm, figures, std::cout);
    }
    return 0;
  };
}

}  // namespace armfarm::cli
