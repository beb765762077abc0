// `armfarm report DB [--sweep NAME] --out DIR`: one self-contained HTML page per sweep (spec,
// provenance, status, default tables, plots) and an index, to share a sweep as a folder.
#include "analysis/plots.hpp"
#include "analysis/report.hpp"
#include "analysis/sweep_data.hpp"
#include "results/readable_check.hpp"
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/run_headline.hpp"

#include <cmath>
#include <cstdio>

#include <iostream>
#include <memory>

namespace armfarm::cli {
namespace {

struct ReportOptions {
  std::string database;
  std::string sweep;
  std::string out;
};

// The index's "best" cell: the run headline's main metric and best job over the done jobs.
std::string describe_best_job(const SweepData& data) {
  std::vector<HeadlineJob> jobs;
  for (const JobResult& job : data.jobs) {
    if (job.status != "done") continue;
    HeadlineJob headline{make_job_label(job), {}};
    for (const auto& [id, value] : job.metrics) {
      if (!id.joint && !id.checkpoint && std::isfinite(value)) headline.metrics[id.name] = value;
    }
    jobs.push_back(std::move(headline));
  }
  const std::optional<RunHeadline> headline = choose_run_headline(jobs);
  if (!headline) return "";
  char best[32];
  std::snprintf(best, sizeof best, "%.4g", headline->best);
  return headline->metric + " = " + best + " (" + headline->direction + " is better, of " + std::to_string(headline->jobs) +
         " done): " + headline->best_label;
}

}  // namespace

RunFunction setup_report(CLI::App& parent) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* sub = parent.add_subcommand("report", "Write an HTML report of a results database into a folder");
  sub->add_option("database", options->database, "Results database (SQLite)")->required();
  sub->add_option("--sweep", options->sweep, "Only this sweep (default: every sweep)");
  sub->add_option("--out", options->out, "Output folder")->required();
  return [options] {
    const ResultsStore store = ResultsStore::open(options->database, ResultsStore::Mode::read_only);
    verify_readable(store);  // damaged rows and series are an error, not a quiet report
    std::optional<std::string> sweep;
    if (!options->sweep.empty()) sweep = options->sweep;
    for (const std::string& page : write_report(store, sweep, options->out, describe_best_job)) std::cout << "wrote " << page << "\n";
    return 0;
  };
}

}  // namespace armfarm::cli
