// `armfarm model dynamics FILE --q … [--qd …] [--qdd …] [--active …] [--ee LINK[:x,y,z]] [--strict] [--json]`:
// the nominal model's rigid-body quantities at one state: the inverse-dynamics torques
// τ = (M(q) + diag(armature)) q̈ + C(q, q̇) q̇ + g(q) (no friction, damping or limit forces;
// gravity −9.81 m/s² along world z), the end-effector position in the world frame and its
// Jacobian d(ee)/dq (3 × n). Vectors have one entry per active joint, in the order of
// --active (1-based movable-joint numbers as in `model info` and job configurations; default
// all); joints not active are locked at their start positions. Values are comma- or
// space-separated: `--q 0.3,-0.5`. Units: rad, rad/s, rad/s² (m… for sliders), N·m, m.
#include "engine/experiment/job_model.hpp"
#include "engine/model/end_effector.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "runner/cli/subcommand.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm::cli {
namespace {

struct DynamicsOptions {
  std::string file;
  std::vector<double> q, qd, qdd;
  std::vector<int> active;  // 1-based
  std::string ee;
  bool json = false;
  bool strict = false;
};

Eigen::VectorXd to_vector(const std::vector<double>& values, int n, const char* option, bool required) {
  if (values.empty() && !required) return Eigen::VectorXd::Zero(n);
  if (static_cast<int>(values.size()) != n) {
    throw std::invalid_argument(std::string(option) + ": " + std::to_string(values.size()) + " values for " + std::to_string(n) +
                                " active joints (one per joint of --active, in its order)");
  }
  for (double v : values) {
    if (!std::isfinite(v)) throw std::invalid_argument(std::string(option) + ": values must be finite");
  }
  return Eigen::Map<const Eigen::VectorXd>(values.data(), n);
}

nlohmann::json to_json(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

void print_row(const char* label, const Eigen::VectorXd& v) {
  std::printf("%-22s", label);
  for (Eigen::Index i = 0; i < v.size(); ++i) std::printf(" %13.6g", v[i]);
  std::printf("\n");
}

int run_dynamics(const DynamicsOptions& options) {
  // The arm as a job with only "model" and end_effector (--ee) set runs it (make_job_model).
  JobConfig job;
  if (!options.ee.empty()) job.end_effector = parse_end_effector_text(options.ee);
  const ArmModel model = make_job_model(load_arm_model_file(options.file), job);
  if (options.strict) check_strict_model(model);
  for (const std::string& warning : model.warnings) std::cerr << "armfarm: warning: " << warning << " (skipped; --strict refuses it)\n";
  const std::vector<int> movable = model.movable_joints();
  const int n_movable = static_cast<int>(movable.size());
  std::vector<int> numbers = options.active;
  if (numbers.empty()) {
    for (int j = 1; j <= n_movable; ++j) numbers.push_back(j);
  }
  std::set<int> seen;
  std::vector<int> indices;  // into movable_joints(), as ArmDynamics takes them
  for (int number : numbers) {
    if (number < 1 || number > n_movable) {
      throw std::invalid_argument("--active: joint " + std::to_string(number) + " does not exist; " + options.file + " has joints 1.." +
                                  std::to_string(n_movable));
    }
    if (!seen.insert(number).second) throw std::invalid_argument("--active: joint " + std::to_string(number) + " is listed twice");
    indices.push_back(number - 1);
  }
  const int n = static_cast<int>(indices.size());
  const Eigen::VectorXd q = to_vector(options.q, n, "--q", true);
  const Eigen::VectorXd qd = to_vector(options.qd, n, "--qd", false);
  const Eigen::VectorXd qdd = to_vector(options.qdd, n, "--qdd", false);

  ArmDynamics dynamics(model, indices);
  const Eigen::VectorXd tau = dynamics.calc_inverse_dynamics(q, qd, qdd);
  const Eigen::Vector3d ee = dynamics.calc_end_effector_position(q);
  const Eigen::Matrix3Xd jacobian = dynamics.calc_end_effector_jacobian(q);

  const std::string tip = model.links[model.end_effector.link].name;
  if (options.json) {
    nlohmann::json out;
    out["file"] = model.source_file;
    out["active_joints"] = numbers;
    out["joint_names"] = nlohmann::json::array();
    for (int index : indices) out["joint_names"].push_back(model.joints[movable[index]].name);
    out["end_effector"] = {{"link", tip}, {"offset", {model.end_effector.offset.x(), model.end_effector.offset.y(), model.end_effector.offset.z()}}};
    out["q"] = to_json(q);
    out["qd"] = to_json(qd);
    out["qdd"] = to_json(qdd);
    out["tau"] = to_json(tau);
    out["ee"] = to_json(ee);
    out["jacobian"] = nlohmann::json::array();  // 3 rows (world x, y, z) × one column per active joint
    for (int row = 0; row < 3; ++row) out["jacobian"].push_back(to_json(jacobian.row(row).transpose()));
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("model %s (%s), end effector %s + (%g %g %g) m\n", model.name.c_str(), model.source_file.c_str(), tip.c_str(),
              model.end_effector.offset.x(), model.end_effector.offset.y(), model.end_effector.offset.z());
  std::printf("%-22s", "joint");
  for (int number : numbers) std::printf(" %13d", number);
  std::printf("\n%-22s", "name");
  for (int index : indices) std::printf(" %13s", model.joints[movable[index]].name.c_str());
  std::printf("\n");
  print_row("q", q);
  print_row("qd", qd);
  print_row("qdd", qdd);
  print_row("tau (N·m or N)", tau);
  for (int row = 0; row < 3; ++row) {
    const std::string label = std::string("jacobian ") + "xyz"[row] + " (m/rad)";
    print_row(label.c_str(), jacobian.row(row).transpose());
  }
  std::printf("end effector (m, world): %.9g %.9g %.9g\n", ee.x(), ee.y(), ee.z());
  return 0;
}

}  // namespace

RunFunction setup_model_dynamics(CLI::App& model) {
  CLI::App* command = model.add_subcommand(
      "dynamics", "Inverse-dynamics torques, end-effector position and Jacobian of a model at a state (q, qd, qdd)");
  auto options = std::make_shared<DynamicsOptions>();
  command->add_option("FILE", options->file, "Model file (.urdf or .dcg)")->required();
  command->add_option("--q", options->q, "Joint positions, one per active joint (rad or m)")->required()->delimiter(',');
  command->add_option("--qd", options->qd, "Joint velocities (rad/s or m/s); default 0")->delimiter(',');
  command->add_option("--qdd", options->qdd, "Joint accelerations (rad/s² or m/s²); default 0")->delimiter(',');
  command->add_option("--active", options->active, "1-based joint numbers the vectors refer to (default all); others stay at their start positions")
      ->delimiter(',');
  command->add_option("--ee", options->ee, "End effector LINK[:x,y,z] (offset in m, in the link's frame)");
  command->add_flag("--strict", options->strict, "Refuse non-URDF elements inside <link>/<joint> (by default skipped with a warning)");
  command->add_flag("--json", options->json, "Print JSON: tau, ee, jacobian (3 rows × n columns), q, qd, qdd, active_joints");
  return [options] { return run_dynamics(*options); };
}

}  // namespace armfarm::cli
