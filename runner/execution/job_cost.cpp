#include "runner/execution/job_cost.hpp"

#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/job_workload.hpp"
#include "runner/config/job_config_json.hpp"
#include "runner/execution/checked_experiment_job.hpp"
#include "runner/execution/job_models.hpp"
#include "runner/spec/input_files.hpp"

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <set>

namespace armfarm {

JobCostFunction make_experiment_cost_function(const JobCostModel& model) {
  auto models = std::make_shared<JobModels>();
  return [model, models](const nlohmann::json& recorded, const CheckedConfig* checked) {
    // An expanded job comes with its validated configuration; another (a finished job of a
    // reference database) is read here.
    const CheckedExperimentJob* carried = find_checked_experiment_job(checked);
    std::optional<ValidJobConfig> parsed;
    std::string path;
    if (carried != nullptr) {
      path = carried->model_path();
      parsed.emplace(carried->job.unpack());
    } else {
      const nlohmann::json config = calc_config_with_resolved_inputs(recorded);
      path = config.at("model").get<std::string>();
      const int movable = static_cast<int>(models->get_file(path)->movable_joints().size());
      // The model a job starts from does not change its cost: a stored one is not fetched here.
      parsed.emplace(parse_job_config(config, movable, [](const std::string&) { return std::string(); }));
      // The arm as the job runs it: its end effector and start posture chosen by the job's own
      // configuration, as at expansion and in the executor (a choice those accept works here).
      models->get(path, *parsed);
    }
    const JobConfig& job = parsed->get();
    const int movable = static_cast<int>(models->get_file(path)->movable_joints().size());
    const int n = job.active_joints.empty() ? movable : static_cast<int>(job.active_joints.size());
    const LearningConfig& learning = job.learning;
    // The control ticks of every pass, as the cost bound counts them (engine/experiment/job_workload.hpp).
    const double ticks = std::max(1.0, calc_job_workload(job, n).control_ticks);
    // A frozen learner predicts but never updates: costed as no learning.
    const bool learns = learning.mode == LearningMode::online || learning.mode == LearningMode::batch;
    const double factor = !learns                                ? model.none_factor
                          : learning.mode == LearningMode::online ? model.online_factor
                                                                  : model.batch_factor;
    JobCostEstimate estimate;
    estimate.cost = ticks * job.simulation.dt * std::max(1, n) * factor;
    estimate.seconds = estimate.cost * model.seconds_per_unit;
    estimate.kind = std::string(find_enum_name(learning_mode_names(), static_cast<int>(learning.mode))) + " " +
                    find_enum_name(trajectory_kind_names(), static_cast<int>(job.trajectory.kind)) + " " +
                    std::to_string(n) + " joints";
    return estimate;
  };
}

namespace {

/// calc_job_costs and calc_job_seconds: the estimates' `unit` (cost or seconds), calibrated
/// by the done jobs of `reference` when it has any.
std::vector<double> calc_calibrated(const ExpandedSweep& sweep, const JobCostFunction& estimate,
                                    const ResultsStore* reference, double JobCostEstimate::*unit) {
  std::vector<JobCostEstimate> estimates;
  estimates.reserve(sweep.jobs.size());
  for (const ExpandedJob& job : sweep.jobs) estimates.push_back(estimate(job.config(), job.checked.get()));
  std::vector<double> costs;
  for (const JobCostEstimate& e : estimates) costs.push_back(e.*unit);
  if (reference == nullptr) return costs;

  // Measured: wall seconds of the reference file's done jobs (each key once), and per kind the
  // sums of wall seconds and of estimates.
  std::map<std::string, double> measured_by_key;
  struct Rate {
    double wall = 0.0, estimated = 0.0;
  };
  std::map<std::string, Rate> by_kind;
  Rate all;
  std::set<std::string> seen;
  for (const SweepRecord& other : reference->find_sweeps()) {
    for (const JobRecord& job : reference->find_jobs(other.name)) {
      if (job.status != "done" || !job.wall_seconds || !(*job.wall_seconds > 0.0) || !seen.insert(job.key).second) {
        continue;
      }
      measured_by_key[job.key] = *job.wall_seconds;
      JobCostEstimate e;
      try {
        e = estimate(job.config, nullptr);
      } catch (const std::exception&) {
        continue;  // e.g. its model file is not on this machine: its time still counts for its own key
      }
      by_kind[e.kind].wall += *job.wall_seconds;
      by_kind[e.kind].estimated += e.*unit;
      all.wall += *job.wall_seconds;
      all.estimated += e.*unit;
    }
  }
  if (measured_by_key.empty()) return costs;
  for (std::size_t i = 0; i < costs.size(); ++i) {
    const auto measured = measured_by_key.find(sweep.jobs[i].key);
    if (measured != measured_by_key.end()) {
      costs[i] = measured->second;
      continue;
    }
    const auto kind = by_kind.find(estimates[i].kind);
    const Rate& rate = kind != by_kind.end() ? kind->second : all;
    // With no estimate to calibrate against (every finished job unreadable), the mean wall time.
    costs[i] = rate.estimated > 0.0 ? estimates[i].*unit * rate.wall / rate.estimated
                                    : all.wall / static_cast<double>(measured_by_key.size());
  }
  return costs;
}

}  // namespace

std::vector<double> calc_job_costs(const ExpandedSweep& sweep, const JobCostFunction& estimate,
                                   const ResultsStore* reference) {
  return calc_calibrated(sweep, estimate, reference, &JobCostEstimate::cost);
}

std::vector<double> calc_job_seconds(const ExpandedSweep& sweep, const JobCostFunction& estimate,
                                     const ResultsStore* reference) {
  return calc_calibrated(sweep, estimate, reference, &JobCostEstimate::seconds);
}

}  // namespace armfarm
