#include "runner/execution/sweep_runner.hpp"

#include "runner/execution/outcome_record.hpp"
#include "runner/execution/result_writer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <mutex>
#include <thread>

namespace armfarm {
namespace {

std::string make_param_text(const nlohmann::json& value) {
  if (value.is_number_float()) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value.get<double>());
    return text;
  }
  return value.is_string() ? value.get<std::string>() : value.dump();
}

}  // namespace

std::string make_job_label(const ExpandedJob& job) {
  std::string label = job.key.substr(0, 8);
  for (const auto& [path, value] : job.params.items()) label += " " + path + "=" + make_param_text(value);
  return label;
}

namespace {

using Clock = std::chrono::steady_clock;

double calc_seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// The jobs of the sweep dealt to this shard (by estimated cost), in expansion order.
std::vector<const ExpandedJob*> select_shard_jobs(const ExpandedSweep& sweep, const RunOptions& options) {
  std::vector<std::string> keys;
  for (const ExpandedJob& job : sweep.jobs) keys.push_back(job.key);
  const std::vector<int> shard_of = calc_shard_assignment(keys, options.job_costs, options.shard.count);
  std::vector<const ExpandedJob*> shard_jobs;
  for (std::size_t i = 0; i < sweep.jobs.size(); ++i) {
    if (shard_of[i] == options.shard.index) shard_jobs.push_back(&sweep.jobs[i]);
  }
  return shard_jobs;
}

SweepRegistration make_sweep_registration(const ExpandedSweep& sweep, const RunOptions& options) {
  SweepRegistration registration;
  registration.name = sweep.spec.name;
  registration.description = sweep.spec.description;
  registration.spec_text = sweep.spec.text;
  registration.spec_hash = sweep.spec_hash;
  registration.started_at = make_utc_timestamp();
  if (options.shard.count > 1) {
    registration.shard = std::to_string(options.shard.index) + "/" + std::to_string(options.shard.count);
  }
  registration.provenance = options.provenance;
  registration.metric_info = make_metric_info_records();
  return registration;
}

/// Registers the sweep's run and the shard's jobs in the store.
RegisteredRun register_shard(ResultsStore& store, const SweepRegistration& registration,
                             const std::vector<const ExpandedJob*>& shard_jobs) {
  std::vector<JobRegistration> jobs;
  for (const ExpandedJob* job : shard_jobs) jobs.push_back({job->key, job->params, job->config(), job->seed});
  return store.insert_sweep_run(registration, jobs);
}

/// The shard's jobs to run: not done (all with `force`), and unless `rerun_unsuccessful` not
/// failed, diverged or timed out either; the others are counted in `skipped`.
std::vector<const ExpandedJob*> select_jobs_to_run(const std::vector<const ExpandedJob*>& shard_jobs,
                                                   const RegisteredRun& registered, const RunOptions& options,
                                                   int& skipped) {
  std::vector<const ExpandedJob*> to_run;
  for (const ExpandedJob* job : shard_jobs) {
    const std::string& status = registered.status_by_key.at(job->key);
    const bool unsuccessful = status == "failed" || status == "diverged" || status == "timeout";
    if (options.force || (status != "done" && (options.rerun_unsuccessful || !unsuccessful))) {
      to_run.push_back(job);
    } else {
      ++skipped;
    }
  }
  return to_run;
}

int choose_thread_count(const RunOptions& options) {
  return options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// The progress lines' jobs: label, short key and estimated cost (1 when unknown).
std::vector<ProgressJob> make_progress_jobs(const ExpandedSweep& sweep, const std::vector<const ExpandedJob*>& to_run,
                                            const RunOptions& options) {
  std::vector<ProgressJob> progress_jobs;
  for (const ExpandedJob* job : to_run) {
    const auto index = static_cast<std::size_t>(job - sweep.jobs.data());
    const double cost = index < options.job_costs.size() ? options.job_costs[index] : 1.0;
    progress_jobs.push_back({make_job_label(*job), job->key.substr(0, 8), cost > 0.0 ? cost : 1.0});
  }
  return progress_jobs;
}

/// Runs the executor on one configuration; an exception is the job's failure.
JobOutcome run_executor(const JobExecutor& executor, const ExpandedJob& job, const JobControl& control) {
  try {
    return executor(job.config(), job.checked.get(), control);
  } catch (const std::exception& e) {
    JobOutcome outcome;
    outcome.status = JobStatus::failed;
    outcome.message = std::string("exception: ") + e.what();
    return outcome;
  } catch (...) {
    JobOutcome outcome;
    outcome.status = JobStatus::failed;
    outcome.message = "unknown exception";
    return outcome;
  }
}

/// A finished job as the writer thread counts it once its result is committed (or fenced out).
struct CommittedJob {
  std::size_t index = 0;  ///< into the jobs to run
  std::string status;
  double wall = 0.0;
  bool ran_on = false;  ///< finished in the stop grace
  std::string key;
  std::string message;
  HeadlineJob headline;
};

/// The running of one shard's jobs in rounds on a task arena, their results committed through
/// one writer thread. Counts go to `summary`, the done jobs' headline metrics to `headline_jobs`,
/// the keys of results fenced out to `discarded_keys`, under one mutex (job threads and the writer's).
class ShardRun {
 public:
  ShardRun(const ExpandedSweep& sweep, const JobExecutor& executor, const RunOptions& options,
           const std::atomic<bool>& stop_requested, const std::vector<const ExpandedJob*>& to_run, ResultsStore& store,
           ClaimKeeper& claims, ProgressReporter& progress, RunSummary& summary, std::vector<HeadlineJob>& headline_jobs,
           std::vector<std::string>& discarded_keys)
      : sweep_(sweep), executor_(executor), options_(options), stop_requested_(stop_requested), to_run_(to_run),
        claims_(claims), progress_(progress), summary_(summary), headline_jobs_(headline_jobs),
        discarded_keys_(discarded_keys), writer_(store, sweep.spec.name, claims.owner().owner) {}

  /// Rounds: every job is claimed and run, or found done, or held by another live runner; those
  /// are looked at again after a poll interval until done elsewhere or their claim goes stale.
  void run_rounds(int threads);
  /// Waits for the writer; sets the summary's write figures (rethrows a heartbeat's failure).
  void finish();

 private:
  /// Watches one running job for the executor (JobControl::should_stop) and records why it stopped.
  struct JobWatch {
    JobWatch(ShardRun& owner, const ExpandedJob& watched, std::size_t index_in_sweep)
        : run(owner), job(watched), sweep_index(index_in_sweep) {}

    ShardRun& run;
    const ExpandedJob& job;
    std::size_t sweep_index;
    Clock::time_point start = Clock::now();
    bool stopped_by_request = false;
    bool stopped_by_timeout = false;
    bool claim_lost = false;
    std::optional<bool> runs_on;  // decided at the first look after the stop request: expected to end within the grace

    bool should_stop();
    bool in_grace();
  };

  bool is_stopping() const {
    return stop_requested_.load() || writer_.failed() || claims_.failed() || claim_failed();
  }
  bool claim_failed() const {
    std::lock_guard lock(summary_mutex_);
    return !claim_error_.empty();
  }
  void count_abandoned() {
    std::lock_guard lock(summary_mutex_);
    ++summary_.abandoned;
  }
  /// When the stop request was first seen (the first caller sets it): the stop grace runs from it.
  Clock::time_point find_stop_seen(Clock::time_point now) {
    Clock::rep expected = kNone;
    stop_seen_.compare_exchange_strong(expected, now.time_since_epoch().count());
    return Clock::time_point(Clock::duration(stop_seen_.load()));
  }

  void run_one(std::size_t index);
  /// Claims the job; false (counted) when it is done elsewhere, held elsewhere or the claim failed.
  bool claim_job(std::size_t index, const ExpandedJob& job);
  /// A job stopped by a lost claim or a stop request without finishing goes back: true then.
  bool drop_stopped(std::size_t index, const ExpandedJob& job, const JobWatch& watch, const JobOutcome& outcome);
  void commit(std::size_t index, const ExpandedJob& job, JobOutcome outcome, const JobWatch& watch, double wall,
              const std::string& started_at, std::int64_t generation);
  void count_committed(CommittedJob& job, bool written);

  static constexpr Clock::rep kNone = std::numeric_limits<Clock::rep>::min();

  const ExpandedSweep& sweep_;
  const JobExecutor& executor_;
  const RunOptions& options_;
  const std::atomic<bool>& stop_requested_;
  const std::vector<const ExpandedJob*>& to_run_;
  ClaimKeeper& claims_;
  ProgressReporter& progress_;
  RunSummary& summary_;  // guarded by summary_mutex_ while jobs run
  std::vector<HeadlineJob>& headline_jobs_;  // guarded by summary_mutex_
  std::vector<std::string>& discarded_keys_;  // guarded by summary_mutex_
  mutable std::mutex summary_mutex_;
  std::vector<std::size_t> elsewhere_;  // indices into to_run held by another live runner (guarded by summary_mutex_)
  std::string claim_error_;  // the first claim that could not be written (guarded by summary_mutex_)
  std::atomic<Clock::rep> stop_seen_{kNone};
  ResultWriter writer_;  // last: its thread (which counts into the above) ends first
};

bool ShardRun::JobWatch::in_grace() {
  // Whether the stop grace lets this job run on now (stop_grace_seconds).
  const RunOptions& options = run.options_;
  if (!options.stop_grace_seconds || (options.stop_at_once != nullptr && options.stop_at_once->load())) return false;
  const auto now = Clock::now();
  const auto seen = run.find_stop_seen(now);
  const double grace = *options.stop_grace_seconds;
  if (std::chrono::duration<double>(now - seen).count() >= grace) return false;
  if (!runs_on) {
    const double ran = std::max(0.0, std::chrono::duration<double>(seen - start).count());
    runs_on = sweep_index < options.job_seconds.size() && options.job_seconds[sweep_index] - ran <= grace;
  }
  return *runs_on;
}

bool ShardRun::JobWatch::should_stop() {
  if (run.claims_.lost(job.key)) {
    claim_lost = true;
    return true;
  }
  if (run.writer_.failed() || run.claims_.failed() || (run.stop_requested_.load() && !in_grace())) {
    stopped_by_request = true;
    return true;
  }
  if (run.options_.timeout_seconds && calc_seconds_since(start) > *run.options_.timeout_seconds) {
    stopped_by_timeout = true;
    return true;
  }
  return false;
}

void ShardRun::run_rounds(int threads) {
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  tbb::task_arena arena(threads);
  std::vector<std::size_t> round(to_run_.size());
  for (std::size_t i = 0; i < round.size(); ++i) round[i] = i;
  while (!round.empty()) {
    arena.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, round.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) run_one(round[i]);
          },
          tbb::simple_partitioner());
    });
    round.swap(elsewhere_);
    elsewhere_.clear();
    std::sort(round.begin(), round.end());  // expansion order
    if (round.empty()) break;
    if (is_stopping()) {
      summary_.abandoned += static_cast<int>(round.size());
      break;
    }
    claims_.wait_poll(stop_requested_);
  }
}

