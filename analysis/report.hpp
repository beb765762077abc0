#pragma once
// A shareable report: one self-contained HTML page per sweep (plots embedded as inline SVG)
// with the spec, provenance, status summary, default tables and the plots the sweep has
// data for, a page per job, plus an index page.
#include "analysis/summary_statistics.hpp"
#include "results/results_store.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

struct SweepData;
struct ThesisResults;

/// The best result of a sweep as the index states it ("tracking_nmse 0.00081 (lower is
/// better): job 3f2a1b7c …"), or empty. The runner supplies it: the main metric is its concept
/// (runner/execution/run_headline.hpp), not the analysis's.
using DescribeBest = std::function<std::string(const SweepData&)>;

/// The main metric of a sweep (a job-level result metric with a direction), or empty. The
/// runner supplies it from the same rule as DescribeBest.
using ChooseMainMetric = std::function<std::optional<std::string>(const SweepData&)>;

struct ReportOptions {
  DescribeBest describe_best;          ///< the index's best-result cell; unset: "–"
  ChooseMainMetric choose_main_metric;  ///< the metric of each sweep page's metric-vs-param figures; unset: none
  std::function<std::string(const std::string& path)> param_unit;  ///< PlotRequest::param_unit
  const ThesisResults* against = nullptr;  ///< the thesis's tables beside each sweep they map to; must outlive the call
  Aggregate aggregate = Aggregate::mean;   ///< of the thesis comparison
};

/// Writes `<out_dir>/index.html` (a row per sweep: jobs, done, failed, diverged, started,
/// spec hash, best result), a page per sweep for the chosen sweep (all sweeps when `sweep` is
/// empty): a table of contents, the figures (the plot kinds it has data for, and the main
/// metric against each numeric swept parameter), then the tables (each in its own horizontally
/// scrolling box, sortable by a click on a column header; a few lines of inline JavaScript,
/// nothing fetched) with links to the jobs of each row, the thesis comparison with --against,
/// status, provenance and the spec; and a page per job (its configuration, metrics with units
/// and reasons, and the figures of its recorded series). File names are safe for any name
/// (make_report_file_name). The index is written even when a page cannot be, and then
/// AnalysisError names the pages that failed. Returns the pages written.
std::vector<std::string> write_report(const ResultsStore& store, const std::optional<std::string>& sweep,
                                      const std::string& out_dir, const ReportOptions& options = {});

/// `prefix` + `name` as a file name stem that any file system takes: letters, digits, "_" and
/// "-" kept, anything else "_", at most 64 characters of the name; when anything was replaced or
/// cut, "_" and 16 hex digits of a hash of the whole name follow, so that distinct names stay distinct.
std::string make_report_file_name(const std::string& prefix, const std::string& name);

/// Escapes &, <, >, " and ' for HTML text and attributes; control characters show as their
/// control pictures (make_visible_text: an ESC from a sweep's name reads "␛[31m").
std::string escape_html(const std::string& text);

}  // namespace armfarm
