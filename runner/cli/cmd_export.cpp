// `armfarm export DB --job KEY --series NAME`, `armfarm export DB --sweep NAME [--series A,B]`
// or `armfarm export DB [--sweep NAME] --metrics` [--format csv] [-o FILE]: recorded series or
// scalar metrics as CSV for pandas, R, Matlab or gnuplot. One job's series: a header of its
// column names and one line per sample. A whole sweep's series, or its metrics: one long-form
// table each (runner/io/sweep_export.hpp). Fields are RFC 4180, numbers the shortest text that reads
// back to the same double. With -o the file appears only once it is complete.
#include "analysis/sweep_data.hpp"
#include "base/number_format.hpp"
#include "results/readable_check.hpp"
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/io/csv_writing.hpp"
#include "runner/io/sweep_export.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace armfarm::cli {
namespace {

struct ExportOptions {
  std::string db;
  std::string job;
  std::string sweep;
  std::vector<std::string> series;
  std::string format = "csv";
  std::string output;
  bool metrics = false;
};

// Writes one job's series; 0, or 2 after a one-line error.
int write_job_series(const ResultsStore& store, const ExportOptions& options, std::ostream& out) {
  const std::vector<std::string> keys = store.find_job_keys(options.job);
  if (keys.empty()) {
    std::cerr << "armfarm: " << options.db << ": no job with key " << options.job << "\n";
    return 2;
  }
  if (keys.size() > 1) {
    std::cerr << "armfarm: " << options.db << ": key prefix " << options.job << " matches " << keys.size()
              << " jobs; give more digits\n";
    return 2;
  }
  const JobRecord job = *store.find_job(keys.front());
  const std::optional<SeriesRecord> series = store.find_series(job.id, options.series.front());
  if (!series) {
    std::string names;
    for (const std::string& name : store.find_series_names(job.id)) names += (names.empty() ? "" : ", ") + name;
    std::cerr << "armfarm: " << options.db << ": job " << job.key << " has no series " << options.series.front()
              << " (it has: " << (names.empty() ? "none" : names) << ")\n";
    return 2;
  }
  for (std::size_t c = 0; c < series->columns.size(); ++c) out << (c ? "," : "") << make_csv_field(series->columns[c]);
  out << "\n";
  for (Eigen::Index r = 0; r < series->rows.rows(); ++r) {
    for (Eigen::Index c = 0; c < series->rows.cols(); ++c) {
      out << (c ? "," : "") << format_shortest_number(series->rows(r, c));
    }
    out << "\n";
  }
  return 0;
}

// Refuses option combinations CLI11 cannot express; 0, or 2 after a one-line error.
int check_export_options(const ExportOptions& options) {
  if (options.job.empty() && options.sweep.empty() && !options.metrics) {
    std::cerr << "armfarm: export: give --job KEY --series NAME, --sweep NAME or --metrics\n";
    return 2;
  }
  if (options.metrics && !options.series.empty()) {
    std::cerr << "armfarm: export: --metrics writes scalar metrics; --series is for the recorded series\n";
    return 2;
  }
  if (!options.job.empty() && options.series.size() != 1) {
    std::cerr << "armfarm: export: --job needs exactly one --series\n";
    return 2;
  }
  return 0;
}

// Writes a sweep's scalar metrics (the only sweep when none is named) and its counts to stderr.
void write_metrics(const ResultsStore& store, const ExportOptions& options, std::ostream& out) {
  const std::string name = choose_sweep(store, options.sweep.empty() ? std::nullopt : std::optional<std::string>(options.sweep));
  const MetricExportCounts counts = write_sweep_metrics_csv(store, name, out);
  std::cerr << "sweep " << name << ": " << counts.rows << " metric rows from " << counts.jobs << " jobs"
            << (counts.jobs_without_metrics ? " (" + std::to_string(counts.jobs_without_metrics) + " jobs without metrics)" : "")
            << "\n";
}

// Writes a sweep's series as one long-form table and its counts to stderr.
void write_sweep_series(const ResultsStore& store, const ExportOptions& options, std::ostream& out) {
  const std::string name = choose_sweep(store, options.sweep);
  const SweepExportCounts counts = write_sweep_long_csv(store, name, options.series, out);
  std::cerr << "sweep " << name << ": " << counts.rows << " rows from " << counts.jobs << " done jobs"
            << (counts.jobs_skipped ? " (" + std::to_string(counts.jobs_skipped) + " jobs not done, left out)" : "") << "\n";
}

// Writes what the options ask for and checks the stream; 0, or 2 after a one-line error.
int write_export(const ResultsStore& store, const ExportOptions& options, std::ostream& out) {
  int status = 0;
  try {
    if (!options.job.empty()) {
      status = write_job_series(store, options, out);
    } else if (options.metrics) {
      write_metrics(store, options, out);
    } else {
      write_sweep_series(store, options, out);
    }
  } catch (const std::exception& e) {  // a bad name, or no such sweep: no file is left behind
    std::cerr << "armfarm: " << options.db << ": " << e.what() << "\n";
    status = 2;
  }
  out.flush();
  if (status == 0 && !out) {
    std::cerr << "armfarm: " << (options.output.empty() ? "standard output" : options.output) << ": cannot write the CSV\n";
    status = 2;
  }
  return status;
}

// Gives the complete file its name, or removes the partial one after a failure; the final status.
int finish_output_file(std::ofstream& file, const std::string& temporary, const std::string& output, int status) {
  file.close();
  std::error_code error;
  if (status == 0) {
    std::filesystem::rename(temporary, output, error);
    if (error) {
      std::cerr << "armfarm: " << output << ": cannot write: " << error.message() << "\n";
      status = 2;
    }
  }
  if (status != 0) std::filesystem::remove(temporary, error);
  return status;
}

// The export: to standard output, or to OUTPUT.partial renamed to OUTPUT once complete.
int run_export(const ExportOptions& options) {
  if (const int refused = check_export_options(options)) return refused;
  const ResultsStore store = ResultsStore::open(options.db, ResultsStore::Mode::read_only);
  verify_readable(store);  // damaged rows and series are an error, not a quiet export
  if (options.output.empty()) return write_export(store, options, std::cout);
  const std::string temporary = options.output + ".partial";
  std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
  if (!file) {
    std::cerr << "armfarm: " << options.output << ": cannot write\n";
    return 2;
  }
  const int status = write_export(store, options, file);
  return finish_output_file(file, temporary, options.output, status);
}

}  // namespace

