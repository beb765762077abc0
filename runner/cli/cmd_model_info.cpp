// `armfarm model info FILE [--ee LINK[:x,y,z]] [--json]`: what a model file describes — the
// link tree, the joints (numbered 1.. as in job configurations) with their limits and drive
// figures, the start posture and where it comes from, what the default job puts on each joint
// (the mass-matrix diagonal at the start posture and the PD gains), the PD period and RK4 steps
// "auto" picks for it with the stability criterion's ratios, link masses, total mass, the leaf
// links, the end effector and reach. The arm is made as a job makes it
// (make_job_model, with --ee as end_effector.link). A file that loads always prints: with
// several leaves and no choice the end effector shows as not chosen. Bad files exit 2 with the
// loader's one-line message.
#include "engine/experiment/control_figures.hpp"
#include "engine/experiment/job_model.hpp"
#include "engine/experiment/job_setup.hpp"
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
// "default_job"): its mass-matrix diagonal and gains, and the step-stability criterion's
// one-joint ratios at the steps "auto" picks (engine/experiment/control_figures.hpp).
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
      {"b", 10, [](const JointControlFigures& f) { return number(f.damping); }},
      {"kd·h/M", 10, [](const JointControlFigures& f) { return number(f.kd_ratio, 3); }},
      {"kp·h²/M", 10, [](const JointControlFigures& f) { return number(f.kp_ratio, 3); }},
      {"b·h_i/M", 10, [](const JointControlFigures& f) { return number(f.damping_ratio, 3); }},
  };
  return columns;
}

// `text` padded with spaces to `width` characters as a terminal shows them (UTF-8: the headings
// have · and ², two bytes each, which std::setw would count twice).
std::string pad(const std::string& text, int width) {
  const auto shown = std::count_if(text.begin(), text.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; });
  return text + std::string(static_cast<std::size_t>(std::max<long>(1, width - static_cast<long>(shown))), ' ');
}

nlohmann::json steps_json(const StepChoice& choice, bool fixed_step) {
  return {{"pd_substeps", choice.pd_substeps},
          {"integrator_steps_per_tick", fixed_step ? nlohmann::json(choice.integrator_steps) : nlohmann::json(nullptr)},
          {"stable", choice.found}};
}

// The steps line under the per-joint table: what "auto" picks for the default job and why.
std::string describe_steps(const JobStepFigures& steps) {
  const StepChoice& run = steps.run;
  const double period = steps.dt / run.pd_substeps;
  std::string text = "steps (\"auto\"): dt " + number(steps.dt) + " s, pd_substeps " + std::to_string(run.pd_substeps) +
                     " (PD period h = " + number(period) + " s)";
  if (steps.fixed_step) {
    text += ", integrator_steps_per_tick " + std::to_string(run.integrator_steps) + " (RK4 step h_i = " +
            number(period / run.integrator_steps) + " s)";
  }
  text += steps.trajectory_problem.empty() ? "\n  judged at the start posture and " + std::to_string(kStepPostures) +
                                                 " postures along each of the default job's trajectories"
                                           : "\n  judged at the start posture only (" + steps.trajectory_problem + ")";
  if (steps.trajectory_problem.empty()) {
    text += " (the start posture alone: " + std::to_string(steps.at_start.pd_substeps) +
            (steps.fixed_step ? ", " + std::to_string(steps.at_start.integrator_steps) : std::string()) + ")";
  }
  text += run.found ? "" : "; NOT stable within the keys' ranges: lower the gains or dt";
  if (steps.spectral_radius > 0.0) {
    text += "\n  at the start posture: fastest coupled mode kd·h/M = " + number(steps.modal_kd_ratio, 3) +
            " (bound 2), error ×" + number(steps.spectral_radius, 3) + " per PD period (≤ 1: stable)";
  }
  return text;
}

nlohmann::json make_json(const ArmModel& model, const ControlFigures& control, const std::string& not_chosen) {
  const std::vector<JointControlFigures>& figures = control.joints;
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
      entry["default_job"] = {{"mass_diagonal", f.mass_diagonal}, {"kp", f.kp},
                              {"kd", f.kd},
                              {"damping", f.damping},
                              {"kd_h_over_m", f.kd_ratio},
                              {"kp_h2_over_m", f.kp_ratio},
                              {"damping_h_over_m", limit_json(f.damping_ratio)}};
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
  if (!figures.empty()) {
    const JobStepFigures& steps = control.steps;
    nlohmann::json json = steps_json(steps.run, steps.fixed_step);
    json["dt"] = steps.dt;
    json["over_trajectories"] = steps.trajectory_problem.empty();
    if (!steps.trajectory_problem.empty()) json["trajectory_problem"] = steps.trajectory_problem;
    json["at_start_posture"] = steps_json(steps.at_start, steps.fixed_step);
    json["modal_kd_h_over_m"] = steps.modal_kd_ratio;
    json["spectral_radius"] = steps.spectral_radius;
    out["default_job_steps"] = json;
  }
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

void print_text(const ArmModel& model, const ControlFigures& control, std::ostream& out) {
  const std::vector<JointControlFigures>& figures = control.joints;
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
    out << "\nthe default job on each joint (only \"model\" set; M_jj + armature at the start posture, gains as the job runs them):\n";
    out << "  " << std::left << std::setw(3) << "#" << std::setw(name_column) << "name";
    for (const FigureColumn& column : figure_columns()) out << pad(column.heading, column.width);
    out << "\n";
    for (const JointControlFigures& f : figures) {
      out << "  " << std::left << std::setw(3) << f.number << std::setw(name_column) << model.joints[movable[f.number - 1]].name;
      for (const FigureColumn& column : figure_columns()) out << pad(column.cell(f), column.width);
      out << "\n";
    }
    out << "  (M_jj kg·m² or kg, kp N·m/rad, kd and b N·m·s/rad; kd·h/M, kp·h²/M, b·h_i/M: the stability criterion's one-joint\n"
           "   ratios at the steps below, bounds 2, 2·kd·h/M and 2.785; the criterion itself judges the coupled modes, engine/README.md)\n";
    out << describe_steps(control.steps) << "\n";
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
    const ControlFigures figures = arm.movable_joints().empty() ? ControlFigures() : calc_control_figures(arm, job);
    if (*json) {
      std::cout << make_json(arm, figures, not_chosen).dump(2) << "\n";
    } else {
      print_text(arm, figures, std::cout);
    }
    return 0;
  };
}

}  // namespace armfarm::cli
