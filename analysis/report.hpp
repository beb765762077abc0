#pragma once
// A shareable report: one self-contained HTML page per sweep (plots embedded as inline SVG)
// with the spec, provenance, status summary, default tables and the plots the sweep has
// data for, plus an index page.
#include "results/results_store.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

struct SweepData;

/// The best result of a sweep as the index states it ("tracking_nmse 0.00081 (lower is
/// better): job 3f2a1b7c …"), or empty. The runner supplies it: the main metric is its concept
/// (runner/execution/run_headline.hpp), not the analysis's.
using DescribeBest = std::function<std::string(const SweepData&)>;

/// Writes `<out_dir>/index.html` (a row per sweep: jobs, done, failed, diverged, started,
/// spec hash, best result) and `<out_dir>/<sweep view name>.html` for the chosen sweep (all
/// sweeps when `sweep` is empty): a table of contents, the figures, then the tables (each in
/// its own horizontally scrolling box, sortable by a click on a column header; a few lines of
/// inline JavaScript, nothing fetched), status, provenance and the spec. Returns the pages
/// written. Throws AnalysisError.
std::vector<std::string> write_report(const ResultsStore& store, const std::optional<std::string>& sweep,
                                      const std::string& out_dir, const DescribeBest& describe_best = {});

/// Escapes &, <, >, " and ' for HTML text and attributes.
std::string escape_html(const std::string& text);

}  // namespace armfarm
