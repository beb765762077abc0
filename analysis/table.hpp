#pragma once
// Experiment tables: swept parameters (and optionally the joint) as rows, metrics as columns,
// repeats (seeds) aggregated to the mean, its 95 % Student-t interval and their count. A row only pools
// jobs that differ in nothing but their seed (anything else is refused, naming the
// parameters). Jobs that did not finish (failed, diverged, timeout) are counted per row and
// never averaged in. Undefined values (NULL in the store) are left out of a cell and footnoted
// with their reason; a cell with no defined value prints "–".
#include "analysis/summary_statistics.hpp"
#include "base/did_you_mean.hpp"
#include "analysis/sweep_data.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace armfarm {

/// What a table shows. The row parameter "joint" puts each joint on its own row (the thesis's
/// per-joint tables) and per-joint metrics show that joint's value; otherwise a per-joint
/// metric shows its job-level row (the mean over the joints) when it has one, else one column
/// per joint. The row parameter "checkpoint" does the same for held-out metrics (stored per
/// checkpoint): one row per checkpoint; without it a checkpointed metric gets one column per
/// checkpoint ("heldout_test_nmse c2"). "joint" and "checkpoint" combine: rows group by the
/// swept parameters first, then expand over joints and checkpoints nested in the order given.
/// A metric without that dimension shows "–" on such rows, footnoted.
struct TableSpec {
  std::string title;
  std::vector<std::string> rows;     ///< dotted parameter paths, "joint" or "checkpoint"
  std::vector<std::string> metrics;  ///< metric names
  std::vector<int> joints;           ///< 1-based; empty = every joint present
  std::vector<std::pair<std::string, std::string>> where;  ///< keep jobs whose param equals the value
};

struct TableColumn {
  std::string header;
  MetricId metric;  ///< joint empty and `joint_from_row` true: the row's joint
  bool joint_from_row = false;
  bool job_level_on_joint_rows = false;  ///< a job-level-only metric in a per-joint table: not shown per joint
  bool checkpoint_from_row = false;      ///< metric.checkpoint empty: the row's checkpoint
  bool unchecked_on_checkpoint_rows = false;  ///< a metric without checkpoints in a per-checkpoint table
};

struct TableRow {
  std::vector<std::string> labels;  ///< one per TableSpec::rows entry
  std::optional<int> joint;         ///< when "joint" is a row parameter
  std::optional<std::int64_t> checkpoint;  ///< when "checkpoint" is a row parameter
  int jobs_done = 0;
  int jobs_failed = 0;    ///< failed, diverged or timeout
  int jobs_unfinished = 0;  ///< pending or running
  std::vector<SummaryStatistics> cells;  ///< one per column, over the row's done jobs' defined values
  std::vector<int> footnotes;            ///< one per column: 1-based index into Table::footnotes, 0 = none
};

struct Table {
  std::string title;
  std::vector<std::string> row_headers;
  std::vector<TableColumn> columns;
  std::vector<TableRow> rows;
  std::vector<std::string> footnotes;  ///< why cells are undefined or what their values leave out
};

enum class TableFormat { markdown, csv, latex, json };
/// Parses "md", "csv", "latex", "json"; throws std::invalid_argument otherwise.
TableFormat parse_table_format(const std::string& word);

/// Builds a table. Throws AnalysisError when a metric, row or --where parameter names nothing
/// in the sweep (with the nearest name), or when a row would pool jobs that differ in more than
/// their seed.
Table make_table(const SweepData& data, const TableSpec& spec);

/// The thesis's default tables that the sweep has metrics for: ff/fb statistics per joint
/// (tables 6.1, 6.4–6.7), tracking nMSE per task axis (6.2–6.3), test nMSE and receptive fields
/// against the swept parameters (figures 6.1–6.2), all from the training run; when the sweep
/// has held-out metrics, their tables with "checkpoint" (and for ff/fb "joint") as rows; a
/// table of all job-level metrics otherwise.
std::vector<TableSpec> make_default_table_specs(const SweepData& data);

/// Whether CSV output carries the footnotes (the reasons for undefined cells) as `# [k] …`
/// lines after the table. Off by default: pandas and R read comment lines as data rows.
enum class CsvNotes { omitted, comment_lines };

/// Renders a table as text in `format`, with cells as the chosen aggregate; the mean adds its
/// 95 % Student-t interval over the repeats, "0.2 [0.1, 0.3] (n=3)" (csv and json also the std).
/// Markdown, LaTeX and JSON always carry the footnotes; CSV only with CsvNotes::comment_lines.
std::string format_table(const Table& table, TableFormat format, Aggregate aggregate,
                         CsvNotes csv_notes = CsvNotes::omitted);

/// How a misspelt parameter or metric name is matched for "did you mean" (base/did_you_mean.hpp):
/// within the default typo limit of `word`, a dotted name also by its last segment.
NameMatch make_param_name_match(const std::string& word);

/// Formats a parameter value for a table cell: numbers with format_table_number, strings unquoted.
std::string format_param_value(const nlohmann::json& value);

}  // namespace armfarm
