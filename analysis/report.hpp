#pragma once
// A shareable report: one self-contained HTML page per sweep (plots embedded as inline SVG)
// with the spec, provenance, status summary, default tables and the plots the sweep has
// data for, plus an index page.
#include "results/results_store.hpp"

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// Writes `<out_dir>/index.html` and `<out_dir>/<sweep view name>.html` for the chosen sweep
/// (all sweeps when `sweep` is empty). Returns the pages written. Throws AnalysisError.
std::vector<std::string> write_report(const ResultsStore& store, const std::optional<std::string>& sweep,
                                      const std::string& out_dir);

/// Escapes &, <, >, " and ' for HTML text and attributes.
std::string escape_html(const std::string& text);

}  // namespace armfarm
