#include "analysis/thesis_comparison.hpp"

#include "analysis/analysis_error.hpp"
#include "base/json_syntax_error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

namespace armfarm {
namespace {

using nlohmann::json;

// Parses one JSON file's text, naming the line and column of a syntax error.
json parse_json_text(const std::string& text, const std::string& path) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    throw AnalysisError(path + ": " + describe_text_position(text, calc_json_syntax_error_offset(e.byte)) + ": " +
                        make_json_syntax_reason(e.what()));
  }
}

// Walks the document, every error naming the file and the JSON path ("tables[2].cells[3].value").
class Reader {
 public:
  explicit Reader(std::string path) : path_(std::move(path)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw AnalysisError(path_ + ": " + where + ": " + what);
  }

  const json& member(const json& object, const std::string& where, const std::string& key) const {
    auto it = object.find(key);
    if (it == object.end()) fail(where, "missing key '" + key + "'");
    return *it;
  }

  std::string string(const json& object, const std::string& where, const std::string& key) const {
    const json& value = member(object, where, key);
    if (!value.is_string()) fail(where + "." + key, "expected a string");
    return value.get<std::string>();
  }

  std::optional<std::string> optional_string(const json& object, const std::string& where, const std::string& key) const {
    auto it = object.find(key);
    if (it == object.end() || it->is_null()) return std::nullopt;
    if (!it->is_string()) fail(where + "." + key, "expected a string or null");
    return it->get<std::string>();
  }

  std::optional<int> optional_positive_int(const json& object, const std::string& where, const std::string& key) const {
    auto it = object.find(key);
    if (it == object.end() || it->is_null()) return std::nullopt;
    if (!it->is_number_integer() || it->get<long long>() < 1) fail(where + "." + key, "expected a positive integer or null");
    return static_cast<int>(it->get<long long>());
  }

  ThesisMapping mapping(const json& owner, const std::string& owner_where) const {
    ThesisMapping result;
    auto it = owner.find("armfarm");
    if (it == owner.end() || it->is_null()) return result;
    const std::string where = owner_where + ".armfarm";
    if (!it->is_object()) fail(where, "expected an object");
    static const std::set<std::string> known = {"sweep", "where", "metric", "active_joint", "checkpoint", "note"};
    for (const auto& item : it->items()) {
      if (!known.count(item.key())) {
        fail(where + "." + item.key(), "unknown key (expected sweep, where, metric, active_joint, checkpoint, note)");
      }
    }
    result.sweep = optional_string(*it, where, "sweep");
    if (auto filter = it->find("where"); filter != it->end() && !filter->is_null()) {
      if (!filter->is_object()) fail(where + ".where", "expected an object {\"dotted.path\": value}");
      for (const auto& item : filter->items()) {
        if (item.value().is_object() || item.value().is_array()) {
          fail(where + ".where[\"" + item.key() + "\"]", "expected a number, string or boolean");
        }
        result.where.emplace_back(item.key(), item.value());
      }
    }
    if (auto metric = it->find("metric"); metric != it->end()) {
      result.metric_given = true;
      if (!metric->is_null() && !metric->is_string()) fail(where + ".metric", "expected a metric name or null");
      if (metric->is_string()) result.metric = metric->get<std::string>();
    }
    result.active_joint = optional_positive_int(*it, where, "active_joint");
    if (auto checkpoint = it->find("checkpoint"); checkpoint != it->end() && !checkpoint->is_null()) {
      if (!checkpoint->is_number() || !(checkpoint->get<double>() > 0.0)) {
        fail(where + ".checkpoint", "expected a positive number (trials or periods) or null");
      }
      result.checkpoint = checkpoint->get<double>();
    }
    return result;
  }

  // Label → mapping of a table's "rows" or "columns".
  std::map<std::string, ThesisMapping> labelled(const json& table, const std::string& where, const std::string& key) const {
    std::map<std::string, ThesisMapping> result;
    const json& list = member(table, where, key);
    if (!list.is_array()) fail(where + "." + key, "expected an array");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string item_where = where + "." + key + "[" + std::to_string(i) + "]";
      if (!list[i].is_object()) fail(item_where, "expected an object");
      const std::string label = string(list[i], item_where, "label");
      if (result.count(label)) fail(item_where + ".label", "'" + label + "' appears twice");
      result[label] = mapping(list[i], item_where);
    }
    return result;
  }

 private:
  std::string path_;
};

