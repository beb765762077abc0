// The search tables (results/search_store.hpp): their migration and ResultsStore's reads and writes.
#include "results/search_store.hpp"

#include "results/store_error.hpp"
#include "results/store_internal.hpp"

namespace armfarm {

namespace search_store_sql {

const char* const kMigration = R"sql(
CREATE TABLE searches (
  id INTEGER PRIMARY KEY,
  sweep_id INTEGER NOT NULL UNIQUE REFERENCES sweeps(id) ON DELETE CASCADE,
  method TEXT NOT NULL CHECK (method IN ('random', 'tpe', 'asha', 'successive_halving', 'hyperband')),
  sampler TEXT NOT NULL CHECK (sampler IN ('random', 'tpe')),
  seed INTEGER NOT NULL,
  eta INTEGER NOT NULL,
  slots INTEGER NOT NULL,
  budget_unit TEXT NOT NULL CHECK (budget_unit IN ('jobs', 'cpu_seconds')),
  budget REAL NOT NULL,
  resumable INTEGER NOT NULL,
  objective_metric TEXT NOT NULL,
  objective_direction TEXT NOT NULL CHECK (objective_direction IN ('lower', 'higher')),
  objective_joint INTEGER,
  objective_checkpoint INTEGER
);
CREATE TABLE search_rungs (
  search_id INTEGER NOT NULL REFERENCES searches(id) ON DELETE CASCADE,
  rung INTEGER NOT NULL,
  checkpoint INTEGER,
  cost REAL NOT NULL,
  PRIMARY KEY (search_id, rung)
);
CREATE TABLE search_trials (
  search_id INTEGER NOT NULL REFERENCES searches(id) ON DELETE CASCADE,
  trial INTEGER NOT NULL,
  bracket INTEGER NOT NULL,
  params TEXT NOT NULL,
  PRIMARY KEY (search_id, trial)
);
CREATE TABLE search_steps (
  search_id INTEGER NOT NULL REFERENCES searches(id) ON DELETE CASCADE,
  step INTEGER NOT NULL,
  trial INTEGER NOT NULL,
  rung INTEGER NOT NULL,
  visible INTEGER NOT NULL,
  kind TEXT NOT NULL CHECK (kind IN ('new', 'promotion')),
  cost REAL NOT NULL,
  job_id INTEGER NOT NULL REFERENCES jobs(id),
  objective REAL,
  reason TEXT,
  committed INTEGER NOT NULL DEFAULT 0,
  PRIMARY KEY (search_id, step),
  FOREIGN KEY (search_id, trial) REFERENCES search_trials(search_id, trial),
  FOREIGN KEY (search_id, rung) REFERENCES search_rungs(search_id, rung)
);
CREATE INDEX search_steps_by_job ON search_steps(job_id);
CREATE VIEW search_promotions AS
  SELECT s.name AS sweep, st.step AS step, st.trial AS trial, st.rung - 1 AS from_rung, st.rung AS to_rung,
         st.cost AS cost, j.key AS key, st.objective AS objective
    FROM search_steps st JOIN searches se ON se.id = st.search_id JOIN sweeps s ON s.id = se.sweep_id
    JOIN jobs j ON j.id = st.job_id
   WHERE st.kind = 'promotion';
)sql";

}  // namespace search_store_sql

namespace {

std::int64_t find_search_id(SqliteConnection& db, const std::string& sweep) {
  SqliteStatement query = db.prepare(
      "SELECT se.id FROM searches se JOIN sweeps s ON s.id = se.sweep_id WHERE s.name = ?");
  query.bind(1, sweep);
  if (!query.step()) throw StoreError(db.path() + ": sweep '" + sweep + "' has no search");
  return query.column_int(0);
}

}  // namespace

void ResultsStore::insert_search(const SearchRecord& search) {
  SqliteTransaction transaction(*db_);
  SqliteStatement sweep = db_->prepare("SELECT id FROM sweeps WHERE name = ?");
  sweep.bind(1, search.sweep);
  if (!sweep.step()) throw StoreError(path_ + ": no sweep '" + search.sweep + "' to attach a search to");
  const std::int64_t sweep_id = sweep.column_int(0);
  // A search is written once; a resumed run finds it and compares (the runner refuses a change).
  SqliteStatement existing = db_->prepare("SELECT id FROM searches WHERE sweep_id = ?");
  existing.bind(1, sweep_id);
  if (existing.step()) return;
  db_->prepare(
         "INSERT INTO searches (sweep_id, method, sampler, seed, eta, slots, budget_unit, budget, resumable, "
         "objective_metric, objective_direction, objective_joint, objective_checkpoint) "
         "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13)")
      .bind(1, sweep_id)
      .bind(2, search.method)
      .bind(3, search.sampler)
      .bind(4, search.seed)
      .bind(5, search.eta)
      .bind(6, search.slots)
      .bind(7, search.budget_unit)
      .bind(8, search.budget)
      .bind(9, static_cast<std::int64_t>(search.resumable))
      .bind(10, search.objective_metric)
      .bind(11, search.objective_direction)
      .bind(12, search.objective_joint)
      .bind(13, search.objective_checkpoint)
      .execute();
  const std::int64_t id = db_->last_insert_rowid();
  SqliteStatement rung = db_->prepare("INSERT INTO search_rungs (search_id, rung, checkpoint, cost) VALUES (?, ?, ?, ?)");
  for (const SearchRungRecord& r : search.rungs) {
    rung.bind(1, id).bind(2, r.rung).bind(3, r.checkpoint).bind(4, r.cost);
    rung.execute();
  }
  transaction.commit();
}

