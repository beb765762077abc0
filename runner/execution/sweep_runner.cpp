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

RunSummary run_sweep(const ExpandedSweep& sweep, const JobExecutor& executor, const RunOptions& options,
                     const std::atomic<bool>& stop_requested) {
  const auto start = std::chrono::steady_clock::now();
  RunSummary summary;
  summary.jobs_in_sweep = static_cast<int>(sweep.jobs.size());

  std::vector<const ExpandedJob*> shard_jobs;
  {
    std::vector<std::string> keys;
    for (const ExpandedJob& job : sweep.jobs) keys.push_back(job.key);
    const std::vector<int> shard_of = calc_shard_assignment(keys, options.job_costs, options.shard.count);
    for (std::size_t i = 0; i < sweep.jobs.size(); ++i) {
      if (shard_of[i] == options.shard.index) shard_jobs.push_back(&sweep.jobs[i]);
    }
  }
  summary.jobs_in_shard = static_cast<int>(shard_jobs.size());

  ResultsStore store = ResultsStore::open(options.db_path, ResultsStore::Mode::read_write);
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
  std::vector<JobRegistration> jobs;
  for (const ExpandedJob* job : shard_jobs) jobs.push_back({job->key, job->params, job->config(), job->seed});
  const RegisteredRun registered = store.insert_sweep_run(registration, jobs);

  std::vector<const ExpandedJob*> to_run;
  for (const ExpandedJob* job : shard_jobs) {
    const std::string& status = registered.status_by_key.at(job->key);
    const bool unsuccessful = status == "failed" || status == "diverged" || status == "timeout";
    if (options.force || (status != "done" && (options.rerun_unsuccessful || !unsuccessful))) {
      to_run.push_back(job);
    } else {
      ++summary.skipped;
    }
  }

  ClaimKeeper claims(options.db_path, make_claim_owner(options.provenance.host, registered.run_id, sweep.spec.name),
                     options.claims, options.force, registration.started_at);
  summary.taken_over = claims.stale_at_start().claims_interrupted;

  const int threads = options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<ProgressJob> progress_jobs;
  for (const ExpandedJob* job : to_run) {
    const auto index = static_cast<std::size_t>(job - sweep.jobs.data());
    const double cost = index < options.job_costs.size() ? options.job_costs[index] : 1.0;
    progress_jobs.push_back({make_job_label(*job), job->key.substr(0, 8), cost > 0.0 ? cost : 1.0});
  }
  ProgressReporter progress(options.progress_out, options.progress, std::move(progress_jobs), threads);
  std::mutex summary_mutex;
  std::vector<HeadlineJob> headline_jobs;
  std::vector<std::string> discarded_keys;  // guarded by summary_mutex
  // When the stop request was first seen (steady clock ticks; `none` before): the stop grace runs from it.
  constexpr std::chrono::steady_clock::rep none = std::numeric_limits<std::chrono::steady_clock::rep>::min();
  std::atomic<std::chrono::steady_clock::rep> stop_seen{none};
  const auto find_stop_seen = [&](std::chrono::steady_clock::time_point now) {
    std::chrono::steady_clock::rep expected = none;
    stop_seen.compare_exchange_strong(expected, now.time_since_epoch().count());
    return std::chrono::steady_clock::time_point(std::chrono::steady_clock::duration(stop_seen.load()));
  };
  {
    ResultWriter writer(store, sweep.spec.name, claims.owner().owner);
    std::vector<std::size_t> elsewhere;  // indices into to_run held by another live runner: looked at again
    std::string claim_error;  // the first claim that could not be written (guarded by summary_mutex)
    const auto claim_failed = [&] {
      std::lock_guard lock(summary_mutex);
      return !claim_error.empty();
    };
    auto run_one = [&](std::size_t index) {
      const ExpandedJob& job = *to_run[index];
      if (stop_requested.load() || writer.failed() || claims.failed() || claim_failed()) {
        std::lock_guard lock(summary_mutex);
        ++summary.abandoned;
        return;
      }
      ClaimAttempt claim;
      try {
        claim = claims.claim(job.key);
      } catch (const StoreError& e) {
        // A claim that cannot be written (a full disk) stops the run like a failed commit.
        std::lock_guard lock(summary_mutex);
        if (claim_error.empty()) claim_error = e.what();
        ++summary.abandoned;
        return;
      }
      if (claim.result != ClaimResult::claimed) {
        std::lock_guard lock(summary_mutex);
        if (claim.result == ClaimResult::done) ++summary.done_elsewhere;
        if (claim.result == ClaimResult::claimed_elsewhere) elsewhere.push_back(index);
        return;
      }
      progress.job_started(index);
      const std::string started_at = make_utc_timestamp();
      const auto job_start = std::chrono::steady_clock::now();
      bool stopped_by_request = false;
      bool stopped_by_timeout = false;
      bool claim_lost = false;
      std::optional<bool> runs_on;  // decided at the first look after the stop request: expected to end within the grace
      const auto sweep_index = static_cast<std::size_t>(&job - sweep.jobs.data());
      // Whether the stop grace lets this job run on now (stop_grace_seconds).
      const auto in_grace = [&] {
        if (!options.stop_grace_seconds || (options.stop_at_once != nullptr && options.stop_at_once->load())) return false;
        const auto now = std::chrono::steady_clock::now();
        const auto seen = find_stop_seen(now);
        const double grace = *options.stop_grace_seconds;
        if (std::chrono::duration<double>(now - seen).count() >= grace) return false;
        if (!runs_on) {
          const double ran = std::max(0.0, std::chrono::duration<double>(seen - job_start).count());
          runs_on = sweep_index < options.job_seconds.size() && options.job_seconds[sweep_index] - ran <= grace;
        }
        return *runs_on;
      };
      JobControl control;
      control.should_stop = [&] {
        if (claims.lost(job.key)) {
          claim_lost = true;
          return true;
        }
        if (writer.failed() || claims.failed() || (stop_requested.load() && !in_grace())) {
          stopped_by_request = true;
          return true;
        }
        if (options.timeout_seconds &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - job_start).count() > *options.timeout_seconds) {
          stopped_by_timeout = true;
          return true;
        }
        return false;
      };
      JobOutcome outcome;
      try {
        outcome = executor(job.config(), control);
      } catch (const std::exception& e) {
        outcome = JobOutcome{};
        outcome.status = JobStatus::failed;
        outcome.message = std::string("exception: ") + e.what();
      } catch (...) {
        outcome = JobOutcome{};
        outcome.status = JobStatus::failed;
        outcome.message = "unknown exception";
      }
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - job_start).count();
      const std::int64_t generation = claims.generation(job.key);
      claims.forget(job.key);  // before the writer releases the claim
      if (claim_lost && outcome.status != JobStatus::done) {
        writer.push_abandoned(job.key);  // another runner took it over: wait for its result
        progress.job_dropped(index);
        std::lock_guard lock(summary_mutex);
        elsewhere.push_back(index);
        return;
      }
      if (stopped_by_request && outcome.status != JobStatus::done) {
        writer.push_abandoned(job.key);
        progress.job_dropped(index);
        std::lock_guard lock(summary_mutex);
        ++summary.abandoned;
        return;
      }
      if (stopped_by_timeout && outcome.status != JobStatus::done) {
        outcome.status = JobStatus::timeout;
        char text[96];
        std::snprintf(text, sizeof text, "stopped after the timeout of %g s", *options.timeout_seconds);
        outcome.message = text;
      }
      const std::string status = to_string(outcome.status);
      HeadlineJob headline{make_job_label(job), {}};
      for (const Metric& metric : outcome.metrics) {
        if (!metric.joint && !metric.checkpoint && metric.value) headline.metrics[metric.name] = *metric.value;
      }
      // Counted and reported on the writer thread, once the result is committed.
      const bool ran_on = runs_on.value_or(false);
      auto on_committed = [&, index, status, wall, ran_on, key = job.key, message = outcome.message,
                           headline = std::move(headline)](bool written) mutable {
        if (!written) {  // fenced out: the claim was taken over while this attempt ran
          progress.job_dropped(index);
          std::lock_guard lock(summary_mutex);
          ++summary.discarded;
          discarded_keys.push_back(key);
          return;
        }
        progress.job_committed(index, status, wall, message);
        std::lock_guard lock(summary_mutex);
        ++summary.run;
        if (ran_on) ++summary.finished_in_grace;
        if (status == "done") {
          ++summary.done;
          headline_jobs.push_back(std::move(headline));
        } else {
          if (status == "failed") ++summary.failed;
          if (status == "diverged") ++summary.diverged;
          if (status == "timeout") ++summary.timeout;
          summary.failures.push_back(headline.label + ": " + status + ": " + message);
        }
      };
      JobResultRecord record = make_job_result_record(job.key, std::move(outcome), wall, started_at, make_utc_timestamp());
      record.claim_generation = generation;
      writer.push_finished(std::move(record), std::move(on_committed));
    };

    tbb::global_control allow(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    tbb::task_arena arena(threads);
    // Rounds: every job is claimed and run, or found done, or held by another live runner; those
    // are looked at again after a poll interval until done elsewhere or their claim goes stale.
    std::vector<std::size_t> round(to_run.size());
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
      round.swap(elsewhere);
      elsewhere.clear();
      std::sort(round.begin(), round.end());  // expansion order
      if (round.empty()) break;
      if (stop_requested.load() || writer.failed() || claims.failed() || claim_failed()) {
        summary.abandoned += static_cast<int>(round.size());
        break;
      }
      claims.wait_poll(stop_requested);
    }
    try {
      writer.finish();
    } catch (const std::exception&) {
      // Reported through the summary: the caller says how many finished jobs were lost.
    }
    progress.finish();
    summary.not_saved = writer.finished_not_saved();
    summary.write_error = writer.error_text();
    if (summary.write_error.empty() && !claim_error.empty()) summary.write_error = claim_error;
    if (summary.write_error.empty()) claims.rethrow_error();
  }
  // A discarded result is the job of the runner that took its claim over: done there, or not yet.
  if (summary.write_error.empty()) {
    for (const std::string& key : discarded_keys) {
      const std::optional<JobRecord> job = store.find_job(key);
      if (!job || job->status != "done") ++summary.discarded_not_done;
    }
  }
  summary.taken_over += claims.taken_over();
  // A stop that came after (or let finish) every job of the shard interrupted nothing.
  summary.interrupted = stop_requested.load() && summary.abandoned > 0;
  summary.headline = choose_run_headline(headline_jobs);
  if (summary.write_error.empty()) {
    store.update_run_finished(registered.run_id, summary.interrupted ? "interrupted" : "complete", summary.run,
                              summary.skipped, make_utc_timestamp());
  }
  summary.elapsed_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace armfarm