// Later levels replace fields and add to `where`.
void merge_into(ThesisMapping& merged, const ThesisMapping& level) {
  if (level.sweep) merged.sweep = level.sweep;
  for (const auto& [path, value] : level.where) {
    auto it = std::find_if(merged.where.begin(), merged.where.end(), [&key = path](const auto& entry) { return entry.first == key; });
    if (it != merged.where.end()) it->second = value;
    else merged.where.emplace_back(path, value);
  }
  if (level.metric_given) {
    merged.metric_given = true;
    merged.metric = level.metric;
  }
  if (level.active_joint) merged.active_joint = level.active_joint;
  if (level.checkpoint) merged.checkpoint = level.checkpoint;
}

ThesisTable parse_table(const Reader& reader, const json& node, const std::string& where) {
  if (!node.is_object()) reader.fail(where, "expected an object");
  ThesisTable table;
  table.id = reader.string(node, where, "id");
  table.number = reader.optional_string(node, where, "number");
  table.caption = reader.string(node, where, "caption");
  reader.member(node, where, "page");  // required, null where the thesis text gives no page
  table.page = reader.optional_positive_int(node, where, "page");
  table.heading = reader.optional_string(node, where, "heading").value_or("");
  const ThesisMapping table_mapping = reader.mapping(node, where);
  const auto columns = reader.labelled(node, where, "columns");
  const auto rows = reader.labelled(node, where, "rows");
  const json& cells = reader.member(node, where, "cells");
  if (!cells.is_array()) reader.fail(where + ".cells", "expected an array");
  std::set<std::pair<std::string, std::string>> seen;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::string cell_where = where + ".cells[" + std::to_string(i) + "]";
    const json& cell_node = cells[i];
    if (!cell_node.is_object()) reader.fail(cell_where, "expected an object");
    ThesisCell cell;
    cell.row = reader.string(cell_node, cell_where, "row");
    cell.column = reader.string(cell_node, cell_where, "column");
    auto row = rows.find(cell.row);
    if (row == rows.end()) reader.fail(cell_where + ".row", "'" + cell.row + "' is not a label of " + where + ".rows");
    auto column = columns.find(cell.column);
    if (column == columns.end()) {
      reader.fail(cell_where + ".column", "'" + cell.column + "' is not a label of " + where + ".columns");
    }
    if (!seen.insert({cell.row, cell.column}).second) reader.fail(cell_where, "a second cell for this row and column");
    const json& value = reader.member(cell_node, cell_where, "value");
    if (!value.is_number()) reader.fail(cell_where + ".value", "expected a number");
    cell.value = value.get<double>();
    cell.printed = reader.string(cell_node, cell_where, "printed");
    // The printed text is the published figure; the number must be the same figure.
    char* end = nullptr;
    const double printed_value = std::strtod(cell.printed.c_str(), &end);
    if (cell.printed.empty() || *end != '\0' || printed_value != cell.value) {
      reader.fail(cell_where + ".printed", "'" + cell.printed + "' is not the value " + format_table_number(cell.value, 6));
    }
    merge_into(cell.mapping, table_mapping);
    merge_into(cell.mapping, column->second);
    merge_into(cell.mapping, row->second);
    merge_into(cell.mapping, reader.mapping(cell_node, cell_where));
    table.cells.push_back(std::move(cell));
  }
  return table;
}

std::string describe_where(const ThesisMapping& mapping) {
  std::string text;
  for (const auto& [path, value] : mapping.where) {
    text += (text.empty() ? "" : ", ") + path + "=" + (value.is_string() ? value.get<std::string>() : value.dump());
  }
  return text;
}

// `job`'s value of `path`, without a "params"."seed" that equals the job's own seed: a stored-model
// reference to the earlier stage's job of the same seed ({"stage": "train", "params": {"seed": s}}
// in the job of seed s) repeats with the seed, so two-stage specs repeated by seed pool.
json param_value_without_own_seed(const JobResult& job, const std::string& path) {
  json value = find_param_value(job, path);
  if (!value.is_object()) return value;
  auto params = value.find("params");
  if (params == value.end() || !params->is_object()) return value;
  auto seed = params->find("seed");
  if (seed != params->end() && seed->is_number_integer() && seed->get<std::int64_t>() == job.seed) params->erase(seed);
  return value;
}

// The swept parameters (other than the seed) in which `jobs` differ, comma-separated.
std::string find_differing_params(const SweepData& data, const std::vector<const JobResult*>& jobs) {
  std::string names;
  for (const std::string& path : data.varying_params) {
    if (path == "seed" || jobs.empty()) continue;
    const json first = param_value_without_own_seed(*jobs.front(), path);
    for (const JobResult* job : jobs) {
      if (param_value_without_own_seed(*job, path) != first) {
        names += (names.empty() ? "" : ", ") + path;
        break;
      }
    }
  }
  return names;
}

