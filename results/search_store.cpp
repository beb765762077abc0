// The search tables (results/search_store.hpp): their migration and ResultsStore's reads and writes.
#include "results/search_store.hpp"

#include "results/results_store.hpp"
#include "results/store_error.hpp"
#include "results/store_internal.hpp"

#include <cstdio>
#include <utility>

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

// NULL in a row migrated from version 6: not recorded (the runner fills it in when it resumes).
const char* const kSettingsMigration = R"sql(
ALTER TABLE searches ADD COLUMN max_trials INTEGER;
ALTER TABLE searches ADD COLUMN bracket_size INTEGER;
ALTER TABLE searches ADD COLUMN tpe_startup INTEGER;
ALTER TABLE searches ADD COLUMN tpe_gamma REAL;
ALTER TABLE searches ADD COLUMN tpe_max_good INTEGER;
ALTER TABLE searches ADD COLUMN tpe_candidates INTEGER;
ALTER TABLE searches ADD COLUMN space TEXT;
)sql";

// NULL in a row migrated from version 7 (or 6): a TPE search of those builds used the per-axis
// rule, and a runner reads NULL so (search_store.hpp, SearchRecord::tpe_rule).
const char* const kTpeRuleMigration = R"sql(
ALTER TABLE searches ADD COLUMN tpe_rule TEXT CHECK (tpe_rule IN ('joint', 'per_axis'));
)sql";

// The joint rule's constants: the prior's weight w, the bandwidth fraction h and the liar's
// bandwidth factor λ (runner/search/tpe_sampler.hpp, TpeSettings), written where TPE proposes
// with the joint rule. NULL in a row migrated from version 8 means the constants of the version-8
// build, w 1, h 0.2, λ 0.7 (kTpeConstantsOfVersion8), which equal those of the build that added
// this migration; a build with other constants refuses to resume or merge such a search.
const char* const kTpeConstantsMigration = R"sql(
ALTER TABLE searches ADD COLUMN tpe_prior_weight REAL CHECK (tpe_prior_weight > 0);
ALTER TABLE searches ADD COLUMN tpe_bandwidth REAL CHECK (tpe_bandwidth > 0);
ALTER TABLE searches ADD COLUMN tpe_liar_bandwidth REAL CHECK (tpe_liar_bandwidth > 0);
)sql";

}  // namespace search_store_sql