void ShardRun::finish() {
  try {
    writer_.finish();
  } catch (const std::exception&) {
    // Reported through the summary: the caller says how many finished jobs were lost.
  }
  progress_.finish();
  summary_.not_saved = writer_.finished_not_saved();
  summary_.write_error = writer_.error_text();
  if (summary_.write_error.empty() && !claim_error_.empty()) summary_.write_error = claim_error_;
  if (summary_.write_error.empty()) claims_.rethrow_error();
}

void ShardRun::run_one(std::size_t index) {
  const ExpandedJob& job = *to_run_[index];
  if (is_stopping()) {
    count_abandoned();
    return;
  }
  if (!claim_job(index, job)) return;
  progress_.job_started(index);
  const std::string started_at = make_utc_timestamp();
  JobWatch watch(*this, job, static_cast<std::size_t>(&job - sweep_.jobs.data()));
  JobControl control;
  control.should_stop = [&watch] { return watch.should_stop(); };
  JobOutcome outcome = run_executor(executor_, job, control);
  const double wall = calc_seconds_since(watch.start);
  const std::int64_t generation = claims_.generation(job.key);
  claims_.forget(job.key);  // before the writer releases the claim
  if (drop_stopped(index, job, watch, outcome)) return;
  if (watch.stopped_by_timeout && outcome.status != JobStatus::done) {
    outcome.status = JobStatus::timeout;
    char text[96];
    std::snprintf(text, sizeof text, "stopped after the timeout of %g s", *options_.timeout_seconds);
    outcome.message = text;
  }
  commit(index, job, std::move(outcome), watch, wall, started_at, generation);
}