// Marks a cell whose mapping names no sweep or no metric (unmapped, or armfarm has no metric);
// false when the mapping names both.
bool mark_unmapped(const ThesisMapping& mapping, ComparedCell& result) {
  if (!mapping.sweep) {
    result.state = CellState::unmapped;
    result.reason = "no sweep mapped";
  } else if (mapping.metric_given && !mapping.metric) {
    result.state = CellState::no_metric;
    result.reason = "armfarm has no metric for this cell";
  } else if (!mapping.metric) {
    result.state = CellState::unmapped;
    result.reason = "no metric mapped";
  } else {
    return false;
  }
  return true;
}

// The jobs of a sweep that a cell's mapping selects, counted by outcome, and the finite values
// of its metric (with their jobs and seeds).
struct CellPool {
  int matching = 0, done = 0, failed = 0, unfinished = 0, joint_missing = 0, undefined = 0;
  std::string undefined_reason;  ///< the first stored reason of an undefined value
  std::vector<double> values;
  std::vector<const JobResult*> jobs;      ///< the job of each value
  std::map<std::int64_t, double> by_seed;  ///< the first value of each seed
};

// The metric id a done job holds the cell's value under; empty when the job moves fewer joints
// than the cell's active_joint.
std::optional<MetricId> find_cell_metric_id(const JobResult& job, const ThesisMapping& mapping) {
  MetricId id{*mapping.metric, std::nullopt};
  if (mapping.active_joint) {
    id.joint = resolve_thesis_joint(job, *mapping.active_joint);
    if (!id.joint) return std::nullopt;
  }
  if (mapping.checkpoint) id.checkpoint = static_cast<std::int64_t>(std::llround(*mapping.checkpoint));
  return id;
}

CellPool pool_cell_jobs(const SweepData& sweep, const ThesisMapping& mapping) {
  CellPool pool;
  for (const JobResult& job : sweep.jobs) {
    if (!matches_thesis_where(job, mapping)) continue;
    ++pool.matching;
    if (job.status != "done") {
      (job.status == "pending" || job.status == "running" ? pool.unfinished : pool.failed) += 1;
      continue;
    }
    ++pool.done;
    const std::optional<MetricId> id = find_cell_metric_id(job, mapping);
    if (!id) {
      ++pool.joint_missing;
      continue;
    }
    auto metric = job.metrics.find(*id);
    if (metric == job.metrics.end()) continue;
    if (std::isfinite(metric->second)) {
      pool.values.push_back(metric->second);
      pool.by_seed.emplace(job.seed, metric->second);
      pool.jobs.push_back(&job);
    } else {
      ++pool.undefined;  // stored NULL: the metric is undefined for this job (its reason is in the store)
      auto reason = job.reasons.find(*id);
      if (reason != job.reasons.end() && pool.undefined_reason.empty()) pool.undefined_reason = reason->second;
    }
  }
  return pool;
}

// Why a pool has no value: no matching job, none done, too few joints, undefined or absent metric.
std::string describe_empty_pool(const CellPool& pool, const ThesisMapping& mapping) {
  if (pool.matching == 0) {
    const std::string filter = describe_where(mapping);
    return "no job of " + *mapping.sweep + (filter.empty() ? "" : " with " + filter);
  }
  if (pool.done == 0) {
    return "0 done, " + std::to_string(pool.failed) + " failed, " + std::to_string(pool.unfinished) + " unfinished";
  }
  if (pool.joint_missing == pool.done) return "the jobs move fewer than " + std::to_string(*mapping.active_joint) + " joints";
  if (pool.undefined > 0) {
    return "undefined in " + std::to_string(pool.undefined) + " job(s)" +
           (pool.undefined_reason.empty() ? "" : ": " + pool.undefined_reason);
  }
  if (mapping.checkpoint) {
    return "no checkpoint " + format_table_number(*mapping.checkpoint) + " of " + *mapping.metric + " in the database";
  }
  return "metric " + make_metric_label(MetricId{*mapping.metric, mapping.active_joint}) + " absent";
}

// Why a pool with values is not a set of repeats (its jobs differ in more than their seed, or
// two share a seed); empty when it is.
std::string find_pooling_problem(const SweepData& sweep, const CellPool& pool) {
  const std::string differing = find_differing_params(sweep, pool.jobs);
  if (!differing.empty()) return "the matching jobs differ in " + differing + ", not only in their seed; narrow the cell's where";
  if (pool.by_seed.size() != pool.values.size()) return "two matching jobs share a seed";
  return "";
}

