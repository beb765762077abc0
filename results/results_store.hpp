#pragma once
// The results store: one SQLite file holding sweeps, jobs, metrics and recorded series
// (schema in results/README.md). All of armfarm's SQL lives behind this class.
//
// One ResultsStore is one SQLite connection: use it from one thread at a time, open one per
// thread to read in parallel (WAL mode lets readers run while a writer commits). Times are UTC
// ISO-8601 text; durations and simulated times are seconds. Errors throw StoreError whose
// message names the file.
#include "results/job_claims.hpp"
#include "results/search_store.hpp"
#include "results/store_error.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

class SqliteConnection;

/// The schema version this build writes and reads (PRAGMA user_version).
inline constexpr int kResultsSchemaVersion = 9;

/// Where a sweep's results came from: the armfarm build and the machine.
struct Provenance {
  std::string armfarm_version;
  std::string git_commit;
  bool git_dirty = false;
  std::string compiler;
  std::string simbody_version;
  std::string host;
};

/// One row of `sweeps`.
struct SweepRecord {
  std::int64_t id = 0;
  std::string name;
  std::string description;
  std::string spec_text;
  std::string spec_hash;
  std::string started_at;
  std::optional<std::string> finished_at;  ///< empty while running or after an interrupted run
  Provenance provenance;
};

/// One job as seen from a sweep: a row of `jobs` with the sweep's own varying parameters.
struct JobRecord {
  std::int64_t id = 0;
  std::string key;             ///< 32 hex digits, XXH3-128 of the canonical configuration
  std::string sweep;           ///< the sweep that last ran the job
  nlohmann::json params;       ///< varying parameters, {"dotted.path": value, ...}
  nlohmann::json config;       ///< the full resolved job configuration
  std::string status;          ///< pending, running, done, failed, diverged, timeout
  std::string message;         ///< empty when done
  std::int64_t seed = 0;
  std::optional<double> end_time;      ///< simulated time reached, s
  std::optional<double> wall_seconds;  ///< last attempt, s
  std::optional<std::string> started_at;
  std::optional<std::string> finished_at;
  int attempts = 0;
};

/// One row of `metrics`. `job_id` is ignored when writing. A non-finite value is stored as NULL.
struct MetricRecord {
  std::int64_t job_id = 0;
  std::string name;
  std::optional<int> joint;                ///< 1-based joint number; empty for a job-level metric
  std::optional<double> value;             ///< empty = undefined (NULL), see `reason`
  std::string reason{};                    ///< why undefined, or a note on the value; empty = NULL
  std::optional<std::int64_t> checkpoint{};  ///< held-out evaluation checkpoint; empty otherwise (last, so
                                           ///< that {job_id, name, joint, value} still means what it says)
};

/// One row of `metric_info`: what a metric name means (the runner writes its catalog).
struct MetricInfoRecord {
  std::string name;
  std::string unit;       ///< "1" dimensionless, "count", or an SI symbol
  std::string meaning;    ///< one line
  std::string direction;  ///< lower, higher, none
  std::string scope;      ///< job, joint, task_axis, segment, checkpoint
  std::string kind;       ///< result, timing, diagnostic
};

/// One row of `series`, decoded. `job_id` is ignored when writing.
struct SeriesRecord {
  std::int64_t job_id = 0;
  std::string name;
  std::vector<std::string> columns;
  Eigen::MatrixXd rows;  ///< n_samples × columns.size()
};

/// A job of a sweep as the runner registers it before running anything.
struct JobRegistration {
  std::string key;
  nlohmann::json params;
  nlohmann::json config;
  std::int64_t seed = 0;
};

/// A sweep run as the runner registers it.
struct SweepRegistration {
  std::string name;
  std::string description;
  std::string spec_text;
  std::string spec_hash;
  std::string started_at;
  std::optional<std::string> shard;  ///< "I/N" when the run is one shard of the sweep
  Provenance provenance;
  std::vector<MetricInfoRecord> metric_info;  ///< upserted into `metric_info`
};