RunFunction setup_export(CLI::App& parent) {
  auto options = std::make_shared<ExportOptions>();
  CLI::App* app = parent.add_subcommand("export", "Write recorded series as CSV: one job's, or a whole sweep's as one long-form table");
  app->add_option("db", options->db, "Results database")->required();
  CLI::Option* job = app->add_option("--job", options->job, "Job key (or a unique prefix of it): its series as columns");
  CLI::Option* sweep = app->add_option("--sweep", options->sweep,
                                       "Sweep name: every done job's series as rows of job, swept parameters, time, "
                                       "joint, signal, value");
  CLI::Option* metrics = app->add_flag("--metrics", options->metrics,
                                       "The sweep's scalar metrics instead of its series, one row each: job, status, swept "
                                       "parameters, name, joint (1-based), checkpoint, value, unit, reason (why a value is empty)");
  job->excludes(sweep);
  sweep->excludes(job);
  metrics->excludes(job);
  app->add_option("--series", options->series,
                  "Series name (POS, TOR, ...); with --sweep a comma-separated list (default: every recorded series)")
      ->delimiter(',');
  app->add_option("--format", options->format,
                  "Output format (csv; parquet is not offered: Debian has no Arrow/Parquet C++ package)")
      ->check(CLI::IsMember({"csv"}))
      ->capture_default_str();
  app->add_option("-o,--output", options->output, "Output file, written complete or not at all (default: standard output)");
  return [options] { return run_export(*options); };
}

}  // namespace armfarm::cli
