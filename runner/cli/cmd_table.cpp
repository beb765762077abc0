// `armfarm table DB [--sweep NAME] [--rows P,…] [--cols M,…] [--joints …] [--where P=V]
// [--agg mean|median|min|max] [--format md|csv|latex|json]`: experiment tables of a sweep,
// by default the thesis's (analysis/table.hpp); for a search sweep (md) also its best trials,
// rung survivors and budget spent (analysis/search_summary.hpp).
#include "analysis/analysis_error.hpp"
#include "analysis/printable_text.hpp"
#include "analysis/search_summary.hpp"
#include "analysis/table.hpp"
#include "analysis/thesis_comparison.hpp"
#include "engine/io/input_file.hpp"
#include "results/readable_check.hpp"
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"

#include <iostream>
#include <memory>

namespace armfarm::cli {
namespace {

struct TableOptions {
  std::string database;
  std::string sweep;
  std::vector<std::string> rows;
  std::vector<std::string> cols;
  std::vector<int> joints;
  std::vector<std::string> where;
  std::string aggregate = "mean";
  std::string format = "md";
  bool notes = false;
  std::string against;  ///< analysis/thesis_comparison.hpp
};

std::pair<std::string, std::string> parse_where(const std::string& text) {
  const auto equals = text.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw AnalysisError("--where \"" + text + "\": expected PARAM=VALUE");
  }
  return {text.substr(0, equals), text.substr(equals + 1)};
}

// The sweeps a table command prints: the one asked for, else every sweep of the database.
std::vector<std::string> choose_table_sweeps(const ResultsStore& store, const TableOptions& options) {
  if (!options.sweep.empty()) return {choose_sweep(store, options.sweep)};
  std::vector<std::string> sweeps;
  for (const SweepRecord& record : store.find_sweeps()) sweeps.push_back(record.name);
  if (sweeps.empty()) throw AnalysisError(options.database + ": the database holds no sweep");
  return sweeps;
}

// A sweep's table specs: one of --cols against the swept parameters, else the thesis's
// defaults; --rows, --joints and --where apply to each.
std::vector<TableSpec> make_table_specs(const SweepData& data, const TableOptions& options,
                                        const std::vector<std::pair<std::string, std::string>>& where) {
  std::vector<TableSpec> specs;
  if (!options.cols.empty()) {
    TableSpec spec;
    spec.title = "Sweep " + data.name;
    spec.metrics = options.cols;
    for (const std::string& path : data.varying_params) {
      if (path != "seed") spec.rows.push_back(path);
    }
    specs.push_back(spec);
  } else {
    specs = make_default_table_specs(data);
    for (TableSpec& spec : specs) spec.title = spec.title + " — sweep " + data.name;
  }
  for (TableSpec& spec : specs) {
    if (!options.rows.empty()) spec.rows = options.rows;
    spec.joints = options.joints;
    spec.where = where;
  }
  return specs;
}

// Prints one table (json: adds it to `json_tables`, printed at the end as one document); returns
// the footnotes a CSV left out.
std::size_t print_table(const Table& table, const std::string& sweep, TableFormat format, Aggregate aggregate, bool notes,
                        nlohmann::json& json_tables) {
  const std::string text = format_table(table, format, aggregate, notes ? CsvNotes::comment_lines : CsvNotes::omitted);
  if (format == TableFormat::json) {
    nlohmann::json document = {{"sweep", sweep}};
    document.update(nlohmann::json::parse(text));
    json_tables.push_back(std::move(document));
    return 0;
  }
  // md and latex are text for a terminal or a document: names print without escapes
  // (csv keeps the values exactly, json escapes control characters).
  const bool for_reading = format == TableFormat::markdown || format == TableFormat::latex;
  std::cout << (for_reading ? make_printable_text(text, /*keep_newlines=*/true) : text);
  if (format != TableFormat::csv) return 0;
  std::cout << "\n";
  return notes ? 0 : table.footnotes.size();
}

int run_table(const TableOptions& options) {
  const ResultsStore store = ResultsStore::open(options.database, ResultsStore::Mode::read_only);
  verify_readable(store);  // damaged rows and series are an error, not a quiet table
  const Aggregate aggregate = parse_aggregate(options.aggregate);
  const TableFormat format = parse_table_format(options.format);
  if (!options.against.empty()) {
    const ThesisResults thesis =
        parse_thesis_results_text(read_input_file_as<AnalysisError>(options.against, InputFileKind::json), options.against);
    const auto only = options.sweep.empty() ? std::nullopt : std::optional<std::string>(options.sweep);
    std::cout << format_thesis_comparison(make_thesis_comparison(thesis, store, aggregate, only), format, aggregate);
    return 0;
  }
  std::vector<std::pair<std::string, std::string>> where;
  for (const std::string& text : options.where) where.push_back(parse_where(text));
  std::size_t notes_left_out = 0;
  // json: one document for every table of every sweep, {"tables": [{"sweep": …, "title": …}, …]}.
  nlohmann::json json_tables = nlohmann::json::array();
  for (const std::string& sweep : choose_table_sweeps(store, options)) {
    const SweepData data = load_sweep_data(store, sweep);
    for (const TableSpec& spec : make_table_specs(data, options, where)) {
      notes_left_out += print_table(make_table(data, spec), sweep, format, aggregate, options.notes, json_tables);
    }
    // A search's best trials, rung survivors and budget (markdown only: csv, latex and json
    // stay one table kind; the rows are in the search tables for any other reader).
    if (format == TableFormat::markdown) {
      if (const std::optional<SearchSummary> summary = load_search_summary(store, sweep)) std::cout << "\n" << format_search_summary(*summary);
    }
  }
  if (format == TableFormat::json) std::cout << nlohmann::json{{"tables", json_tables}}.dump(2) << "\n";
  if (notes_left_out > 0) {
    std::cerr << "armfarm: table: " << notes_left_out
              << " footnotes (why cells are empty) left out of the CSV; --notes adds them as '# [k]' lines\n";
  }
  return 0;
}

}  // namespace