std::optional<SearchRecord> ResultsStore::find_search(const std::string& sweep) const {
  SqliteStatement query = db_->prepare(
      "SELECT se.id, se.method, se.sampler, se.seed, se.eta, se.slots, se.budget_unit, se.budget, se.resumable, "
      "se.objective_metric, se.objective_direction, se.objective_joint, se.objective_checkpoint "
      "FROM searches se JOIN sweeps s ON s.id = se.sweep_id WHERE s.name = ?");
  query.bind(1, sweep);
  if (!query.step()) return std::nullopt;
  SearchRecord r;
  r.sweep = sweep;
  const std::int64_t id = query.column_int(0);
  r.method = query.column_text(1);
  r.sampler = query.column_text(2);
  r.seed = query.column_int(3);
  r.eta = query.column_int(4);
  r.slots = query.column_int(5);
  r.budget_unit = query.column_text(6);
  r.budget = query.column_double(7);
  r.resumable = query.column_int(8) != 0;
  r.objective_metric = query.column_text(9);
  r.objective_direction = query.column_text(10);
  if (!query.is_null(11)) r.objective_joint = query.column_int(11);
  if (!query.is_null(12)) r.objective_checkpoint = query.column_int(12);
  SqliteStatement rungs = db_->prepare("SELECT rung, checkpoint, cost FROM search_rungs WHERE search_id = ? ORDER BY rung");
  rungs.bind(1, id);
  while (rungs.step()) {
    SearchRungRecord rung;
    rung.rung = rungs.column_int(0);
    if (!rungs.is_null(1)) rung.checkpoint = rungs.column_int(1);
    rung.cost = rungs.column_double(2);
    r.rungs.push_back(rung);
  }
  return r;
}

void ResultsStore::insert_search_step(const std::string& sweep, const SearchStepRecord& step,
                                      const std::optional<SearchTrialRecord>& new_trial) {
  SqliteTransaction transaction(*db_);
  const std::int64_t id = find_search_id(*db_, sweep);
  if (new_trial) {
    db_->prepare("INSERT INTO search_trials (search_id, trial, bracket, params) VALUES (?, ?, ?, ?)")
        .bind(1, id)
        .bind(2, new_trial->trial)
        .bind(3, new_trial->bracket)
        .bind(4, new_trial->params)
        .execute();
  }
  SqliteStatement job = db_->prepare("SELECT id FROM jobs WHERE key = ?");
  job.bind(1, step.job_key);
  if (!job.step()) throw StoreError(path_ + ": search step " + std::to_string(step.step) + " names no job '" + step.job_key + "'");
  const std::int64_t job_id = job.column_int(0);
  db_->prepare(
         "INSERT INTO search_steps (search_id, step, trial, rung, visible, kind, cost, job_id) "
         "VALUES (?, ?, ?, ?, ?, ?, ?, ?)")
      .bind(1, id)
      .bind(2, step.step)
      .bind(3, step.trial)
      .bind(4, step.rung)
      .bind(5, step.visible)
      .bind(6, step.kind)
      .bind(7, step.cost)
      .bind(8, job_id)
      .execute();
  transaction.commit();
}

void ResultsStore::update_search_objective(const std::string& sweep, std::int64_t step, const std::optional<double>& objective,
                                           const std::string& reason) {
  SqliteTransaction transaction(*db_);
  const std::int64_t id = find_search_id(*db_, sweep);
  db_->prepare("UPDATE search_steps SET objective = ?, reason = ?, committed = 1 WHERE search_id = ? AND step = ?")
      .bind(1, objective)
      .bind(2, objective ? std::optional<std::string>() : std::optional<std::string>(reason))
      .bind(3, id)
      .bind(4, step)
      .execute();
  transaction.commit();
}

std::vector<SearchTrialRecord> ResultsStore::find_search_trials(const std::string& sweep) const {
  const std::int64_t id = find_search_id(*db_, sweep);
  SqliteStatement query = db_->prepare("SELECT trial, bracket, params FROM search_trials WHERE search_id = ? ORDER BY trial");
  query.bind(1, id);
  std::vector<SearchTrialRecord> trials;
  while (query.step()) trials.push_back({query.column_int(0), query.column_int(1), query.column_text(2)});
  return trials;
}

std::vector<SearchStepRecord> ResultsStore::find_search_steps(const std::string& sweep) const {
  const std::int64_t id = find_search_id(*db_, sweep);
  SqliteStatement query = db_->prepare(
      "SELECT st.step, st.trial, st.rung, st.visible, st.kind, st.cost, j.key, st.objective, st.reason, st.committed "
      "FROM search_steps st JOIN jobs j ON j.id = st.job_id WHERE st.search_id = ? ORDER BY st.step");
  query.bind(1, id);
  std::vector<SearchStepRecord> steps;
  while (query.step()) {
    SearchStepRecord s;
    s.step = query.column_int(0);
    s.trial = query.column_int(1);
    s.rung = query.column_int(2);
    s.visible = query.column_int(3);
    s.kind = query.column_text(4);
    s.cost = query.column_double(5);
    s.job_key = query.column_text(6);
    s.objective = query.column_optional_double(7);
    s.reason = query.column_optional_text(8).value_or("");
    s.committed = query.column_int(9) != 0;
    steps.push_back(s);
  }
  return steps;
}

}  // namespace armfarm