TpeJointConstants read_tpe_constants(const SearchRecord& search) {
  return {search.tpe_prior_weight.value_or(kTpeConstantsOfVersion8.prior_weight),
          search.tpe_bandwidth.value_or(kTpeConstantsOfVersion8.bandwidth),
          search.tpe_liar_bandwidth.value_or(kTpeConstantsOfVersion8.liar_bandwidth)};
}

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
  // A row of schema version 6 lacks the decision settings added by version 7: they are filled in.
  SqliteStatement existing = db_->prepare("SELECT id FROM searches WHERE sweep_id = ?");
  existing.bind(1, sweep_id);
  if (existing.step()) {
    const std::int64_t id = existing.column_int(0);
    db_->prepare(
           "UPDATE searches SET max_trials = COALESCE(max_trials, ?1), bracket_size = COALESCE(bracket_size, ?2), "
           "tpe_startup = COALESCE(tpe_startup, ?3), tpe_gamma = COALESCE(tpe_gamma, ?4), "
           "tpe_max_good = COALESCE(tpe_max_good, ?5), tpe_candidates = COALESCE(tpe_candidates, ?6), "
           "space = COALESCE(space, ?7), tpe_rule = COALESCE(tpe_rule, ?9), "
           "tpe_prior_weight = COALESCE(tpe_prior_weight, ?10), tpe_bandwidth = COALESCE(tpe_bandwidth, ?11), "
           "tpe_liar_bandwidth = COALESCE(tpe_liar_bandwidth, ?12) WHERE id = ?8")
        .bind(1, search.max_trials)
        .bind(2, search.bracket_size)
        .bind(3, search.tpe_startup)
        .bind(4, search.tpe_gamma)
        .bind(5, search.tpe_max_good)
        .bind(6, search.tpe_candidates)
        .bind(7, search.space)
        .bind(8, id)
        .bind(9, search.tpe_rule)
        .bind(10, search.tpe_prior_weight)
        .bind(11, search.tpe_bandwidth)
        .bind(12, search.tpe_liar_bandwidth)
        .execute();
    transaction.commit();
    return;
  }
  db_->prepare(
         "INSERT INTO searches (sweep_id, method, sampler, seed, eta, slots, budget_unit, budget, resumable, "
         "objective_metric, objective_direction, objective_joint, objective_checkpoint, max_trials, bracket_size, "
         "tpe_startup, tpe_gamma, tpe_max_good, tpe_candidates, space, tpe_rule, tpe_prior_weight, tpe_bandwidth, "
         "tpe_liar_bandwidth) "
         "VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16, ?17, ?18, ?19, ?20, ?21, ?22, ?23, "
         "?24)")
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
      .bind(14, search.max_trials)
      .bind(15, search.bracket_size)
      .bind(16, search.tpe_startup)
      .bind(17, search.tpe_gamma)
      .bind(18, search.tpe_max_good)
      .bind(19, search.tpe_candidates)
      .bind(20, search.space)
      .bind(21, search.tpe_rule)
      .bind(22, search.tpe_prior_weight)
      .bind(23, search.tpe_bandwidth)
      .bind(24, search.tpe_liar_bandwidth)
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
      "se.objective_metric, se.objective_direction, se.objective_joint, se.objective_checkpoint, se.max_trials, "
      "se.bracket_size, se.tpe_startup, se.tpe_gamma, se.tpe_max_good, se.tpe_candidates, se.space, se.tpe_rule, "
      "se.tpe_prior_weight, se.tpe_bandwidth, se.tpe_liar_bandwidth "
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
  if (!query.is_null(13)) r.max_trials = query.column_int(13);
  if (!query.is_null(14)) r.bracket_size = query.column_int(14);
  if (!query.is_null(15)) r.tpe_startup = query.column_int(15);
  r.tpe_gamma = query.column_optional_double(16);
  if (!query.is_null(17)) r.tpe_max_good = query.column_int(17);
  if (!query.is_null(18)) r.tpe_candidates = query.column_int(18);
  r.space = query.column_optional_text(19);
  r.tpe_rule = query.column_optional_text(20);
  r.tpe_prior_weight = query.column_optional_double(21);
  r.tpe_bandwidth = query.column_optional_double(22);
  r.tpe_liar_bandwidth = query.column_optional_double(23);
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
  SqliteStatement job = db_->prepare("SELECT id FROM jobs WHERE key = ?");
  job.bind(1, step.job_key);
  if (!job.step()) throw StoreError(path_ + ": search step " + std::to_string(step.step) + " names no job '" + step.job_key + "'");
  const std::int64_t job_id = job.column_int(0);
  // Several runners on one file record the same steps: a step written already is left as it is
  // when it agrees (the same decision, taken by the other runner), refused when it does not.
  SqliteStatement existing = db_->prepare(
      "SELECT st.trial, st.rung, st.visible, st.kind, st.job_id, t.params FROM search_steps st "
      "LEFT JOIN search_trials t ON t.search_id = st.search_id AND t.trial = st.trial WHERE st.search_id = ? AND st.step = ?");
  existing.bind(1, id).bind(2, step.step);
  if (existing.step()) {
    const bool same = existing.column_int(0) == step.trial && existing.column_int(1) == step.rung &&
                      existing.column_int(2) == step.visible && existing.column_text(3) == step.kind &&
                      existing.column_int(4) == job_id && (!new_trial || existing.column_text(5) == new_trial->params);
    if (!same) {
      throw StoreError(path_ + ": search step " + std::to_string(step.step) + " of sweep '" + sweep +
                       "' is recorded with another decision (trial " + std::to_string(existing.column_int(0)) + ", rung " +
                       std::to_string(existing.column_int(1)) + ") than this runner took (trial " + std::to_string(step.trial) +
                       ", rung " + std::to_string(step.rung) + "): the file holds another search under this name");
    }
    return;  // the transaction rolls back: nothing was written
  }
  if (new_trial) {
    db_->prepare("INSERT INTO search_trials (search_id, trial, bracket, params) VALUES (?, ?, ?, ?)")
        .bind(1, id)
        .bind(2, new_trial->trial)
        .bind(3, new_trial->bracket)
        .bind(4, new_trial->params)
        .execute();
  }
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

