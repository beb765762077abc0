#pragma once
// A search's record in the store (results/README.md, "Searches"): its settings and objective
// (`searches`), its rungs (`search_rungs`), its trials (`search_trials`) and its steps — new
// trials and promotions, each one job with a normal key (`search_steps`; the view
// `search_promotions` lists the promotions). A resumed search reads them back and replays its
// decisions (runner/search/search_sequence.hpp); the objective value each step saw is stored
// with it so the replay needs no metric lookups, and `table`, `plot search` and `status` read
// the same rows. Costs are estimated CPU-seconds (or 1 per job for a budget in jobs).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

struct SearchRungRecord {
  std::int64_t rung = 0;
  std::optional<std::int64_t> checkpoint;  ///< the learning checkpoint it stops at; empty: the whole job
  double cost = 0.0;                       ///< estimated cost of a job from scratch to this rung
};

struct SearchRecord {
  std::string sweep;
  std::string method;   ///< random, tpe, asha, successive_halving, hyperband
  std::string sampler;  ///< random, tpe
  std::int64_t seed = 0;
  std::int64_t eta = 3;
  std::int64_t slots = 1;
  std::string budget_unit;  ///< jobs, cpu_seconds
  double budget = 0.0;
  bool resumable = true;    ///< promotions continue from the stored model (false: they rerun, costing the whole rung)
  std::string objective_metric;
  std::string objective_direction;  ///< lower, higher
  std::optional<std::int64_t> objective_joint;       ///< empty: the mean over the joints
  std::optional<std::int64_t> objective_checkpoint;  ///< empty: a metric without checkpoints
  std::vector<SearchRungRecord> rungs;
  // What else a decision depends on (schema version 7; empty: a search recorded by schema 6,
  // filled in by the next runner that writes it). A resumed search or a second runner compares
  // the spec's and adopts the build's (runner/execution/search_runner.hpp).
  std::optional<std::int64_t> max_trials;      ///< 0: no limit but the budget
  std::optional<std::int64_t> bracket_size;    ///< 0: η^(rungs − 1)
  std::optional<std::int64_t> tpe_startup;     ///< the effective start-up: the spec's, or the budget rule's
  std::optional<double> tpe_gamma;             ///< TPE's good fraction γ
  std::optional<std::int64_t> tpe_max_good;    ///< TPE's cap on the good group
  std::optional<std::int64_t> tpe_candidates;  ///< TPE's draws scored per proposal
  std::optional<std::string> space;            ///< the axes as JSON, in the order that fixes the draws
  // Schema version 8: TPE's estimator rule, "joint" or "per_axis" (runner/search/tpe_sampler.hpp),
  // written only where TPE proposes (method tpe, or sampler tpe). NULL in a TPE search's row means "per_axis": every build
  // before version 8 proposed with the per-axis rule. A resumed search adopts it.
  std::optional<std::string> tpe_rule;
  // Schema version 9: the joint rule's constants (TpeSettings::prior_weight, bandwidth,
  // liar_bandwidth), written only where TPE proposes with the joint rule. NULL in such a row (one
  // migrated from version 8) means the constants of the version-8 build, kTpeConstantsOfVersion8.
  // A resumed search or a merge whose constants differ is refused.
  std::optional<double> tpe_prior_weight;    ///< w, the prior's weight beside a group's points
  std::optional<double> tpe_bandwidth;       ///< h, a lone point's bandwidth as a fraction of its axis
  std::optional<double> tpe_liar_bandwidth;  ///< λ, a liar's bandwidth as a fraction of ℓ's
};

/// The joint rule's constants as one value (SearchRecord's tpe_prior_weight, tpe_bandwidth,
/// tpe_liar_bandwidth).
struct TpeJointConstants {
  double prior_weight = 0.0;
  double bandwidth = 0.0;
  double liar_bandwidth = 0.0;
};

/// The constants every build of schema version 8 proposed with under the joint rule (w 1, h 0.2,
/// λ 0.7): what a NULL in a joint search's row of version 8 means.
inline constexpr TpeJointConstants kTpeConstantsOfVersion8{1.0, 0.2, 0.7};

/// A joint search's recorded constants, a NULL read as kTpeConstantsOfVersion8.
TpeJointConstants read_tpe_constants(const SearchRecord& search);

struct SearchTrialRecord {
  std::int64_t trial = 0;
  std::int64_t bracket = 0;
  std::string params;  ///< JSON object of the axes' values {"dotted.path": value}
};

struct SearchStepRecord {
  std::int64_t step = 0;
  std::int64_t trial = 0;
  std::int64_t rung = 0;
  std::int64_t visible = 0;  ///< the steps whose objectives the decision saw
  std::string kind;          ///< new, promotion
  double cost = 0.0;
  std::string job_key;
  std::optional<double> objective;  ///< the value seen (signed as the metric, not as a loss); empty until committed or undefined
  std::string reason;               ///< why `objective` is empty once the job ended (failed, diverged, NULL metric)
  bool committed = false;           ///< the job ended and its objective (or reason) is stored
};

class SqliteConnection;
struct MergeReport;

/// ResultsStore::merge_from's part for the search tables, inside its transaction, with the other
/// file attached as `src`: a search this file lacks is copied whole (its rungs, trials and steps,
/// their jobs mapped by `job_ids`, src id → main id; its sweep by `sweep_ids`); a search both
/// files have must agree on its settings and on every step both hold (the steps are a function
/// of the spec and the committed results, so one file's steps are a prefix of the other's): the
/// missing trials and steps are added and a step committed only in the other file takes its
/// objective. A disagreement adds one line to `report.conflicts` and leaves this file's search as it was.
void merge_search_tables(SqliteConnection& db, const std::map<std::int64_t, std::int64_t>& sweep_ids,
                         const std::map<std::int64_t, std::int64_t>& job_ids, const std::string& other_path,
                         MergeReport& report);

namespace search_store_sql {
/// The migration step that adds the search tables (appended to the store's migration list).
extern const char* const kMigration;
/// The migration step that adds the decision settings to `searches` (schema version 7).
extern const char* const kSettingsMigration;
/// The migration step that adds TPE's estimator rule to `searches` (schema version 8).
extern const char* const kTpeRuleMigration;
/// The migration step that adds the joint rule's constants to `searches` (schema version 9).
extern const char* const kTpeConstantsMigration;
}  // namespace search_store_sql

}  // namespace armfarm
