#pragma once
// The thesis's published tables (sweeps/thesis/thesis_results.json) beside a results database:
// per thesis cell the printed value, the armfarm value over the matching done jobs and their
// ratio (armfarm / thesis). The JSON file says, per table, column, row or cell, which sweep,
// parameter filter, metric, joint and checkpoint reproduce the cell (`armfarm` objects):
//
//   {"sweep": "table6_4_sine", "where": {"control.mode": "composite"}, "metric": "ff_fb_ratio_avg",
//    "active_joint": 2, "checkpoint": 200}
//
// Levels merge table ← column ← row ← cell: `where` entries are added (a later level replaces a
// path an earlier one set), every other field is replaced. `"metric": null` says that armfarm has
// no counterpart for the cell. `active_joint` k is the thesis's "Joint k", the k-th entry of the
// job's `active_joints` (k itself when the job moves every joint); job-level metrics take none.
//
// A cell pools only jobs that differ in nothing but their seed. Each compared cell gets a
// verdict by the rule written in sweeps/thesis/README.md ("Verdicts"): "matches" when the
// thesis value lies inside armfarm's 95 % Student-t interval over the seeds; otherwise "same
// direction" when every comparison the thesis draws on the cell (the file's `comparisons`:
// cell A above cell B) holds in armfarm seed by seed, in every seed or by a one-sided sign
// test at 5 %; otherwise "differs". One seed gives no interval and no verdict ("one seed").
#include "analysis/summary_statistics.hpp"
#include "analysis/sweep_data.hpp"
#include "analysis/table.hpp"

#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace armfarm {

/// Which armfarm result reproduces a thesis cell (one level of the file, or the merged result).
struct ThesisMapping {
  std::optional<std::string> sweep;
  std::vector<std::pair<std::string, nlohmann::json>> where;  ///< dotted parameter path, value
  bool metric_given = false;          ///< the level names a metric (possibly null = none)
  std::optional<std::string> metric;  ///< empty with metric_given: no armfarm counterpart
  std::optional<int> active_joint;    ///< 1-based position in the job's active_joints
  std::optional<double> checkpoint;   ///< trials or periods of a held-out metric
};

/// One printed cell of a thesis table with its merged mapping.
struct ThesisCell {
  std::string row;
  std::string column;
  double value = 0.0;
  std::string printed;  ///< exactly as the thesis prints it ("1.95E-03", "0.013400")
  ThesisMapping mapping;
};

struct ThesisTable {
  std::string id;                     ///< "table6_1", "fig6_12_numerical"
  std::optional<std::string> number;  ///< "6.1"; empty for the unnumbered tables
  std::string caption;
  std::optional<int> page;            ///< only where the thesis text states it
  std::string heading;                ///< the line printed above the columns, if any
  std::vector<ThesisCell> cells;      ///< in the file's order
};

/// A cell of the file, by table id, row and column label.
struct ThesisCellRef {
  std::string table;
  std::string row;
  std::string column;
};

/// A comparison the thesis draws: `greater` above `less` (the thesis's own values agree; the
/// reader checks). Growth over reaches is the later checkpoint's cell above the earlier's.
struct ThesisClaim {
  std::string claim;  ///< the thesis's statement, in a few words
  ThesisCellRef greater;
  ThesisCellRef less;
};

/// A figure of the thesis as the file states it: number, caption, page (where the text gives
/// one), its stated facts (as written: numbers, text) and its `armfarm` mapping.
struct ThesisFigure {
  std::string number;  ///< "6.7"
  std::string caption;
  std::optional<int> page;
  nlohmann::json facts;  ///< the `facts` object (null when absent)
  ThesisMapping mapping;
};

struct ThesisResults {
  std::string path;
  /// The printed tables, then one table per figure with `fact_cells` (id "fig6_7", no number,
  /// one row per stated number, column "fact"; the value read from the figure's `facts` by its
  /// dotted path, so the number has one home).
  std::vector<ThesisTable> tables;
  std::vector<ThesisClaim> comparisons;
  std::vector<ThesisFigure> figures;  ///< in the file's order
  /// Sweeps the figures name (their `armfarm.sweep`), with the figure numbers: a --sweep that
  /// only draws figures without numbers is still known.
  std::map<std::string, std::vector<std::string>> figure_sweeps;
};

/// Whether `job` passes every `where` entry of `mapping` (its swept parameter, else its resolved
/// configuration by dotted path, equals the value).
bool matches_thesis_where(const JobResult& job, const ThesisMapping& mapping);