ComparedCell compare_cell(const ThesisCell& cell, const std::map<std::string, SweepData>& sweeps, Aggregate aggregate) {
  ComparedCell result;
  result.thesis = &cell;
  const ThesisMapping& mapping = cell.mapping;
  if (mark_unmapped(mapping, result)) return result;
  auto sweep = sweeps.find(*mapping.sweep);
  if (sweep == sweeps.end()) {
    result.reason = "sweep " + *mapping.sweep + " absent";
    return result;
  }
  CellPool pool = pool_cell_jobs(sweep->second, mapping);
  if (pool.values.empty()) {
    result.reason = describe_empty_pool(pool, mapping);
    return result;
  }
  result.reason = find_pooling_problem(sweep->second, pool);  // repeats only: the jobs may differ in their seed alone
  if (!result.reason.empty()) return result;
  result.by_seed = std::move(pool.by_seed);
  result.state = CellState::compared;
  result.armfarm = calc_summary_statistics(pool.values);
  result.armfarm_value = result.armfarm.value(aggregate);
  if (cell.value != 0.0) result.ratio = result.armfarm_value / cell.value;
  return result;
}

std::string table_title(const ThesisTable& table) {
  std::string title = table.number ? "Table " + *table.number + ": " + table.caption : table.caption;
  if (!table.heading.empty()) title += " [" + table.heading + "]";
  if (table.page) title += " (page " + std::to_string(*table.page) + ")";
  return title;
}

std::string format_armfarm(const ComparedCell& cell, Aggregate aggregate) {
  if (cell.state == CellState::compared) return format_compared_value(cell, aggregate) + " (" + std::to_string(cell.armfarm.count) + ")";
  if (cell.state == CellState::not_run) return "not run (" + cell.reason + ")";
  if (cell.state == CellState::no_metric) return "no metric";
  return "not mapped (" + cell.reason + ")";
}

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string format_verdict(const ComparedCell& cell) {
  if (cell.verdict == Verdict::none) return "—";
  std::string text = to_string(cell.verdict);
  if (!cell.verdict_note.empty()) text += " (" + cell.verdict_note + ")";
  return text;
}

std::string describe_ref(const ThesisCellRef& ref) { return ref.table + " " + ref.row + " / " + ref.column; }

const char* to_string(CellState state) {
  switch (state) {
    case CellState::compared: return "compared";
    case CellState::not_run: return "not_run";
    case CellState::no_metric: return "no_metric";
    case CellState::unmapped: return "unmapped";
  }
  return "unknown";
}

// The document's "tables", each id once.
void parse_tables(const Reader& reader, const json& document, ThesisResults& results) {
  const json& tables = reader.member(document, "(top level)", "tables");
  if (!tables.is_array()) reader.fail("tables", "expected an array");
  std::set<std::string> ids;
  for (std::size_t i = 0; i < tables.size(); ++i) {
    const std::string where = "tables[" + std::to_string(i) + "]";
    results.tables.push_back(parse_table(reader, tables[i], where));
    if (!ids.insert(results.tables.back().id).second) reader.fail(where + ".id", "'" + results.tables.back().id + "' appears twice");
  }
}

// A figure as the file states it (number, caption, page, facts, mapping).
ThesisFigure parse_figure(const Reader& reader, const json& figure, const std::string& where) {
  ThesisFigure drawn;
  drawn.number = reader.string(figure, where, "number");
  drawn.caption = reader.string(figure, where, "caption");
  drawn.page = reader.optional_positive_int(figure, where, "page");
  if (auto facts = figure.find("facts"); facts != figure.end()) drawn.facts = *facts;
  drawn.mapping = reader.mapping(figure, where);
  return drawn;
}

// The sweep a figure's mapping names, if it names one by a string.
std::optional<std::string> find_figure_sweep(const json& figure) {
  auto mapping = figure.find("armfarm");
  if (mapping == figure.end() || !mapping->is_object()) return std::nullopt;
  auto sweep = mapping->find("sweep");
  if (sweep == mapping->end() || !sweep->is_string()) return std::nullopt;
  return sweep->get<std::string>();
}

// One stated number of a figure: the `facts` element its "fact" (a path, base/config_path.hpp) names.
// Its mapping is the figure's, then the cell's own.
ThesisCell parse_fact_cell(const Reader& reader, const json& node, const std::string& cell_where, const json& facts,
                           const std::string& facts_where, const ThesisMapping& figure_mapping) {
  if (!node.is_object()) reader.fail(cell_where, "expected an object {fact, label, armfarm}");
  ThesisCell cell;
  const std::string fact = reader.string(node, cell_where, "fact");
  cell.row = reader.string(node, cell_where, "label");
  cell.column = "fact";
  const json* value = find_config_value(facts, fact);
  if (value == nullptr) reader.fail(cell_where + ".fact", "no fact '" + fact + "' in " + facts_where);
  if (!value->is_number()) reader.fail(cell_where + ".fact", "'" + fact + "' is not a number");
  cell.value = value->get<double>();
  cell.printed = value->dump();
  merge_into(cell.mapping, figure_mapping);
  merge_into(cell.mapping, reader.mapping(node, cell_where));
  return cell;
}

