// `armfarm report DB [--sweep NAME] --out DIR [--against THESIS.json]`: one self-contained HTML page
// per sweep (spec, provenance, status, default tables, plots, the thesis's values) and per job, and an
// index, to share a sweep as a folder.
#include "analysis/plots.hpp"
#include "analysis/report.hpp"
#include "analysis/analysis_error.hpp"
#include "analysis/sweep_data.hpp"
#include "analysis/thesis_comparison.hpp"
#include "engine/io/input_file.hpp"
#include "results/readable_check.hpp"
#include "results/results_store.hpp"
#include "runner/cli/param_unit.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/run_headline.hpp"

#include <cmath>
#include <cstdio>

#include <iostream>
#include <memory>

namespace armfarm::cli {
namespace {

struct ReportCommandOptions {
  std::string database;
  std::string sweep;
  std::string out;
  std::string against;
  std::string aggregate = "mean";
};

// The run headline (main metric, best job) over a sweep's done jobs.
std::optional<RunHeadline> find_headline(const SweepData& data) {
  std::vector<HeadlineJob> jobs;
  for (const JobResult& job : data.jobs) {
    if (job.status != "done") continue;
    HeadlineJob headline{make_job_label(job), {}};
    for (const auto& [id, value] : job.metrics) {
      if (!id.joint && !id.checkpoint && std::isfinite(value)) headline.metrics[id.name] = value;
    }
    jobs.push_back(std::move(headline));
  }
  return choose_run_headline(jobs);
}

// The index's "best" cell: the run headline's main metric and best job over the done jobs.
std::string describe_best_job(const SweepData& data) {
  const std::optional<RunHeadline> headline = find_headline(data);
  if (!headline) return "";
  char best[32];
  std::snprintf(best, sizeof best, "%.4g", headline->best);
  return headline->metric + " = " + best + " (" + headline->direction + " is better, of " + std::to_string(headline->jobs) +
         " done): " + headline->best_label;
}

std::optional<std::string> choose_main_metric(const SweepData& data) {
  const std::optional<RunHeadline> headline = find_headline(data);
  return headline ? std::optional<std::string>(headline->metric) : std::nullopt;
}

}  // namespace

RunFunction setup_report(CLI::App& parent) {
  auto options = std::make_shared<ReportCommandOptions>();
  CLI::App* sub = parent.add_subcommand("report", "Write an HTML report of a results database into a folder");
  sub->add_option("database", options->database, "Results database (SQLite)")->required();
  sub->add_option("--sweep", options->sweep, "Only this sweep (default: every sweep)");
  sub->add_option("--out", options->out, "Output folder")->required();
  sub->add_option("--against", options->against,
                  "Thesis results JSON (sweeps/thesis/thesis_results.json): each sweep page gets the thesis's values beside armfarm's");
  sub->add_option("--agg", options->aggregate, "With --against: aggregate over repeats, mean (with its 95 % interval), median, min, max")
      ->check(CLI::IsMember({"mean", "median", "min", "max"}));
  return [options] {
    const ResultsStore store = ResultsStore::open(options->database, ResultsStore::Mode::read_only);
    verify_readable(store);  // damaged rows and series are an error, not a quiet report
    std::optional<std::string> sweep;
    if (!options->sweep.empty()) sweep = options->sweep;
    armfarm::ReportOptions report;
    report.describe_best = describe_best_job;
    report.choose_main_metric = choose_main_metric;
    report.param_unit = find_param_unit;
    report.aggregate = parse_aggregate(options->aggregate);
    std::optional<ThesisResults> thesis;
    if (!options->against.empty()) {
      thesis = parse_thesis_results_text(read_input_file_as<AnalysisError>(options->against, InputFileKind::json), options->against);
      report.against = &*thesis;
    }
    for (const std::string& page : write_report(store, sweep, options->out, report)) std::cout << "wrote " << page << "\n";
    return 0;
  };
}

}  // namespace armfarm::cli