bool ShardRun::claim_job(std::size_t index, const ExpandedJob& job) {
  ClaimAttempt claim;
  try {
    claim = claims_.claim(job.key);
  } catch (const StoreError& e) {
    // A claim that cannot be written (a full disk) stops the run like a failed commit.
    std::lock_guard lock(summary_mutex_);
    if (claim_error_.empty()) claim_error_ = e.what();
    ++summary_.abandoned;
    return false;
  }
  if (claim.result == ClaimResult::claimed) return true;
  std::lock_guard lock(summary_mutex_);
  if (claim.result == ClaimResult::done) ++summary_.done_elsewhere;
  if (claim.result == ClaimResult::claimed_elsewhere) elsewhere_.push_back(index);
  return false;
}

bool ShardRun::drop_stopped(std::size_t index, const ExpandedJob& job, const JobWatch& watch, const JobOutcome& outcome) {
  if (watch.claim_lost && outcome.status != JobStatus::done) {
    writer_.push_abandoned(job.key);  // another runner took it over: wait for its result
    progress_.job_dropped(index);
    std::lock_guard lock(summary_mutex_);
    elsewhere_.push_back(index);
    return true;
  }
  if (watch.stopped_by_request && outcome.status != JobStatus::done) {
    writer_.push_abandoned(job.key);
    progress_.job_dropped(index);
    count_abandoned();
    return true;
  }
  return false;
}

