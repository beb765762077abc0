// `armfarm export DB --job KEY --series NAME [--format csv]`: a recorded series as CSV (header
// of column names, one line per sample, full double precision) for Matlab, gnuplot or pandas.
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>

namespace armfarm::cli {

RunFunction setup_export(CLI::App& parent) {
  struct Options {
    std::string db;
    std::string job;
    std::string series;
    std::string format = "csv";
    std::string output;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand("export", "Write a job's recorded series as CSV");
  app->add_option("db", options->db, "Results database")->required();
  app->add_option("--job", options->job, "Job key (or a unique prefix of it)")->required();
  app->add_option("--series", options->series, "Series name (POS, TOR, ...)")->required();
  app->add_option("--format", options->format, "Output format")->check(CLI::IsMember({"csv"}))->capture_default_str();
  app->add_option("-o,--output", options->output, "Output file (default: standard output)");

  return [options] {
    const ResultsStore store = ResultsStore::open(options->db, ResultsStore::Mode::read_only);
    const std::vector<std::string> keys = store.find_job_keys(options->job);
    if (keys.empty()) {
      std::cerr << "armfarm: " << options->db << ": no job with key " << options->job << "\n";
      return 2;
    }
    if (keys.size() > 1) {
      std::cerr << "armfarm: " << options->db << ": key prefix " << options->job << " matches " << keys.size()
                << " jobs; give more digits\n";
      return 2;
    }
    const JobRecord job = *store.find_job(keys.front());
    const std::optional<SeriesRecord> series = store.find_series(job.id, options->series);
    if (!series) {
      std::string names;
      for (const std::string& name : store.find_series_names(job.id)) names += (names.empty() ? "" : ", ") + name;
      std::cerr << "armfarm: " << options->db << ": job " << job.key << " has no series " << options->series
                << " (it has: " << (names.empty() ? "none" : names) << ")\n";
      return 2;
    }
    std::ofstream file;
    if (!options->output.empty()) {
      file.open(options->output);
      if (!file) {
        std::cerr << "armfarm: " << options->output << ": cannot write\n";
        return 2;
      }
    }
    std::ostream& out = options->output.empty() ? std::cout : file;
    for (std::size_t c = 0; c < series->columns.size(); ++c) out << (c ? "," : "") << series->columns[c];
    out << "\n";
    char number[32];
    for (Eigen::Index r = 0; r < series->rows.rows(); ++r) {
      for (Eigen::Index c = 0; c < series->rows.cols(); ++c) {
        std::snprintf(number, sizeof number, "%.17g", series->rows(r, c));
        out << (c ? "," : "") << number;
      }
      out << "\n";
    }
    out.flush();
    if (!out) {
      std::cerr << "armfarm: cannot write the CSV\n";
      return 2;
    }
    return 0;
  };
}

}  // namespace armfarm::cli
