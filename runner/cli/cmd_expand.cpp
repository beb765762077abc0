// `armfarm expand SPEC.json [--json]`: the jobs a sweep spec expands into, with their keys and
// varying parameters (the JSON form also gives each job's full configuration, accepted as is by
// `armfarm job`). A spec with stages expands one stage (--stage, default the first); a stage whose
// jobs start from stored models needs the database that holds them (--db).
#include "runner/cli/number_checks.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/job_kind.hpp"
#include "runner/execution/sweep_runner.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_stages.hpp"

#include <iostream>
#include <memory>

namespace armfarm::cli {

RunFunction setup_expand(CLI::App& parent) {
  struct Options {
    std::string spec;
    bool json = false;
    std::string db;
    std::string stage;
    ExpansionLimits limits;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand("expand", "List the jobs of a sweep spec with their keys and parameters");
  app->add_option("spec", options->spec, "Sweep spec (JSON)")->required();
  app->add_flag("--json", options->json, "Print {\"jobs\": [{\"key\", \"params\", \"config\"}]}");
  app->add_option("--db", options->db, "Results database whose stored models learning.initial_model references name");
  app->add_option("--stage", options->stage, "The stage of a staged spec to expand (default: the first)");
  app->add_option("--max-jobs", options->limits.max_jobs, "Refuse a sweep of more jobs than this")
      ->capture_default_str()->check(make_positive_check());

  return [options] {
    const JobKind kind = make_job_kind(options->db);
    ExpandedSweep sweep;
    try {
      std::vector<SweepSpec> stages = load_sweep_stages(options->spec, kind.schema);
      std::size_t chosen = 0;
      if (!options->stage.empty()) {
        std::string names;
        chosen = stages.size();
        for (std::size_t i = 0; i < stages.size(); ++i) {
          const std::string& name = stages[i].name;
          const std::string suffix = "." + options->stage;
          if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) chosen = i;
          names += (names.empty() ? "" : ", ") + name;
        }
        if (chosen == stages.size() || stages.size() == 1) {
          throw SpecError({options->spec + ": --stage " + options->stage + ": no such stage (the spec's sweeps: " + names + ")"});
        }
      }
      sweep = expand_sweep(std::move(stages[chosen]), kind.schema, options->limits);
    } catch (const SpecError& e) {
      for (const std::string& line : e.lines()) std::cerr << "armfarm: " << line << "\n";
      return 2;
    }
    if (options->json) {
      nlohmann::json out;
      out["sweep"] = sweep.spec.name;
      out["spec_hash"] = sweep.spec_hash;
      out["jobs"] = nlohmann::json::array();
      for (const ExpandedJob& job : sweep.jobs) {
        out["jobs"].push_back({{"key", job.key}, {"params", job.params}, {"config", job.config()}});
      }
      std::cout << out.dump(2) << "\n";
      return 0;
    }
    std::cout << "sweep " << sweep.spec.name << ": " << sweep.jobs.size() << " jobs\n";
    for (const ExpandedJob& job : sweep.jobs) {
      std::cout << job.key;
      for (const auto& [path, value] : job.params.items()) std::cout << "  " << path << "=" << value.dump();
      std::cout << "\n";
    }
    return 0;
  };
}

}  // namespace armfarm::cli