RunFunction setup_table(CLI::App& parent) {
  auto options = std::make_shared<TableOptions>();
  CLI::App* sub = parent.add_subcommand("table", "Print experiment tables of a results database (thesis tables by default)");
  sub->add_option("database", options->database, "Results database (SQLite)")->required();
  sub->add_option("--sweep", options->sweep, "Sweep name (default: every sweep of the database)");
  sub->add_option("--rows", options->rows, "Row parameters: dotted paths, 'joint' or 'checkpoint' (held-out metrics), e.g. learning.lwpr.init_D,checkpoint,joint (default: the swept parameters)")->delimiter(',');
  sub->add_option("--cols", options->cols, "Metrics as columns (default: the thesis's tables)")->delimiter(',');
  sub->add_option("--joints", options->joints, "Joints to show, 1-based (default: all)")->delimiter(',');
  sub->add_option("--where", options->where, "Keep jobs whose PARAM=VALUE (repeatable)");
  sub->add_option("--agg", options->aggregate, "Aggregate over repeats: mean (± std), median, min, max")
      ->check(CLI::IsMember({"mean", "median", "min", "max"}));
  sub->add_flag("--notes", options->notes,
                "With --format csv: the footnotes (why a cell is empty or what a mean left out) as '# [k] ...' lines "
                "after each table (off by default: pandas reads them as rows)");
  sub->add_option("--format", options->format, "md, csv, latex or json (one document: {\"tables\": [{\"sweep\", \"title\", \"rows\", …}]})")->check(CLI::IsMember({"md", "csv", "latex", "json"}));
  sub->add_option("--against", options->against, "Thesis results JSON (sweeps/thesis/thesis_results.json): thesis value, armfarm value, ratio per cell");
  return [options] { return run_table(*options); };
}

}  // namespace armfarm::cli