namespace {

// The columns of `searches` a merge compares and copies (all but id and sweep_id).
constexpr const char* kSearchSettingColumns =
    "method, sampler, seed, eta, slots, budget_unit, budget, resumable, objective_metric, objective_direction, "
    "objective_joint, objective_checkpoint, max_trials, bracket_size, tpe_startup, tpe_gamma, tpe_max_good, "
    "tpe_candidates, space, tpe_rule, tpe_prior_weight, tpe_bandwidth, tpe_liar_bandwidth";
// The columns of version 7: NULL in a row migrated from version 6 (not recorded), so a NULL agrees
// with any value and is filled in from the other file.
constexpr const char* kSearchDecisionColumns[] = {"max_trials",   "bracket_size",   "tpe_startup", "tpe_gamma",
                                                  "tpe_max_good", "tpe_candidates", "space"};

// The joint rule's constants (version 9) in merge_search_tables's comparison of two rows m and o
// and its fill-in: where the rule is joint (the rules agree already), each constant read as the
// version-8 build's where NULL (kTpeConstantsOfVersion8) must be the same in both files.
void add_tpe_constants_terms(std::string& agree, std::string& fill) {
  const std::pair<const char*, double> constants[] = {{"tpe_prior_weight", kTpeConstantsOfVersion8.prior_weight},
                                                      {"tpe_bandwidth", kTpeConstantsOfVersion8.bandwidth},
                                                      {"tpe_liar_bandwidth", kTpeConstantsOfVersion8.liar_bandwidth}};
  std::string same;
  for (const auto& [column, version8] : constants) {
    const std::string c = column;
    char value[32];
    std::snprintf(value, sizeof value, "%.17g", version8);
    same += std::string(same.empty() ? "" : " AND ") + "COALESCE(m." + c + ", " + value + ") IS COALESCE(o." + c + ", " + value + ")";
    fill += ", " + c + " = COALESCE(" + c + ", (SELECT " + c + " FROM src.searches WHERE id = ?2))";
  }
  agree += " AND ((m.method <> 'tpe' AND m.sampler <> 'tpe') OR COALESCE(m.tpe_rule, 'per_axis') <> 'joint' OR (" + same + "))";
}

// The rungs (search_rungs) in merge_search_tables's comparison of two rows m and o: the same
// rungs with the same checkpoints and costs. A rung's cost is the build's estimate times its
// cost factor (runner/execution/search_runner.hpp), and the budget's decisions follow it, so two
// files whose runners had other factors or cost models hold different searches under one name.
void add_rung_terms(std::string& agree) {
  agree += " AND (SELECT count(*) FROM main.search_rungs WHERE search_id = m.id) = "
           "(SELECT count(*) FROM src.search_rungs WHERE search_id = o.id) AND NOT EXISTS (SELECT 1 FROM main.search_rungs mr "
           "LEFT JOIN src.search_rungs orr ON orr.search_id = o.id AND orr.rung = mr.rung WHERE mr.search_id = m.id AND "
           "(orr.rung IS NULL OR orr.checkpoint IS NOT mr.checkpoint OR orr.cost IS NOT mr.cost))";
}

// The part of one search that both files hold, merged; returns the conflict, empty when none.
std::string merge_one_search(SqliteConnection& db, std::int64_t src_id, std::int64_t main_id,
                             const std::map<std::int64_t, std::int64_t>& job_ids) {
  // Trials: by number; a trial both files have must have the same point and bracket.
  SqliteStatement trials = db.prepare("SELECT trial, bracket, params FROM src.search_trials WHERE search_id = ? ORDER BY trial");
  trials.bind(1, src_id);
  SqliteStatement mine_trial = db.prepare("SELECT bracket, params FROM main.search_trials WHERE search_id = ? AND trial = ?");
  SqliteStatement insert_trial = db.prepare("INSERT INTO main.search_trials (search_id, trial, bracket, params) VALUES (?, ?, ?, ?)");
  while (trials.step()) {
    const std::int64_t trial = trials.column_int(0);
    mine_trial.bind(1, main_id).bind(2, trial);
    if (mine_trial.step()) {
      const bool same = mine_trial.column_int(0) == trials.column_int(1) && mine_trial.column_text(1) == trials.column_text(2);
      mine_trial.reset();
      if (!same) return "trial " + std::to_string(trial) + " has a different point";
      continue;
    }
    mine_trial.reset();
    insert_trial.bind(1, main_id).bind(2, trial).bind(3, trials.column_int(1)).bind(4, trials.column_text(2)).execute();
  }
  // Steps: the same trial, rung and job where both have them; the missing ones appended.
  SqliteStatement steps = db.prepare(
      "SELECT step, trial, rung, visible, kind, cost, job_id, objective, reason, committed FROM src.search_steps "
      "WHERE search_id = ? ORDER BY step");
  steps.bind(1, src_id);
  SqliteStatement mine_step =
      db.prepare("SELECT trial, rung, job_id, committed FROM main.search_steps WHERE search_id = ? AND step = ?");
  while (steps.step()) {
    const std::int64_t step = steps.column_int(0);
    const std::int64_t job_id = job_ids.at(steps.column_int(6));
    const bool src_committed = steps.column_int(9) != 0;
    mine_step.bind(1, main_id).bind(2, step);
    if (mine_step.step()) {
      const bool same = mine_step.column_int(0) == steps.column_int(1) && mine_step.column_int(1) == steps.column_int(2) &&
                        mine_step.column_int(2) == job_id;
      const bool main_committed = mine_step.column_int(3) != 0;
      mine_step.reset();
      if (!same) return "step " + std::to_string(step) + " runs a different trial, rung or job";
      if (src_committed && !main_committed) {
        db.prepare("UPDATE main.search_steps SET objective = ?, reason = ?, committed = 1 WHERE search_id = ? AND step = ?")
            .bind(1, steps.column_optional_double(7))
            .bind(2, steps.column_optional_text(8))
            .bind(3, main_id)
            .bind(4, step)
            .execute();
      }
      continue;
    }
    mine_step.reset();
    db.prepare(
          "INSERT INTO main.search_steps (search_id, step, trial, rung, visible, kind, cost, job_id, objective, reason, "
          "committed) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)")
        .bind(1, main_id)
        .bind(2, step)
        .bind(3, steps.column_int(1))
        .bind(4, steps.column_int(2))
        .bind(5, steps.column_int(3))
        .bind(6, steps.column_text(4))
        .bind(7, steps.column_double(5))
        .bind(8, job_id)
        .bind(9, steps.column_optional_double(7))
        .bind(10, steps.column_optional_text(8))
        .bind(11, static_cast<std::int64_t>(src_committed))
        .execute();
  }
  return "";
}

}  // namespace