// A figure's `fact_cells` as a table (id "fig6_7", column "fact"), the figure's mapping under each cell's.
ThesisTable parse_fact_table(const Reader& reader, const json& figure, const json& fact_cells, const std::string& where,
                             const std::string& number) {
  if (!fact_cells.is_array()) reader.fail(where + ".fact_cells", "expected an array");
  ThesisTable table;
  table.id = "fig" + number;
  std::replace(table.id.begin(), table.id.end(), '.', '_');
  table.caption = "Figure " + number + ": " + reader.string(figure, where, "caption") + " (stated facts)";
  table.page = reader.optional_positive_int(figure, where, "page");
  const ThesisMapping figure_mapping = reader.mapping(figure, where);
  const json& facts = reader.member(figure, where, "facts");
  for (std::size_t c = 0; c < fact_cells.size(); ++c) {
    const std::string cell_where = where + ".fact_cells[" + std::to_string(c) + "]";
    table.cells.push_back(parse_fact_cell(reader, fact_cells[c], cell_where, facts, where + ".facts", figure_mapping));
  }
  return table;
}

// The document's "figures" (optional): each figure, the sweeps they name, and a table per figure
// with fact cells (its id unique among the tables).
void parse_figures(const Reader& reader, const json& document, ThesisResults& results) {
  auto figures = document.find("figures");
  if (figures == document.end() || figures->is_null()) return;
  if (!figures->is_array()) reader.fail("figures", "expected an array");
  for (std::size_t i = 0; i < figures->size(); ++i) {
    const std::string where = "figures[" + std::to_string(i) + "]";
    const json& figure = (*figures)[i];
    if (!figure.is_object()) reader.fail(where, "expected an object");
    results.figures.push_back(parse_figure(reader, figure, where));
    const std::string& number = results.figures.back().number;
    if (auto sweep = find_figure_sweep(figure)) results.figure_sweeps[*sweep].push_back(number);
    auto fact_cells = figure.find("fact_cells");
    if (fact_cells == figure.end() || fact_cells->is_null()) continue;
    ThesisTable table = parse_fact_table(reader, figure, *fact_cells, where, number);
    for (const ThesisTable& other : results.tables) {
      if (other.id == table.id) reader.fail(where + ".number", "figure table '" + table.id + "' appears twice");
    }
    results.tables.push_back(std::move(table));
  }
}

// The cell `key` ("greater" or "less") of a comparison names, with the thesis's value there.
std::pair<ThesisCellRef, double> read_cell_ref(const Reader& reader, const ThesisResults& results, const json& node,
                                               const std::string& where, const std::string& key) {
  const std::string ref_where = where + "." + key;
  const json& ref_node = reader.member(node, where, key);
  if (!ref_node.is_object()) reader.fail(ref_where, "expected an object {table, row, column}");
  ThesisCellRef ref{reader.string(ref_node, ref_where, "table"), reader.string(ref_node, ref_where, "row"),
                    reader.string(ref_node, ref_where, "column")};
  for (const ThesisTable& table : results.tables) {
    if (table.id != ref.table) continue;
    for (const ThesisCell& cell : table.cells) {
      if (cell.row == ref.row && cell.column == ref.column) return {ref, cell.value};
    }
    reader.fail(ref_where, "table '" + ref.table + "' has no cell '" + ref.row + "' / '" + ref.column + "'");
  }
  reader.fail(ref_where + ".table", "no table '" + ref.table + "'");
}

// One comparison: `greater` above `less`, which the thesis's own values must agree with.
ThesisClaim parse_comparison(const Reader& reader, const ThesisResults& results, const json& node, const std::string& where) {
  if (!node.is_object()) reader.fail(where, "expected an object {claim, greater, less}");
  ThesisClaim claim;
  claim.claim = reader.string(node, where, "claim");
  const auto [greater, greater_value] = read_cell_ref(reader, results, node, where, "greater");
  const auto [less, less_value] = read_cell_ref(reader, results, node, where, "less");
  if (!(greater_value > less_value)) {
    reader.fail(where, "the thesis's own values (" + format_table_number(greater_value, 6) + " and " + format_table_number(less_value, 6) +
                           ") do not have greater above less");
  }
  claim.greater = greater;
  claim.less = less;
  return claim;
}

