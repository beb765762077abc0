// `armfarm report DB [--sweep NAME] --out DIR`: one self-contained HTML page per sweep (spec,
// provenance, status, default tables, plots) and an index, to share a sweep as a folder.
#include "analysis/report.hpp"
#include "results/readable_check.hpp"
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"

#include <iostream>
#include <memory>

namespace armfarm::cli {
namespace {

struct ReportOptions {
  std::string database;
  std::string sweep;
  std::string out;
};

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
    for (const std::string& page : write_report(store, sweep, options->out)) std::cout << "wrote " << page << "\n";
    return 0;
  };
}

}  // namespace armfarm::cli
