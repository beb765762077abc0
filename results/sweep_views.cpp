// The per-sweep views (one row per job, parameters and metrics as columns) and their names.
#include "results/store_internal.hpp"

#include <cstdio>
#include <set>
#include <sstream>

namespace armfarm {

std::string make_sweep_view_name(const std::string& sweep) {
  std::string name = "sweep_";
  bool replaced = false;
  for (char c : sweep) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    name += keep ? c : '_';
    replaced = replaced || !keep;
  }
  if (replaced) {
    std::uint64_t hash = 14695981039346656037ull;  // FNV-1a, 64 bit
    for (unsigned char c : sweep) hash = (hash ^ c) * 1099511628211ull;
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, "_%06llx", static_cast<unsigned long long>(hash & 0xFFFFFFull));
    name += suffix;
  }
  return name;
}

namespace store_detail {

void write_sweep_view(SqliteConnection& db, const std::string& sweep) {
  // Columns: the sweep's varying parameters, then its metrics (name, or name_j<joint>).
  std::set<std::string> param_names;
  {
    SqliteStatement statement = db.prepare(
        "SELECT DISTINCT e.key FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id, json_each(sj.params) e "
        "WHERE s.name = ? ORDER BY e.key");
    statement.bind(1, sweep);
    while (statement.step()) param_names.insert(statement.column_text(0));
  }
  struct MetricColumn {
    std::string name;
    std::optional<std::int64_t> joint, checkpoint;
  };
  std::vector<MetricColumn> metric_columns;
  {
    SqliteStatement statement = db.prepare(
        "SELECT DISTINCT m.name, m.joint, m.checkpoint FROM metrics m JOIN sweep_jobs sj ON sj.job_id = m.job_id "
        "JOIN sweeps s ON s.id = sj.sweep_id WHERE s.name = ? ORDER BY m.name, m.joint, m.checkpoint");
    statement.bind(1, sweep);
    while (statement.step()) {
      MetricColumn column{statement.column_text(0), std::nullopt, std::nullopt};
      if (!statement.is_null(1)) column.joint = statement.column_int(1);
      if (!statement.is_null(2)) column.checkpoint = statement.column_int(2);
      metric_columns.push_back(std::move(column));
    }
  }
  std::set<std::string> used = {"job_id", "key", "status", "seed", "message"};
  std::ostringstream sql;
  const std::string view = make_sweep_view_name(sweep);
  sql << "CREATE VIEW " << quote_identifier(view)
      << " AS SELECT j.id AS job_id, j.key AS key, j.status AS status, j.seed AS seed, j.message AS message";
  for (const std::string& param : param_names) {
    if (param.find('"') != std::string::npos || !used.insert(param).second) continue;
    sql << ", json_extract(sj.params, " << quote_literal("$.\"" + param + "\"") << ") AS " << quote_identifier(param);
  }
  for (const MetricColumn& metric : metric_columns) {
    const std::string column = make_metric_column_name(
        metric.name, metric.joint ? std::optional<int>(static_cast<int>(*metric.joint)) : std::nullopt, metric.checkpoint);
    if (!used.insert(column).second) continue;
    const auto match = [](const std::optional<std::int64_t>& value) {
      return value ? "= " + std::to_string(*value) : std::string("IS NULL");
    };
    sql << ", (SELECT m.value FROM metrics m WHERE m.job_id = j.id AND m.name = " << quote_literal(metric.name)
        << " AND m.joint " << match(metric.joint) << " AND m.checkpoint " << match(metric.checkpoint) << ") AS "
        << quote_identifier(column);
  }
  sql << " FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id JOIN jobs j ON j.id = sj.job_id WHERE s.name = "
      << quote_literal(sweep) << " ORDER BY sj.position";
  db.execute("DROP VIEW IF EXISTS " + quote_identifier(view));
  db.execute(sql.str());
}

}  // namespace store_detail

std::string make_metric_column_name(const std::string& name, std::optional<int> joint,
                                    std::optional<std::int64_t> checkpoint) {
  std::string column = name;
  if (joint) column += "_j" + std::to_string(*joint);
  if (checkpoint) column += "_c" + std::to_string(*checkpoint);
  return column;
}

void ResultsStore::update_sweep_view(const std::string& sweep) {
  SqliteTransaction transaction(*db_);
  store_detail::write_sweep_view(*db_, sweep);
  transaction.commit();
}

}  // namespace armfarm
