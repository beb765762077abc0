// `armfarm job CONFIG.json [--json]`: runs one experiment job outside any sweep and prints its
// metrics. The file holds any subset of a job configuration; the rest takes the defaults. The
// configuration is validated first (the same checks as `expand` and `run`); the job then runs
// under a wall-time limit (--timeout, default one hour) and stops on Ctrl-C.
#include "engine/experiment/job_outcome.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/execution/stop_signal.hpp"
#include "runner/spec/config_check.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <string>

namespace armfarm::cli {
namespace {

nlohmann::json load_job_config(const std::string& path, const JobConfigSchema& schema) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error(path + ": cannot open the job configuration");
  nlohmann::json overrides;
  try {
    overrides = nlohmann::json::parse(file);
  } catch (const nlohmann::json::parse_error& error) {
    throw std::runtime_error(path + ": not valid JSON: " + error.what());
  }
  if (!overrides.is_object()) throw std::runtime_error(path + ": expected a JSON object");
  std::vector<std::string> errors;
  const nlohmann::json checked = calc_checked_value(overrides, schema.defaults, "", errors);
  if (!errors.empty()) throw std::runtime_error(path + ": " + errors.front());
  nlohmann::json config = schema.defaults;
  merge_config_into(config, checked);
  try {
    schema.validate(config);
  } catch (const ConfigError& error) {
    throw std::runtime_error(path + ": " + error.what());
  }
  return config;
}

nlohmann::json number_or_null(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

}  // namespace

RunFunction setup_job(CLI::App& parent) {
  CLI::App* command = parent.add_subcommand("job", "Run one experiment job from a configuration file and print its metrics");
  auto path = std::make_shared<std::string>();
  auto as_json = std::make_shared<bool>(false);
  auto timeout = std::make_shared<double>(3600.0);
  command->add_option("config", *path, "Job configuration (JSON; missing keys take their defaults)")->required();
  command->add_flag("--json", *as_json, "Print {status, message, end_time, metrics, per_joint} as JSON");
  command->add_option("--timeout", *timeout, "Stop the job after this many seconds of wall clock (0: none)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  return [path, as_json, timeout] {
    const JobConfigSchema schema = make_experiment_config_schema();
    const nlohmann::json config = load_job_config(*path, schema);
    JobOutcome outcome;
    StopSignalScope signals;
    const std::atomic<bool>& interrupted = signals.stop_requested();
    const auto start = std::chrono::steady_clock::now();
    const double limit = *timeout;
    bool timed_out = false;
    JobControl control;
    control.should_stop = [&] {
      if (limit > 0.0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > limit) timed_out = true;
      return timed_out || interrupted.load();
    };
    try {
      outcome = make_experiment_executor()(config, control);
    } catch (const ConfigError& error) {
      throw std::runtime_error(*path + ": " + error.what());
    }
    if (timed_out && outcome.status == JobStatus::timeout) {
      char text[96];
      std::snprintf(text, sizeof text, "stopped after the timeout of %g s (--timeout)", limit);
      outcome.message = text;
    }
    std::map<int, nlohmann::json> per_joint;
    nlohmann::json metrics = nlohmann::json::object();
    for (const Metric& metric : outcome.metrics) {
      if (metric.joint) {
        per_joint[*metric.joint]["joint"] = *metric.joint;
        per_joint[*metric.joint][metric.name] = number_or_null(metric.value.value_or(std::nan("")));
      } else {
        metrics[metric.name] = number_or_null(metric.value.value_or(std::nan("")));
      }
    }
    if (*as_json) {
      nlohmann::json out = {{"status", to_string(outcome.status)}, {"message", outcome.message}, {"end_time", outcome.end_time},
                            {"metrics", metrics}, {"per_joint", nlohmann::json::array()}};
      for (auto& [joint, values] : per_joint) out["per_joint"].push_back(values);
      std::cout << out.dump(2) << "\n";
    } else {
      std::printf("status %s at t = %.3f s%s%s\n", to_string(outcome.status), outcome.end_time,
                  outcome.message.empty() ? "" : ": ", outcome.message.c_str());
      for (const auto& [name, value] : metrics.items()) {
        std::printf("  %-30s %s\n", name.c_str(), value.dump().c_str());
      }
      for (const auto& [joint, values] : per_joint) {
        std::printf("  joint %d:", joint);
        for (const auto& [name, value] : values.items()) {
          if (name != "joint") std::printf(" %s=%s", name.c_str(), value.is_number() ? std::to_string(value.get<double>()).c_str() : "null");
        }
        std::printf("\n");
      }
    }
    return outcome.status == JobStatus::done ? 0 : 1;
  };
}

}  // namespace armfarm::cli