void merge_search_tables(SqliteConnection& db, const std::map<std::int64_t, std::int64_t>& sweep_ids,
                         const std::map<std::int64_t, std::int64_t>& job_ids, const std::string& other_path,
                         MergeReport& report) {
  SqliteStatement searches = db.prepare(
      "SELECT se.id, se.sweep_id, s.name FROM src.searches se JOIN src.sweeps s ON s.id = se.sweep_id ORDER BY se.id");
  while (searches.step()) {
    const std::int64_t src_id = searches.column_int(0);
    const std::int64_t sweep_id = sweep_ids.at(searches.column_int(1));
    const std::string sweep = searches.column_text(2);
    SqliteStatement mine = db.prepare("SELECT id FROM main.searches WHERE sweep_id = ?");
    mine.bind(1, sweep_id);
    std::int64_t main_id = 0;
    if (mine.step()) {
      main_id = mine.column_int(0);
      // The same settings, compared column by column with IS (NULL objective joint or checkpoint).
      std::string agree, fill;
      for (const char* column : kSearchDecisionColumns) {
        const std::string c = column;
        agree += " AND (m." + c + " IS o." + c + " OR m." + c + " IS NULL OR o." + c + " IS NULL)";
        fill += std::string(fill.empty() ? "" : ", ") + c + " = COALESCE(" + c + ", (SELECT " + c + " FROM src.searches WHERE id = ?2))";
      }
      // TPE's rule (version 8): NULL is the per-axis rule, so it is compared as that (a NULL
      // agreeing with "joint" would merge steps of two rules), and only where TPE proposes.
      agree += " AND ((m.method <> 'tpe' AND m.sampler <> 'tpe') OR COALESCE(m.tpe_rule, 'per_axis') IS COALESCE(o.tpe_rule, 'per_axis'))";
      fill += ", tpe_rule = COALESCE(tpe_rule, (SELECT tpe_rule FROM src.searches WHERE id = ?2))";
      add_tpe_constants_terms(agree, fill);
      add_rung_terms(agree);
      SqliteStatement same = db.prepare(
          "SELECT count(*) FROM main.searches m, src.searches o WHERE m.id = ?1 AND o.id = ?2 AND "
          "m.method IS o.method AND m.sampler IS o.sampler AND m.seed IS o.seed AND m.eta IS o.eta AND "
          "m.slots IS o.slots AND m.budget_unit IS o.budget_unit AND m.budget IS o.budget AND "
          "m.resumable IS o.resumable AND m.objective_metric IS o.objective_metric AND "
          "m.objective_direction IS o.objective_direction AND m.objective_joint IS o.objective_joint AND "
          "m.objective_checkpoint IS o.objective_checkpoint" + agree);
      same.bind(1, main_id).bind(2, src_id);
      if (!same.step() || same.column_int(0) != 1) {
        report.conflicts.push_back("search " + sweep + ": different settings in " + other_path + "; kept this file's");
        continue;
      }
      db.prepare("UPDATE main.searches SET " + fill + " WHERE id = ?1").bind(1, main_id).bind(2, src_id).execute();
    } else {
      db.prepare(std::string("INSERT INTO main.searches (sweep_id, ") + kSearchSettingColumns + ") SELECT ?, " +
                 kSearchSettingColumns + " FROM src.searches WHERE id = ?")
          .bind(1, sweep_id)
          .bind(2, src_id)
          .execute();
      main_id = db.last_insert_rowid();
      db.prepare("INSERT INTO main.search_rungs (search_id, rung, checkpoint, cost) SELECT ?, rung, checkpoint, cost "
                 "FROM src.search_rungs WHERE search_id = ?")
          .bind(1, main_id)
          .bind(2, src_id)
          .execute();
    }
    // A savepoint: a conflict found part way takes back the trials and objectives added before it.
    db.execute("SAVEPOINT merge_search");
    const std::string conflict = merge_one_search(db, src_id, main_id, job_ids);
    if (!conflict.empty()) {
      db.execute("ROLLBACK TO merge_search");
      report.conflicts.push_back("search " + sweep + ": " + conflict + " in " + other_path + "; kept this file's");
    }
    db.execute("RELEASE merge_search");
  }
}

}  // namespace armfarm