// The document's "comparisons" (optional), over the tables and figure tables read before.
void parse_comparisons(const Reader& reader, const json& document, ThesisResults& results) {
  auto comparisons = document.find("comparisons");
  if (comparisons == document.end() || comparisons->is_null()) return;
  if (!comparisons->is_array()) reader.fail("comparisons", "expected an array");
  for (std::size_t i = 0; i < comparisons->size(); ++i) {
    const std::string where = "comparisons[" + std::to_string(i) + "]";
    results.comparisons.push_back(parse_comparison(reader, results, (*comparisons)[i], where));
  }
}

json make_compared_cell_json(const ComparedCell& cell) {
  json entry = {{"row", cell.thesis->row}, {"column", cell.thesis->column}, {"thesis", cell.thesis->value},
                {"printed", cell.thesis->printed}, {"state", to_string(cell.state)}};
  entry["armfarm"] = cell.state == CellState::compared ? json(cell.armfarm_value) : json(nullptr);
  entry["ratio"] = cell.ratio ? json(*cell.ratio) : json(nullptr);
  entry["n"] = cell.armfarm.count;
  if (cell.state == CellState::compared) {
    entry["mean"] = cell.armfarm.mean;
    entry["std"] = cell.armfarm.std_dev;
    entry["ci95"] = cell.armfarm.has_ci() ? json::array({cell.armfarm.ci_low, cell.armfarm.ci_high}) : json(nullptr);
  }
  entry["verdict"] = cell.verdict == Verdict::none ? json(nullptr) : json(to_string(cell.verdict));
  if (!cell.verdict_note.empty()) entry["verdict_note"] = cell.verdict_note;
  if (!cell.reason.empty()) entry["reason"] = cell.reason;
  return entry;
}

// One array of tables, each with its cells (the note is not printed).
std::string format_comparison_json(const ThesisComparison& comparison, Aggregate aggregate) {
  json tables = json::array();
  for (const ComparedTable& table : comparison.tables) {
    json cells = json::array();
    for (const ComparedCell& cell : table.cells) cells.push_back(make_compared_cell_json(cell));
    tables.push_back({{"id", table.thesis->id},
                      {"number", table.thesis->number ? json(*table.thesis->number) : json(nullptr)},
                      {"caption", table.thesis->caption},
                      {"page", table.thesis->page ? json(*table.thesis->page) : json(nullptr)},
                      {"sweeps", table.sweeps},
                      {"aggregate", to_string(aggregate)},
                      {"cells", cells}});
  }
  return tables.dump(2) + "\n";
}

// One header, then a line per cell of every table (the note is not printed).
std::string format_comparison_csv(const ThesisComparison& comparison) {
  std::ostringstream out;
  out << "table,row,column,thesis,armfarm,ci95_low,ci95_high,ratio,n,verdict,state,reason\n";
  for (const ComparedTable& table : comparison.tables) {
    for (const ComparedCell& cell : table.cells) {
      const bool ci = cell.state == CellState::compared && cell.armfarm.has_ci();
      out << csv_field(table.thesis->id) << "," << csv_field(cell.thesis->row) << "," << csv_field(cell.thesis->column) << ","
          << cell.thesis->printed << ","
          << (cell.state == CellState::compared ? format_table_number(cell.armfarm_value, 6) : "") << ","
          << (ci ? format_table_number(cell.armfarm.ci_low, 6) : "") << "," << (ci ? format_table_number(cell.armfarm.ci_high, 6) : "") << ","
          << (cell.ratio ? format_table_number(*cell.ratio, 6) : "") << "," << cell.armfarm.count << ","
          << (cell.verdict == Verdict::none ? "" : to_string(cell.verdict)) << "," << to_string(cell.state) << ","
          << csv_field(cell.reason) << "\n";
    }
  }
  return out.str();
}

// "Verdicts over N cells: a matches, b same direction, …" over every table.
std::string format_verdict_counts(const ThesisComparison& comparison) {
  std::map<std::string, int> counts;
  int cells = 0;
  for (const ComparedTable& table : comparison.tables) {
    for (const ComparedCell& cell : table.cells) {
      ++cells;
      ++counts[cell.verdict == Verdict::none ? "not compared" : to_string(cell.verdict)];
    }
  }
  std::string text = "Verdicts over " + std::to_string(cells) + " cells:";
  bool first = true;
  for (const char* word : {"matches", "same direction", "differs", "one seed", "not compared"}) {
    text += (first ? " " : ", ") + std::to_string(counts[word]) + " " + word;
    first = false;
  }
  return text + "\n";
}