/// What the store knows of a freshly registered sweep run.
struct RegisteredRun {
  std::int64_t sweep_id = 0;
  std::int64_t run_id = 0;
  std::map<std::string, std::string> status_by_key;  ///< every registered job's current status
};

/// A learned model a job stored (table `models`): the learner's versioned model file.
struct StoredModelRecord {
  std::string kind;  ///< the learner: "lwpr", "ssgpr" (the file's magic says the same)
  std::string hash;  ///< "xxh3-128:<32 hex digits>" of `data`, as job keys write input hashes
  std::string data;  ///< the model file's bytes
};

/// A stored model without its bytes: which job stored it.
struct StoredModelInfo {
  std::string job_key;
  std::string kind;
  std::string hash;
  std::int64_t bytes = 0;
};

/// The result of one attempt of a job, written when it ends.
struct JobResultRecord {
  std::string key;
  std::string status;  ///< done, failed, diverged or timeout
  std::string message;
  double end_time = 0.0;
  double wall_seconds = 0.0;
  std::string started_at;
  std::string finished_at;
  std::vector<MetricRecord> metrics;
  std::vector<SeriesRecord> series;
  std::optional<StoredModelRecord> model;  ///< the job's learned model (learning.store_model); replaces an earlier one
  /// With JobBatch::claim_owner: the fencing token of the claim the attempt ran under
  /// (ClaimAttempt::generation); the result is discarded unless that claim is still current.
  std::int64_t claim_generation = 0;
};

/// Events of a sweep run handed to the store by the writer thread.
struct JobBatch {
  std::vector<std::string> started;
  std::vector<JobResultRecord> finished;
  std::vector<std::string> abandoned;
  /// The claim owner (results/job_claims.hpp) whose claims the finished and abandoned jobs
  /// release; empty when the jobs were not claimed (`started` marks them running instead).
  std::string claim_owner{};
};

/// What `merge_from` did. A conflict is a job key present in both files with a different
/// status, result metrics or series (metrics whose metric_info kind is timing or diagnostic,
/// wall-clock times and provenance are not compared).
struct MergeReport {
  int jobs_added = 0;
  int jobs_identical = 0;
  int jobs_replaced = 0;  ///< not done here, done in the other file: taken from the other file
  std::vector<std::string> conflicts;  ///< one line per conflicting job or sweep
};

class ResultsStore {
 public:
  enum class Mode { read_only, read_write };

  /// Opens (read_write: creating if absent and migrating to kResultsSchemaVersion) the database
  /// at `path`. Throws StoreError for a file that is not SQLite, is corrupt, belongs to another
  /// application or was written by a newer schema.
  static ResultsStore open(const std::string& path, Mode mode);

  ResultsStore(ResultsStore&&) noexcept;
  ResultsStore& operator=(ResultsStore&&) noexcept;
  ~ResultsStore();

  const std::string& path() const { return path_; }
  int schema_version() const;
  /// The result of PRAGMA integrity_check (`quick`: quick_check, which skips the indexes'
  /// agreement with their tables): "ok" for a sound file, otherwise SQLite's findings.
  std::string check_integrity(bool quick = false) const;
  /// Row by row, what armfarm itself would never have written: dangling references
  /// (foreign_key_check), stored JSON that does not parse or is not an object, values of the
  /// wrong storage class, series whose blob does not decode to rows × columns, and (with
  /// `integrity`) SQLite's integrity_check findings. One line per problem ("table.column of
  /// row …: …"), at most `limit` lines; empty for a sound file. Opening already checked the
  /// tables and columns exist.
  std::vector<std::string> check_contents(bool integrity, std::size_t limit = 20) const;
  /// Opens `path` read-only and checks its structure and contents (integrity included); throws
  /// StoreError "<path>: damaged armfarm database: <first problem>" for a file that fails.
  static void verify_file(const std::string& path);