void ShardRun::commit(std::size_t index, const ExpandedJob& job, JobOutcome outcome, const JobWatch& watch,
                      double wall, const std::string& started_at, std::int64_t generation) {
  CommittedJob committed{index, to_string(outcome.status), wall, watch.runs_on.value_or(false), job.key,
                         outcome.message, HeadlineJob{make_job_label(job), {}}};
  for (const Metric& metric : outcome.metrics) {
    if (!metric.joint && !metric.checkpoint && metric.value) committed.headline.metrics[metric.name] = *metric.value;
  }
  JobResultRecord record = make_job_result_record(job.key, std::move(outcome), wall, started_at, make_utc_timestamp());
  record.claim_generation = generation;
  // Counted and reported on the writer thread, once the result is committed.
  writer_.push_finished(std::move(record), [this, committed = std::move(committed)](bool written) mutable {
    count_committed(committed, written);
  });
}

void ShardRun::count_committed(CommittedJob& job, bool written) {
  if (!written) {  // fenced out: the claim was taken over while this attempt ran
    progress_.job_dropped(job.index);
    std::lock_guard lock(summary_mutex_);
    ++summary_.discarded;
    discarded_keys_.push_back(job.key);
    return;
  }
  progress_.job_committed(job.index, job.status, job.wall, job.message);
  std::lock_guard lock(summary_mutex_);
  ++summary_.run;
  if (job.ran_on) ++summary_.finished_in_grace;
  if (job.status == "done") {
    ++summary_.done;
    headline_jobs_.push_back(std::move(job.headline));
  } else {
    if (job.status == "failed") ++summary_.failed;
    if (job.status == "diverged") ++summary_.diverged;
    if (job.status == "timeout") ++summary_.timeout;
    summary_.failures.push_back(job.headline.label + ": " + job.status + ": " + job.message);
  }
}

/// A discarded result is the job of the runner that took its claim over: done there, or not yet.
int count_discarded_not_done(const ResultsStore& store, const std::vector<std::string>& discarded_keys) {
  int count = 0;
  for (const std::string& key : discarded_keys) {
    const std::optional<JobRecord> job = store.find_job(key);
    if (!job || job->status != "done") ++count;
  }
  return count;
}

}  // namespace

RunSummary run_sweep(const ExpandedSweep& sweep, const JobExecutor& executor, const RunOptions& options,
                     const std::atomic<bool>& stop_requested) {
  const auto start = Clock::now();
  RunSummary summary;
  summary.jobs_in_sweep = static_cast<int>(sweep.jobs.size());
  const std::vector<const ExpandedJob*> shard_jobs = select_shard_jobs(sweep, options);
  summary.jobs_in_shard = static_cast<int>(shard_jobs.size());

  ResultsStore store = ResultsStore::open(options.db_path, ResultsStore::Mode::read_write);
  const SweepRegistration registration = make_sweep_registration(sweep, options);
  const RegisteredRun registered = register_shard(store, registration, shard_jobs);
  const std::vector<const ExpandedJob*> to_run = select_jobs_to_run(shard_jobs, registered, options, summary.skipped);

  ClaimKeeper claims(options.db_path, make_claim_owner(options.provenance.host, registered.run_id, sweep.spec.name),
                     options.claims, options.force, registration.started_at);
  summary.taken_over = claims.stale_at_start().claims_interrupted;
  const int threads = choose_thread_count(options);
  ProgressReporter progress(options.progress_out, options.progress, make_progress_jobs(sweep, to_run, options), threads);
  std::vector<HeadlineJob> headline_jobs;
  std::vector<std::string> discarded_keys;
  {
    ShardRun run(sweep, executor, options, stop_requested, to_run, store, claims, progress, summary, headline_jobs,
                 discarded_keys);
    run.run_rounds(threads);
    run.finish();
  }
  if (summary.write_error.empty()) summary.discarded_not_done += count_discarded_not_done(store, discarded_keys);
  summary.taken_over += claims.taken_over();
  // A stop that came after (or let finish) every job of the shard interrupted nothing.
  summary.interrupted = stop_requested.load() && summary.abandoned > 0;
  summary.headline = choose_run_headline(headline_jobs);
  if (summary.write_error.empty()) {
    store.update_run_finished(registered.run_id, summary.interrupted ? "interrupted" : "complete", summary.run,
                              summary.skipped, make_utc_timestamp());
  }
  summary.elapsed_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return summary;
}

}  // namespace armfarm