/// The arm joint (1-based) of the thesis's "Joint k" in `job`: the k-th of its active_joints, k
/// itself when every joint moves; empty when the job moves fewer than k joints.
std::optional<int> resolve_thesis_joint(const JobResult& job, int active_joint);

/// Parses the text of the thesis results file `path` (the runner reads it, see
/// engine/io/input_file.hpp). Throws AnalysisError "path: line L, column C: not valid JSON: …"
/// or "path: tables[2].cells[3].value: expected a number" (the JSON path of the first problem).
ThesisResults parse_thesis_results_text(const std::string& text, const std::string& path);

/// Parses an already-read document; `path` names it in messages.
ThesisResults parse_thesis_results(const nlohmann::json& document, const std::string& path);

enum class CellState {
  compared,   ///< at least one done job has the metric
  not_run,    ///< the sweep, a matching done job or the metric is absent (reason says which)
  no_metric,  ///< the mapping says armfarm has no counterpart
  unmapped,   ///< no sweep named for the cell
};

enum class Verdict {
  none,            ///< not compared
  one_seed,        ///< a single seed: no interval, no verdict
  matches,         ///< the thesis value lies inside the 95 % interval
  same_direction,  ///< every comparison the thesis draws on the cell holds across the seeds
  differs,         ///< neither
};
const char* to_string(Verdict verdict);

/// Whether a comparison holds across paired seeds: in every seed (at least 2), or a one-sided
/// sign test P(X ≥ successes | trials, ½) below 5 %.
bool holds_across_seeds(int successes, int trials);

struct ComparedCell {
  const ThesisCell* thesis = nullptr;
  CellState state = CellState::not_run;
  std::string reason;           ///< why not compared; empty when compared
  SummaryStatistics armfarm;    ///< over the matching done jobs that have the metric
  double armfarm_value = 0.0;   ///< the chosen aggregate
  std::optional<double> ratio;  ///< armfarm_value / thesis value (empty for a thesis 0)
  std::map<std::int64_t, double> by_seed;  ///< the pooled values by seed, for paired comparisons
  Verdict verdict = Verdict::none;
  std::string verdict_note;  ///< for "same direction" and "differs": each claim's seed count
};

struct ComparedTable {
  const ThesisTable* thesis = nullptr;
  std::vector<std::string> sweeps;  ///< the sweeps its cells read, in first-seen order
  std::vector<ComparedCell> cells;
};

struct ThesisComparison {
  std::vector<ComparedTable> tables;
  std::string note;  ///< printed when no table maps to the chosen sweep
};

/// Assigns every compared cell its verdict (cells located by table id, row and column).
void assign_verdicts(const ThesisResults& thesis, std::vector<ComparedTable>& tables);

/// Compares every cell against `sweeps` (by name; an absent name gives "not run").
/// `only_sweep`, when given, keeps the tables with a cell mapped to that sweep; when none is, the
/// result has no table and a `note` (which figures the sweep draws, if any); AnalysisError when
/// the file names the sweep nowhere and `known_sweeps` (the database's) lacks it too. The result points into `thesis`, which must outlive it.
ThesisComparison make_thesis_comparison(const ThesisResults& thesis, const std::map<std::string, SweepData>& sweeps,
                                        Aggregate aggregate, const std::optional<std::string>& only_sweep = std::nullopt,
                                        const std::vector<std::string>& known_sweeps = {});

/// Loads the sweeps the file names that the database holds, then compares.
ThesisComparison make_thesis_comparison(const ThesisResults& thesis, const ResultsStore& store, Aggregate aggregate,
                                        const std::optional<std::string>& only_sweep = std::nullopt);

/// A compared cell's armfarm value as every comparison prints it (`table --against`, the report's
/// Thesis section, the figures' tables): the mean and its 95 % interval, or the median, with 4
/// significant digits (format_table_number); "" when the cell was not compared.
std::string format_compared_value(const ComparedCell& cell, Aggregate aggregate);

/// The cell's armfarm/thesis ratio with 4 significant digits; "—" when it has none.
std::string format_compared_ratio(const ComparedCell& cell);

/// One table per thesis table: row, column, thesis value (as printed), armfarm value, ratio, n.
/// md, csv or json; throws AnalysisError for latex.
std::string format_thesis_comparison(const ThesisComparison& comparison, TableFormat format, Aggregate aggregate);

}  // namespace armfarm