  // ---- reads ----
  std::vector<SweepRecord> find_sweeps() const;
  std::optional<SweepRecord> find_sweep(const std::string& name) const;
  /// The jobs of a sweep in expansion order, `params` as varied in that sweep.
  std::vector<JobRecord> find_jobs(const std::string& sweep) const;
  std::optional<JobRecord> find_job(const std::string& key) const;
  /// Keys of all jobs starting with `prefix` (to accept abbreviated keys on the command line).
  std::vector<std::string> find_job_keys(const std::string& prefix) const;
  std::vector<MetricRecord> find_metrics(std::int64_t job_id) const;
  /// All metrics of the jobs of a sweep, ordered by job position, name, joint.
  std::vector<MetricRecord> find_sweep_metrics(const std::string& sweep) const;
  std::vector<std::string> find_series_names(std::int64_t job_id) const;
  std::optional<SeriesRecord> find_series(std::int64_t job_id, const std::string& name) const;
  /// The `metric_info` rows, by name.
  std::vector<MetricInfoRecord> find_metric_info() const;
  /// The learned model the job stored (results/model_store.cpp), if any.
  std::optional<StoredModelRecord> find_job_model(std::int64_t job_id) const;
  /// The models the jobs of a sweep stored, in expansion order.
  std::vector<StoredModelInfo> find_sweep_models(const std::string& sweep) const;
  /// Number of the sweep's jobs per status ("done" → 12, …).
  std::map<std::string, int> count_jobs_by_status(const std::string& sweep) const;

  // Searches (results/search_store.hpp).
  /// Writes `search` and its rungs for its (existing) sweep, unless the sweep already has one.
  void insert_search(const SearchRecord& search);
  std::optional<SearchRecord> find_search(const std::string& sweep) const;
  /// Appends one step (its job registered already) and, for a new trial, the trial, in one transaction.
  void insert_search_step(const std::string& sweep, const SearchStepRecord& step,
                          const std::optional<SearchTrialRecord>& new_trial);
  /// Marks step `step` committed with the objective it saw (empty: undefined, with `reason`).
  void update_search_objective(const std::string& sweep, std::int64_t step, const std::optional<double>& objective,
                               const std::string& reason);
  std::vector<SearchTrialRecord> find_search_trials(const std::string& sweep) const;
  std::vector<SearchStepRecord> find_search_steps(const std::string& sweep) const;

  // ---- writes (read_write only) ----
  /// Registers a run of a sweep: upserts the sweep row, inserts unknown jobs as pending, makes
  /// `jobs` the sweep's membership (replacing the old one unless `shard` is set, in which case
  /// the membership grows), opens a `runs` row. One transaction.
  RegisteredRun insert_sweep_run(const SweepRegistration& sweep, const std::vector<JobRegistration>& jobs);
  /// Applies a batch of job events in one transaction, in this order: `started` jobs become
  /// `running` (attempts + 1, `jobs.sweep` = sweep_name), `finished` attempts are recorded
  /// (status, message, timings; metrics and series replace earlier ones), `abandoned` jobs
  /// (interrupted by Ctrl-C) go back to `pending`. With a claim owner, a finished result is
  /// written only when its claim (owner and claim_generation) is still the job's current live
  /// claim: the keys of results discarded because another runner took the claim over are
  /// returned (the rest of the batch commits).
  std::vector<std::string> insert_job_batch(const JobBatch& batch, const std::string& sweep_name);
  /// Closes a run: `complete` or `interrupted`; a complete run stamps sweeps.finished_at. A row
  /// already `interrupted` (by another runner that found this one stale) keeps that status.
  /// Regenerates the sweep's `sweep_<name>` view.
  void update_run_finished(std::int64_t run_id, const std::string& status, int jobs_run, int jobs_skipped,
                           const std::string& finished_at);
  /// Writes a consistent copy of this database (WAL contents included) to a new file `path`.
  void copy_to(const std::string& path) const;
  /// Copies the sweeps, jobs, memberships, metrics and series of another database into this one.
  /// A run of the other file already here (same sweep, start time, shard and host) is not added
  /// again, so merging the same file twice adds nothing the second time.
  /// The other file is verified first (verify_file): a damaged input changes nothing here.
  MergeReport merge_from(const std::string& other_path);
  /// Recreates the `sweep_<name>` view of one sweep (columns: its params and metrics).
  void update_sweep_view(const std::string& sweep);
  /// Inserts or replaces `metric_info` rows.
  void upsert_metric_info(const std::vector<MetricInfoRecord>& records);

