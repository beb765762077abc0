// `armfarm job CONFIG.json [--json] [--db DB]`: runs one experiment job outside any sweep and
// prints its metrics. The file holds any subset of a job configuration; the rest takes the
// defaults. A stored-model reference in learning.initial_model ({"job": KEY} or {"sweep": NAME,
// "params": {...}}) is resolved from DB, read-only, by the resolver sweep expansion uses
// (runner/execution/stored_models.hpp). The configuration is validated first (the same checks as
// `expand` and `run`); the job then runs under a wall-time limit (--timeout, default one hour)
// and stops on Ctrl-C.
#include "engine/experiment/job_outcome.hpp"
#include "engine/model/end_effector.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/io/input_file.hpp"
#include "results/results_store.hpp"
#include "runner/cli/number_checks.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/execution/stop_signal.hpp"
#include "runner/execution/stored_models.hpp"
#include "runner/io/sweep_export.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/config_check.hpp"
#include "runner/spec/config_path.hpp"
#include "runner/spec/input_files.hpp"
#include "runner/spec/json_document.hpp"
#include "runner/spec/spec_error.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <stdexcept>
#include <sstream>
#include <string>

namespace armfarm::cli {
namespace {

// The stored model learning.initial_model names, resolved by the schema's resolver (from --db).
// A recorded "stored:<hash>" is resolved again from the reference recorded beside it; a note
// says when the database's model is no longer the recorded one (the job key differs).
void resolve_initial_model(nlohmann::json& config, const nlohmann::json& recorded, const JsonDocument& document,
                           const std::string& path, const JobConfigSchema& schema) {
  static const char* const kField = "learning.initial_model";
  static const char* const kStoredEntry = "learning.initial_model (stored)";
  nlohmann::json* value = nullptr;
  if (config.contains("learning") && config["learning"].is_object() && config["learning"].contains("initial_model")) {
    value = &config["learning"]["initial_model"];
  }
  std::string recorded_hash;
  if (value && value->is_string() && value->get<std::string>().rfind(kStoredModelPrefix, 0) == 0) {
    const auto entry = recorded.find(kStoredEntry);
    if (entry == recorded.end() || !entry->is_object() || !entry->contains("reference")) {
      throw std::runtime_error(path + ": " + kField + ": " + value->get<std::string>() + " is a resolved stored model but inputs[\"" +
                               kStoredEntry + "\"] does not record its reference");
    }
    recorded_hash = value->get<std::string>().substr(std::string(kStoredModelPrefix).size());
    *value = (*entry)["reference"];
  }
  if (!schema.resolve_references) return;
  try {
    schema.resolve_references(config);
  } catch (const std::runtime_error& error) {
    const std::string where = document.describe_position(kField);
    throw std::runtime_error(path + ": " + error.what() + (where.empty() ? "" : " (" + where + ")"));
  }
  if (recorded_hash.empty() || !config.contains("inputs") || !config["inputs"].contains(kStoredEntry)) return;
  const nlohmann::json& now = config["inputs"][kStoredEntry];
  if (now.value("hash", "") != recorded_hash) {
    std::cerr << "armfarm: note: " << path << ": " << kField << ": the stored model of job " << now.value("job", "").substr(0, 8)
              << " changed since the configuration was recorded (the job key differs)\n";
  }
}

// Reads a job configuration file: any subset of the keys (the rest take their defaults), or a
// stored configuration with its "inputs" (from `armfarm expand --json` or the results database).
// Input paths written in the file resolve against its folder; an input whose recorded entry
// still matches and whose resolved file exists is read from there; defaults resolve against the
// data folder. Every problem is a std::runtime_error naming the file.
// `end_effector` (from --ee) replaces the file's end_effector block. A stored-model reference is
// resolved by schema.resolve_references; a configuration recorded with a resolved one
// ("stored:<hash>" and its inputs entry) is resolved again from the reference it records.
// The configuration as the job records it, and what the schema's check made of it (the job runs
// from that: it is validated once).
struct LoadedJob {
  nlohmann::json config;
  std::shared_ptr<const CheckedConfig> checked;
};

LoadedJob load_job_config(const std::string& path, const JobConfigSchema& schema,
                          const std::optional<EndEffectorConfig>& end_effector) {
  const std::string text = read_input_file(path, InputFileKind::json);
  JsonDocument document;
  try {
    document = parse_json_document(text, path);
  } catch (const SpecError& error) {
    throw std::runtime_error(error.what());
  }
  nlohmann::json overrides = document.value;
  if (!overrides.is_object()) throw std::runtime_error(path + ": expected a JSON object");
  nlohmann::json recorded = nlohmann::json::object();
  if (overrides.contains("inputs")) {
    recorded = overrides["inputs"];
    if (!recorded.is_object()) throw std::runtime_error(path + ": inputs: expected an object (as `armfarm expand --json` writes it)");
    overrides.erase("inputs");
  }
  std::vector<CheckedValueProblem> errors;
  const nlohmann::json checked = calc_checked_value(overrides, schema.type_reference(), "", errors);
  if (!errors.empty()) {
    const CheckedValueProblem& first = errors.front();
    const std::string where = document.describe_position(first.path);
    throw std::runtime_error(path + ": " + first.line() + (where.empty() ? "" : " (" + where + ")"));
  }
  nlohmann::json config = schema.defaults;
  merge_config_into(config, checked);
  if (end_effector) {
    const Eigen::Vector3d& offset = end_effector->offset;
    config["end_effector"] = {{"link", end_effector->link}, {"offset", {offset.x(), offset.y(), offset.z()}}};
  }

  // Recorded includes stay (the key covers them); fields are read again.
  for (const auto& [name, entry] : recorded.items()) {
    if (entry.is_object() && entry.value("kind", "file") == "include") config["inputs"][name] = entry;
  }
  resolve_initial_model(config, recorded, document, path, schema);
  std::string folder = std::filesystem::path(path).parent_path().string();
  if (folder.empty()) folder = ".";
  std::map<std::string, std::string> written;
  for (const InputFileField& field : schema.input_files) {
    std::string unused;
    const ConfigPath segments = parse_config_path(field.path);
    const nlohmann::json* value = find_config_element(config, segments, unused);
    const auto entry = recorded.find(field.path);
    if (value == nullptr || entry == recorded.end() || !entry->is_object() || entry->value("path", "") != *value) continue;
    const std::string resolved = entry->value("resolved", "");
    if (resolved.empty() || !std::filesystem::exists(resolved)) continue;
    written[field.path] = value->get<std::string>();
    set_config_element(config, segments, resolved);
  }
  const auto folder_of = [&](const std::string& field) {
    std::string unused;
    return find_config_element(overrides, parse_config_path(field), unused) != nullptr ? folder : schema.default_folder;
  };
  InputFileReader reader;
  const std::vector<InputProblem> problems = record_input_files(config, schema.input_files, folder_of, reader);
  if (!problems.empty()) throw std::runtime_error(path + ": " + problems.front().field + ": " + problems.front().message);
  for (const auto& [field, text_as_written] : written) {
    set_config_element(config, parse_config_path(field), text_as_written);
    if (config.contains("inputs") && config["inputs"].contains(field)) config["inputs"][field]["path"] = text_as_written;
  }
  for (const auto& [name, entry] : recorded.items()) {
    if (!config.contains("inputs") || !config["inputs"].contains(name) || !entry.is_object() || !entry.contains("hash")) continue;
    if (config["inputs"][name]["hash"] != entry["hash"]) {
      std::cerr << "armfarm: note: " << path << ": inputs." << name << ": " << config["inputs"][name]["resolved"].get<std::string>()
                << " changed since the configuration was recorded (the job key differs)\n";
    }
  }
  try {
    std::shared_ptr<const CheckedConfig> checked = schema.validate(config);
    return {std::move(config), std::move(checked)};
  } catch (const ConfigError& error) {
    throw std::runtime_error(path + ": " + error.what());
  }
}

nlohmann::json number_or_null(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

struct JobOptions {
  std::string path;
  bool json = false;
  double timeout = 3600.0;
  std::string ee;
  bool strict = false;
  std::string db;
};

// The model's non-URDF elements: refused with --strict, else each a warning.
void check_model_elements(const nlohmann::json& config, bool strict) {
  const ArmModel model = load_arm_model_file(calc_config_with_resolved_inputs(config).at("model").get<std::string>());
  if (strict) check_strict_model(model);
  for (const std::string& warning : model.warnings) std::cerr << "armfarm: warning: " << warning << " (skipped; --strict refuses it)\n";
}

// Runs the job until it ends, Ctrl-C or the wall-time limit (0: none), which its message names.
JobOutcome run_loaded_job(const LoadedJob& job, const std::shared_ptr<StoredModels>& stored, const JobOptions& options) {
  StopSignalScope signals;
  const std::atomic<bool>& interrupted = signals.stop_requested();
  const auto start = std::chrono::steady_clock::now();
  const double limit = options.timeout;
  bool timed_out = false;
  JobControl control;
  control.should_stop = [&] {
    if (limit > 0.0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > limit) timed_out = true;
    return timed_out || interrupted.load();
  };
  JobOutcome outcome;
  try {
    outcome = make_experiment_executor(stored)(job.config, job.checked.get(), control);
  } catch (const ConfigError& error) {
    throw std::runtime_error(options.path + ": " + error.what());
  }
  if (timed_out && outcome.status == JobStatus::timeout) {
    char text[96];
    std::snprintf(text, sizeof text, "stopped after the timeout of %g s (--timeout)", limit);
    outcome.message = text;
  }
  return outcome;
}

// The outcome's metrics by name: the job's own, and per joint (1-based); a reason beside every
// null, and every note on a value.
struct JobMetricsJson {
  nlohmann::json metrics = nlohmann::json::object();
  nlohmann::json reasons = nlohmann::json::object();
  std::map<int, nlohmann::json> per_joint;
};

JobMetricsJson collect_metrics(const JobOutcome& outcome) {
  JobMetricsJson out;
  for (const Metric& metric : outcome.metrics) {
    // Held-out metrics are measured at checkpoints: "heldout_test_nmse_c200", as the sweep view
    // and the tables spell them (joints are the per_joint entries').
    const std::string name = make_metric_column_name(
        metric.name, std::nullopt, metric.checkpoint ? std::optional<std::int64_t>(metric.checkpoint->number) : std::nullopt);
    const nlohmann::json value = number_or_null(metric.value.value_or(std::nan("")));
    const std::string reason = value.is_null() ? describe_undefined_value(metric.reason) : metric.reason;
    if (metric.joint) {
      nlohmann::json& joint = out.per_joint[*metric.joint];
      joint["joint"] = *metric.joint;
      joint[name] = value;
      if (!reason.empty()) joint["reasons"][name] = reason;
    } else {
      out.metrics[name] = value;
      if (!reason.empty()) out.reasons[name] = reason;
    }
  }
  return out;
}

void print_job_json(const nlohmann::json& config, const JobOutcome& outcome, const JobMetricsJson& metrics) {
  nlohmann::json out = {{"key", calc_job_key(config)}, {"status", to_string(outcome.status)}, {"message", outcome.message},
                        {"end_time", outcome.end_time}, {"metrics", metrics.metrics}, {"reasons", metrics.reasons},
                        {"per_joint", nlohmann::json::array()}};
  for (const auto& [joint, values] : metrics.per_joint) out["per_joint"].push_back(values);
  std::cout << out.dump(2) << "\n";
}

void print_job_text(const JobOutcome& outcome, const JobMetricsJson& metrics) {
  std::printf("status %s at t = %.3f s%s%s\n", to_string(outcome.status), outcome.end_time, outcome.message.empty() ? "" : ": ",
              outcome.message.c_str());
  for (const auto& [name, value] : metrics.metrics.items()) {
    const std::string reason = metrics.reasons.value(name, "");
    std::printf("  %-30s %s%s%s\n", name.c_str(), value.dump().c_str(), reason.empty() ? "" : "  # ", reason.c_str());
  }
  for (const auto& [joint, values] : metrics.per_joint) {
    std::printf("  joint %d:", joint);
    for (const auto& [name, value] : values.items()) {
      if (name != "joint" && name != "reasons") {
        std::printf(" %s=%s", name.c_str(), value.is_number() ? std::to_string(value.get<double>()).c_str() : "null");
      }
    }
    std::printf("\n");
  }
}

// The command: load and check the configuration, run it, print its metrics; 0 when it is done.
int run_job_command(const JobOptions& options) {
  // Without --db a reference fails in the resolver with its "needs a results database" line.
  const auto stored = std::make_shared<StoredModels>(options.db);
  const JobConfigSchema schema = make_experiment_config_schema(stored);
  std::optional<EndEffectorConfig> end_effector;
  if (!options.ee.empty()) end_effector = parse_end_effector_text(options.ee);
  const LoadedJob job = load_job_config(options.path, schema, end_effector);
  check_model_elements(job.config, options.strict);
  const JobOutcome outcome = run_loaded_job(job, stored, options);
  const JobMetricsJson metrics = collect_metrics(outcome);
  if (options.json) {
    print_job_json(job.config, outcome, metrics);
  } else {
    print_job_text(outcome, metrics);
  }
  return outcome.status == JobStatus::done ? 0 : 1;
}

}  // namespace

RunFunction setup_job(CLI::App& parent) {
  CLI::App* command = parent.add_subcommand("job", "Run one experiment job from a configuration file and print its metrics");
  auto options = std::make_shared<JobOptions>();
  command->add_option("config", options->path, "Job configuration (JSON; missing keys take their defaults)")->required();
  command->add_flag("--json", options->json,
                    "Print {key, status, message, end_time, metrics, reasons, per_joint} as JSON (reasons: why a value "
                    "is null, or what a mean left out; per_joint entries carry their own)");
  command->add_option("--ee", options->ee, "End effector LINK[:x,y,z] (offset in m, link frame); sets end_effector.link and .offset");
  command->add_flag("--strict", options->strict, "Refuse non-URDF elements inside the model's <link>/<joint> (by default skipped with a warning)");
  command->add_option("--db", options->db, "Results database (read only) whose stored models learning.initial_model references name");
  command->add_option("--timeout", options->timeout, "Stop the job after this many seconds of wall clock (0: none)")
      ->check(make_non_negative_check())
      ->capture_default_str();
  return [options] { return run_job_command(*options); };
}

}  // namespace armfarm::cli