// The note, then per table its title, what armfarm pooled and a row per cell; the verdict counts last.
std::string format_comparison_markdown(const ThesisComparison& comparison, Aggregate aggregate) {
  std::ostringstream out;
  if (!comparison.note.empty()) out << comparison.note << "\n\n";
  for (const ComparedTable& table : comparison.tables) {
    std::string sweeps;
    for (const std::string& sweep : table.sweeps) sweeps += (sweeps.empty() ? "" : ", ") + sweep;
    out << "### " << table_title(*table.thesis) << "\n\n"
        << "armfarm: sweep " << (sweeps.empty() ? "(none mapped)" : sweeps) << ", " << to_string(aggregate)
        << (aggregate == Aggregate::mean ? " [95 % Student-t interval] (n seeds)" : " (n seeds)")
        << " over done jobs; verdicts by the rule of sweeps/thesis/README.md\n\n"
        << "| row | column | thesis | armfarm | armfarm/thesis | verdict |\n|---|---|---|---|---|---|\n";
    for (const ComparedCell& cell : table.cells) {
      out << "| " << cell.thesis->row << " | " << cell.thesis->column << " | " << cell.thesis->printed << " | "
          << format_armfarm(cell, aggregate) << " | " << format_compared_ratio(cell) << " | " << format_verdict(cell) << " |\n";
    }
    out << "\n";
  }
  out << format_verdict_counts(comparison);
  return out.str();
}

}  // namespace

ThesisResults parse_thesis_results(const nlohmann::json& document, const std::string& path) {
  const Reader reader(path);
  if (!document.is_object()) reader.fail("(top level)", "expected an object with a 'tables' array");
  ThesisResults results;
  results.path = path;
  parse_tables(reader, document, results);
  parse_figures(reader, document, results);
  parse_comparisons(reader, document, results);
  return results;
}

const char* to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::none: return "none";
    case Verdict::one_seed: return "one seed";
    case Verdict::matches: return "matches";
    case Verdict::same_direction: return "same direction";
    case Verdict::differs: return "differs";
  }
  return "none";
}

bool holds_across_seeds(int successes, int trials) {
  if (trials >= 2 && successes == trials) return true;
  return calc_sign_test_p(successes, trials) < 0.05;
}

void assign_verdicts(const ThesisResults& thesis, std::vector<ComparedTable>& tables) {
  auto locate = [&](const ThesisCellRef& ref) -> ComparedCell* {
    for (ComparedTable& table : tables) {
      if (table.thesis->id != ref.table) continue;
      for (ComparedCell& cell : table.cells) {
        if (cell.thesis->row == ref.row && cell.thesis->column == ref.column) return &cell;
      }
    }
    return nullptr;
  };
  for (ComparedTable& table : tables) {
    for (ComparedCell& cell : table.cells) {
      cell.verdict = Verdict::none;
      cell.verdict_note.clear();
      if (cell.state != CellState::compared) continue;
      if (!cell.armfarm.has_ci()) {
        cell.verdict = Verdict::one_seed;
        continue;
      }
      const double value = cell.thesis->value;
      if (cell.armfarm.ci_low <= value && value <= cell.armfarm.ci_high) {
        cell.verdict = Verdict::matches;
        continue;
      }
      // Outside the interval: the thesis's comparisons on this cell, paired by seed.
      int claims = 0, holding = 0;
      std::string notes;
      for (const ThesisClaim& claim : thesis.comparisons) {
        ComparedCell* greater = locate(claim.greater);
        ComparedCell* less = locate(claim.less);
        if (greater != &cell && less != &cell) continue;
        ++claims;
        const ThesisCellRef& other_ref = greater == &cell ? claim.less : claim.greater;
        const ComparedCell* other = greater == &cell ? less : greater;
        std::string note = std::string(greater == &cell ? "above " : "below ") + describe_ref(other_ref) + ": ";
        if (!other || other->state != CellState::compared) {
          notes += (notes.empty() ? "" : "; ") + note + "not run";
          continue;
        }
        int successes = 0, trials = 0;
        for (const auto& [seed, mine] : greater->by_seed) {
          auto paired = less->by_seed.find(seed);
          if (paired == less->by_seed.end()) continue;
          ++trials;
          if (mine > paired->second) ++successes;
        }
        const bool holds = holds_across_seeds(successes, trials);
        if (holds) ++holding;
        notes += (notes.empty() ? "" : "; ") + note + std::to_string(successes) + " of " + std::to_string(trials) + " seeds";
      }
      cell.verdict = claims > 0 && holding == claims ? Verdict::same_direction : Verdict::differs;
      cell.verdict_note = notes;
    }
  }
}