  // ---- job claims (results/job_claims.hpp; defined in results/job_claims.cpp) ----
  /// One transaction: claims the job `key` for `owner` unless it is done (a done job is claimed
  /// again only when `redo_done_before` is set and it finished before that time: --force) or
  /// another owner's live claim has a heartbeat at most the file's lease old at `now`; a staler
  /// claim is marked interrupted (with its run) and taken over. A claim makes the job `running`
  /// (attempts + 1, jobs.sweep = owner.sweep, started_at = now) under a new fencing token
  /// (ClaimAttempt::generation).
  ClaimAttempt claim_job(const std::string& key, const ClaimOwner& owner, const std::string& now,
                         const std::optional<std::string>& redo_done_before = std::nullopt);
  /// Sets the heartbeat of `owner`'s live claims and of its `runs` row (and the row's owner and
  /// pid) to `now`; returns the keys of the jobs it still holds (a claim another runner took
  /// over is missing).
  std::vector<std::string> refresh_claims(const ClaimOwner& owner, const std::string& now);
  /// Marks every live claim whose heartbeat is older than the file's lease at `now` interrupted
  /// (its job back to pending, its run interrupted), and `running` runs rows with a stale
  /// heartbeat interrupted; `running` jobs without a live claim go back to pending. Claims and
  /// runs of `dead_owners` (owners the caller knows have stopped, e.g. a pid gone on this host)
  /// count as stale whatever their heartbeat's age.
  StaleClaimReport interrupt_stale_claims(const std::string& now, const std::string& by_owner,
                                          const std::vector<std::string>& dead_owners = {});
  /// The lease of the file's claims, s (claim_lease; 60 s when the file is created): a claim
  /// whose heartbeat is older is stale, and runners heartbeat at a sixth of it.
  double find_lease_seconds() const;
  /// Sets the lease (`armfarm lease DB SECONDS`); throws StoreError unless seconds > 0.
  void update_lease_seconds(double seconds, const std::string& now);
  /// Claims (live only, or interrupted ones as well) with their heartbeat ages at `now`.
  std::vector<JobClaimRecord> find_job_claims(const std::string& now, bool live_only = true) const;
  /// The `runs` rows still marked `running`, oldest first, with their heartbeat ages at `now`.
  std::vector<RunningRunRecord> find_running_runs(const std::string& now) const;

 private:
  ResultsStore(std::string path, std::unique_ptr<SqliteConnection> connection);
  std::string path_;
  std::unique_ptr<SqliteConnection> db_;
};

/// The `sweep_<name>` view name of a sweep (also its report page's name): "sweep_" + name with
/// [^A-Za-z0-9_] replaced by '_', plus "_" and 6 hex digits of a hash of the name whenever a
/// character was replaced, so that "a-b" and "a_b" get different names whatever else the file holds.
std::string make_sweep_view_name(const std::string& sweep);

/// The one spelling of a metric value's name, wherever one is shown or written (the
/// `sweep_<name>` view's columns, `armfarm job --json`, table headers, plot labels):
/// "tracking_nmse" for a job-level value, "tracking_nmse_j2" for joint 2 (1-based),
/// "heldout_test_nmse_c200" at checkpoint 200, "heldout_ff_fb_ratio_avg_j2_c200" for both.
std::string make_metric_column_name(const std::string& name, std::optional<int> joint,
                                    std::optional<std::int64_t> checkpoint);

/// Current UTC time as ISO-8601 text with milliseconds ("2024-05-01T12:34:56.789Z").
std::string make_utc_timestamp();

}  // namespace armfarm
