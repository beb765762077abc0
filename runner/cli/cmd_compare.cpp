// `armfarm compare BASE.db NEW.db [--sweep NAME] [--metrics …] [--rtol X] [--atol Y]
// [--tolerances FILE.json] [--pair-by PARAM,…] [--format md|json] [--all]`: regression check of NEW
// against BASE, jobs paired by what they computed (recording.* left out) or by the given parameters.
// Exit 0 within tolerance, 1 on a regression, 2 on a usage or file error.
#include "analysis/analysis_error.hpp"
#include "engine/io/input_file.hpp"
#include "analysis/comparison.hpp"
#include "results/readable_check.hpp"
#include "results/results_store.hpp"
#include "runner/cli/number_checks.hpp"
#include "runner/cli/subcommand.hpp"

#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

namespace armfarm::cli {
namespace {

struct CompareOptions {
  std::string base;
  std::string next;
  std::string sweep;
  std::vector<std::string> metrics;
  double rtol = 1e-6;
  double atol = 0.0;
  std::string tolerances;
  std::string format = "md";
  bool show_all = false;
  bool timing = false;
  std::vector<std::string> pair_by;
};

// Every job of a database (or of one sweep), each once.
std::vector<JobResult> load_jobs(const ResultsStore& store, const std::string& sweep) {
  if (!sweep.empty()) return load_sweep_data(store, choose_sweep(store, sweep)).jobs;
  std::vector<JobResult> jobs;
  std::map<std::string, bool> seen;
  for (const SweepRecord& record : store.find_sweeps()) {
    for (JobResult& job : load_sweep_data(store, record.name).jobs) {
      if (seen.emplace(job.key, true).second) jobs.push_back(std::move(job));
    }
  }
  return jobs;
}

}  // namespace

RunFunction setup_compare(CLI::App& parent) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* sub = parent.add_subcommand("compare", "Compare two results databases job by job; exit 1 when a metric regressed");
  sub->add_option("base", options->base, "Baseline database")->required();
  sub->add_option("new", options->next, "New database")->required();
  sub->add_option("--sweep", options->sweep, "Only this sweep's jobs");
  sub->add_option("--metrics", options->metrics, "Only these metrics")->delimiter(',');
  sub->add_option("--rtol", options->rtol, "Relative tolerance (default 1e-6)")->check(make_non_negative_check());
  sub->add_option("--atol", options->atol, "Absolute tolerance (default 0)")->check(make_non_negative_check());
  sub->add_option("--tolerances", options->tolerances, "JSON file of per-metric / per-joint tolerances and directions");
  sub->add_option("--format", options->format, "md or json")->check(CLI::IsMember({"md", "json"}));
  sub->add_flag("--all", options->show_all, "List every compared metric, not only those outside tolerance");
  sub->add_option("--pair-by", options->pair_by,
                  "Pair jobs by these parameters (dotted paths, e.g. control.gain_scale,seed) instead of their whole "
                  "configurations; recording.* keys never prevent pairing")
      ->delimiter(',');
  sub->add_flag("--timing", options->timing,
                "Also show timing and diagnostic metrics (metric_info kind); they never count as regressions");
  return [options] {
    const Tolerance defaults{options->rtol, options->atol, std::nullopt};
    ToleranceTable tolerances;
    tolerances.defaults = defaults;
    if (!options->tolerances.empty()) {
      const std::string text = read_input_file_as<AnalysisError>(options->tolerances, InputFileKind::json);
      tolerances = parse_tolerances(text, options->tolerances, defaults);
    }
    const ResultsStore base = ResultsStore::open(options->base, ResultsStore::Mode::read_only);
    const ResultsStore next = ResultsStore::open(options->next, ResultsStore::Mode::read_only);
    verify_readable(base);  // damaged rows and series are an error, not a quiet comparison
    verify_readable(next);
    // What the names mean: the new database's catalog, the base's for names it lacks.
    MetricInfoTable info = load_metric_info(next);
    for (auto& [name, record] : load_metric_info(base)) info.emplace(name, record);
    const ComparisonReport report = compare_results(load_jobs(base, options->sweep), load_jobs(next, options->sweep),
                                                    tolerances, options->metrics, info, options->timing,
                                                    PairingRule{options->pair_by});
    std::cout << format_comparison(report, options->format == "json", options->show_all);
    return report.regressed() ? 1 : 0;
  };
}

}  // namespace armfarm::cli