std::optional<int> resolve_thesis_joint(const JobResult& job, int active_joint) {
  const json active = find_param_value(job, "active_joints");
  if (!active.is_array() || active.empty()) return active_joint;
  if (active_joint > static_cast<int>(active.size()) || !active[active_joint - 1].is_number()) return std::nullopt;
  // The stored configuration is normalized JSON: joint numbers may read back as 2.0.
  const double joint = active[active_joint - 1].get<double>();
  if (joint != std::floor(joint) || joint < 1.0) return std::nullopt;
  return static_cast<int>(joint);
}

bool matches_thesis_where(const JobResult& job, const ThesisMapping& mapping) {
  for (const auto& [path, value] : mapping.where) {
    if (find_param_value(job, path) != value) return false;
  }
  return true;
}

ThesisResults parse_thesis_results_text(const std::string& text, const std::string& path) {
  return parse_thesis_results(parse_json_text(text, path), path);
}

ThesisComparison make_thesis_comparison(const ThesisResults& thesis, const std::map<std::string, SweepData>& sweeps,
                                        Aggregate aggregate, const std::optional<std::string>& only_sweep,
                                        const std::vector<std::string>& known_sweeps) {
  std::vector<ComparedTable> all;
  for (const ThesisTable& table : thesis.tables) {
    ComparedTable compared;
    compared.thesis = &table;
    for (const ThesisCell& cell : table.cells) {
      if (cell.mapping.sweep && std::find(compared.sweeps.begin(), compared.sweeps.end(), *cell.mapping.sweep) == compared.sweeps.end()) {
        compared.sweeps.push_back(*cell.mapping.sweep);
      }
      compared.cells.push_back(compare_cell(cell, sweeps, aggregate));
    }
    all.push_back(std::move(compared));
  }
  assign_verdicts(thesis, all);  // over every table: a comparison may cross tables
  ThesisComparison comparison;
  for (ComparedTable& compared : all) {
    if (only_sweep && std::find(compared.sweeps.begin(), compared.sweeps.end(), *only_sweep) == compared.sweeps.end()) continue;
    comparison.tables.push_back(std::move(compared));
  }
  if (only_sweep && comparison.tables.empty()) {
    auto figures = thesis.figure_sweeps.find(*only_sweep);
    const bool known = sweeps.count(*only_sweep) ||
                       std::find(known_sweeps.begin(), known_sweeps.end(), *only_sweep) != known_sweeps.end();
    if (figures == thesis.figure_sweeps.end() && !known) {
      throw AnalysisError(thesis.path + ": no table maps to sweep '" + *only_sweep + "', and the database holds no such sweep");
    }
    if (figures != thesis.figure_sweeps.end()) {
      std::string numbers;
      for (const std::string& number : figures->second) numbers += (numbers.empty() ? "" : ", ") + number;
      comparison.note = "sweep " + *only_sweep + " draws figure(s) " + numbers + ", whose stated facts give no number armfarm compares; " +
                        "read its metrics with `armfarm table DB --sweep " + *only_sweep + "`";
    } else {
      comparison.note = "sweep " + *only_sweep + " reproduces no table or figure of the thesis (" + thesis.path + ")";
    }
  }
  return comparison;
}

ThesisComparison make_thesis_comparison(const ThesisResults& thesis, const ResultsStore& store, Aggregate aggregate,
                                        const std::optional<std::string>& only_sweep) {
  std::set<std::string> wanted;
  for (const ThesisTable& table : thesis.tables) {
    for (const ThesisCell& cell : table.cells) {
      if (cell.mapping.sweep) wanted.insert(*cell.mapping.sweep);
    }
  }
  std::map<std::string, SweepData> sweeps;
  for (const SweepRecord& record : store.find_sweeps()) {
    if (wanted.count(record.name)) sweeps[record.name] = load_sweep_data(store, record.name);
  }
  std::vector<std::string> known;
  for (const SweepRecord& record : store.find_sweeps()) known.push_back(record.name);
  return make_thesis_comparison(thesis, sweeps, aggregate, only_sweep, known);
}

std::string format_compared_value(const ComparedCell& cell, Aggregate aggregate) {
  if (cell.state != CellState::compared) return "";
  return aggregate == Aggregate::mean ? format_mean_ci(cell.armfarm) : format_table_number(cell.armfarm_value);
}

std::string format_compared_ratio(const ComparedCell& cell) { return cell.ratio ? format_table_number(*cell.ratio) : "—"; }

std::string format_thesis_comparison(const ThesisComparison& comparison, TableFormat format, Aggregate aggregate) {
  if (format == TableFormat::latex) throw AnalysisError("--against prints md, csv or json, not latex");
  if (format == TableFormat::json) return format_comparison_json(comparison, aggregate);
  if (format == TableFormat::markdown) return format_comparison_markdown(comparison, aggregate);
  return format_comparison_csv(comparison);
}

}  // namespace armfarm
