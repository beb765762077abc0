// `armfarm run SPEC.json`: expands a sweep and runs the jobs not yet done, in parallel, into a
// results database (resume is the default; --force runs everything again). A spec with stages
// runs them in order (runner/spec/sweep_stages.hpp).
#include "results/readable_check.hpp"
#include "runner/cli/number_checks.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/input_changes.hpp"
#include "runner/execution/job_kind.hpp"
#include "runner/execution/provenance.hpp"
#include "runner/execution/search_runner.hpp"
#include "runner/execution/stop_signal.hpp"
#include "runner/execution/sweep_runner.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_stages.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

namespace armfarm::cli {

namespace {

// Runs `step`; an error of the spec, its configuration or the store is printed as its one line
// (the configuration's prefixed by the spec's path) and gives false: the command exits 2.
template <class Step>
bool reports_input_errors(const std::string& spec, Step&& step) {
  try {
    step();
    return true;
  } catch (const StoreError& e) {
    std::cerr << "armfarm: " << e.what() << "\n";
  } catch (const ConfigError& e) {
    std::cerr << "armfarm: " << spec << ": " << e.what() << "\n";
  } catch (const SpecError& e) {
    for (const std::string& line : e.lines()) std::cerr << "armfarm: " << line << "\n";
  }
  return false;
}


// The command line of `armfarm run`.
struct RunCommandLine {
  std::string spec;
  std::string db = "results.db";
  int threads = 0;
  double timeout = 0.0;
  double stop_grace = 0.0;
  bool force = false;
  bool keep_failed = false;
  std::string shard;
  std::string shard_costs;
  double claim_timeout = 0.0;  // gone: the lease is the database's (cmd_lease.cpp)
  bool quiet = false;
  double heartbeat = ProgressConfig{}.heartbeat_seconds;
  ExpansionLimits limits;
};

void add_run_options(CLI::App& app, RunCommandLine& line) {
  app.add_option("spec", line.spec, "Sweep spec (JSON)")->required();
  app.add_option("--db", line.db, "Results database (created if absent)")->capture_default_str();
  app.add_option("-j,--jobs", line.threads, "Jobs run in parallel (default: the number of cores)")
      ->check(make_non_negative_check());
  app.add_option("--timeout", line.timeout, "Stop a job after this many seconds of wall clock (0: none)")
      ->check(make_non_negative_check());
  app.add_option("--stop-grace", line.stop_grace,
                 "On a stop signal (Slurm's warning, Ctrl-C), let running jobs the cost model expects to end within "
                 "this many seconds finish, at most that long; the others stop at once and stay pending (0: all stop at once)")
      ->check(make_non_negative_check());
  app.add_flag("--force", line.force, "Run every job again, even those already done");
  app.add_flag("--keep-failed", line.keep_failed,
               "Failed, diverged and timed-out jobs are results: do not run them again (armfarm slurm's tasks)");
  app.add_option("--shard", line.shard,
                 "Run only shard I of N (I/N, 1-based), to split a sweep across machines; jobs are dealt by estimated cost");
  app.add_option("--shard-costs", line.shard_costs,
                 "With --shard: a results database whose finished jobs' wall times calibrate the costs (give every shard "
                 "the same file)");
  // Refused with a pointer to `armfarm lease`: a per-runner timeout let a runner with a shorter
  // one take over the live claims of another (issue 30). Hidden from --help.
  app.add_option("--claim-timeout", line.claim_timeout)->group("");
  app.add_flag("-q,--quiet", line.quiet, "No progress output; only the summary and errors");
  app.add_option("--heartbeat", line.heartbeat,
                 "When standard error is not a terminal: a progress line every this many seconds (0: none)")
      ->check(make_non_negative_check())
      ->capture_default_str();
  app.add_option("--max-jobs", line.limits.max_jobs, "Refuse a sweep of more jobs than this")
      ->capture_default_str()->check(make_positive_check());
}

// An existing file is checked as every reader checks it before anything is added to it: a
// damaged one is refused in one line (exit 2), not run into. Opened writable, as the run opens
// it: a file another runner is creating at this moment (empty, or its schema not yet committed)
// is waited for and created once, never taken for a damaged one. False: refused (printed).
bool check_existing_database(const RunCommandLine& line) {
  if (!std::filesystem::exists(line.db)) return true;
  return reports_input_errors(line.spec, [&] { verify_readable(ResultsStore::open(line.db, ResultsStore::Mode::read_write)); });
}

// What the run reads before anything runs: the spec's stages, the shard (into `run`) and the
// database that calibrates the costs. False: an input error was printed (exit 2).
bool load_run_inputs(const RunCommandLine& line, const JobKind& kind, std::vector<SweepSpec>& stages, RunOptions& run,
                     std::optional<ResultsStore>& cost_reference) {
  try {
    stages = load_sweep_stages(line.spec, kind.schema);
    if (!line.shard.empty()) run.shard = parse_shard(line.shard);
    if (!line.shard_costs.empty() && line.shard.empty()) {
      throw std::invalid_argument("--shard-costs " + line.shard_costs + ": only with --shard");
    }
    if (!line.shard_costs.empty()) cost_reference = ResultsStore::open(line.shard_costs, ResultsStore::Mode::read_only);
    return true;
  } catch (const StoreError& e) {
    std::cerr << "armfarm: " << e.what() << "\n";
  } catch (const SpecError& e) {
    for (const std::string& line_text : e.lines()) std::cerr << "armfarm: " << line_text << "\n";
  } catch (const std::invalid_argument& e) {
    std::cerr << "armfarm: " << e.what() << "\n";
  }
  return false;
}

// The rest of the run's options from the command line: database, threads, timeouts, the
// progress style for this terminal (or log), provenance and the stop signals.
void fill_run_options(const RunCommandLine& line, const StopSignalScope& signals, RunOptions& run) {
  run.db_path = line.db;
  run.threads = line.threads > 0 ? line.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (line.timeout > 0.0) run.timeout_seconds = line.timeout;
  if (line.stop_grace > 0.0) run.stop_grace_seconds = line.stop_grace;
  run.force = line.force;
  run.rerun_unsuccessful = !line.keep_failed;
  const bool terminal = isatty(STDERR_FILENO) != 0;
  run.progress.style = line.quiet ? ProgressStyle::quiet : terminal ? ProgressStyle::terminal : ProgressStyle::lines;
  run.progress.heartbeat_seconds = line.heartbeat;
  winsize size{};
  if (terminal && ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) run.progress.terminal_width = size.ws_col;
  run.progress_out = &std::cerr;
  run.provenance = make_provenance();
  run.stop_at_once = &signals.stop_at_once();
}

// A search stage, run until it finishes or stops, and its summary line. The exit status: 0 when
// it finished (the next stage runs), 1 when not, 2 on an input error (printed).
int run_search_stage(const RunCommandLine& line, const SweepSpec& stage, const JobKind& kind, const RunOptions& run,
                     const StopSignalScope& signals) {
  const SpecSearch& search = *stage.search;
  std::cout << "search " << stage.name << ": " << to_string(search.settings.method) << ", " << run.threads
            << " threads, database " << run.db_path << std::endl;
  SearchRunSummary result;
  if (!reports_input_errors(line.spec, [&] { result = run_search(stage, kind, run, line.limits, signals.stop_requested()); })) {
    return 2;
  }
  std::cout << "search " << stage.name << ": " << result.steps << " steps (" << result.trials << " trials) in "
            << result.rounds << " rounds, spent " << result.spent << " of " << search.budget
            << (search.budget_unit == SpecSearch::BudgetUnit::jobs ? " jobs" : " cost units");
  if (result.best) std::cout << "; best " << search.objective.metric << " " << *result.best << " (trial " << result.best_trial << ")";
  std::cout << (result.finished ? "; finished" : "; not finished: run the same command again to resume") << "\n";
  return result.finished ? 0 : 1;
}

// A sweep stage expanded, with its jobs' estimated costs (they deal the shards and weight the
// progress ETA) and, for the stop grace, their expected wall times in `run`. False: an input
// error was printed (exit 2).
bool expand_run_stage(const RunCommandLine& line, SweepSpec stage, const JobKind& kind,
                      const std::optional<ResultsStore>& cost_reference, RunOptions& run, ExpandedSweep& sweep) {
  return reports_input_errors(line.spec, [&] {
    sweep = expand_sweep(std::move(stage), kind.schema, line.limits);
    run.job_costs = calc_job_costs(sweep, kind.estimate_cost, cost_reference ? &*cost_reference : nullptr);
    // The stop grace goes by expected wall times, calibrated by what finished in this file
    // before (a resumed shard) unless a cost reference is given.
    if (run.stop_grace_seconds) {
      std::optional<ResultsStore> own;
      if (!cost_reference && std::filesystem::exists(run.db_path)) own = ResultsStore::open(run.db_path, ResultsStore::Mode::read_only);
      const ResultsStore* reference = cost_reference ? &*cost_reference : own ? &*own : nullptr;
      run.job_seconds = calc_job_seconds(sweep, kind.estimate_cost, reference);
    }
  });
}

// The line a sweep stage starts with, and what changed in its inputs since the file's jobs ran.
void print_stage_start(const RunCommandLine& line, const ExpandedSweep& sweep, const JobKind& kind, const RunOptions& run,
                       const std::string& stage_text) {
  std::cout << "sweep " << sweep.spec.name << stage_text << ": " << sweep.jobs.size() << " jobs"
            << (run.shard.count > 1 ? " (shard " + line.shard + ")" : "") << ", " << run.threads << " threads, database "
            << run.db_path << (kind.name == "experiment" ? "" : ", " + kind.name + " jobs") << std::endl;
  const std::string changes = make_input_change_text(find_input_changes(sweep, run.db_path));
  if (!changes.empty()) std::cout << "sweep " << sweep.spec.name << ": " << changes << std::endl;
}

// The counts of a finished sweep stage, the results another runner's take-over discarded, the
// headline and the first failures.
void print_stage_counts(const ExpandedSweep& sweep, const RunOptions& run, const RunSummary& summary) {
  std::cout << "sweep " << sweep.spec.name << ": " << summary.done << " done, " << summary.failed << " failed, "
            << summary.diverged << " diverged, " << summary.timeout << " timed out, " << summary.skipped
            << " already done (skipped)";
  if (run.shard.count > 1) std::cout << "; " << summary.jobs_in_shard << " of " << summary.jobs_in_sweep << " jobs in this shard";
  if (summary.done_elsewhere > 0) std::cout << "; " << summary.done_elsewhere << " done by another runner";
  if (summary.taken_over > 0) std::cout << "; " << summary.taken_over << " stale claims of stopped runners taken over";
  std::cout << "; wall time " << make_duration_text(summary.elapsed_seconds) << "\n";
  if (summary.discarded > 0) {
    std::cout << "sweep " << sweep.spec.name << ": " << summary.discarded
              << " finished results discarded: another runner took their claims over while this one went "
                 "without a heartbeat past the lease (paused or cut off); those jobs are that runner's";
    if (summary.discarded_not_done > 0) {
      std::cout << ", and " << summary.discarded_not_done << " of them are not done in the file yet (armfarm status "
                << run.db_path << ")";
    }
    std::cout << "\n";
  }
  if (summary.headline) std::cout << "sweep " << sweep.spec.name << ": " << make_headline_text(*summary.headline) << "\n";
  const std::size_t shown = std::min<std::size_t>(summary.failures.size(), 20);
  for (std::size_t i = 0; i < shown; ++i) std::cout << "  " << summary.failures[i] << "\n";
  if (summary.failures.size() > shown) {
    std::cout << "  ... and " << summary.failures.size() - shown << " more (armfarm status " << run.db_path << ")\n";
  }
}

// The end of a sweep stage: lost results, an interruption, jobs not done. The exit status: 0 when
// every job is done (the next stage runs), 1 when not, 3 when finished results were not saved.
int finish_stage(const ExpandedSweep& sweep, const RunOptions& run, const RunSummary& summary, bool later_stages) {
  if (!summary.write_error.empty()) {
    std::cout.flush();
    std::cerr << "armfarm: " << run.db_path << ": writing results failed (" << summary.write_error << "); stopped: "
              << summary.not_saved << " finished jobs were not saved, " << summary.run
              << " saved; run the same command again to rerun the unsaved ones\n";
    return kExitResultsNotSaved;
  }
  if (summary.interrupted) {
    std::cout << "interrupted: " << summary.abandoned << " jobs not finished";
    if (run.stop_grace_seconds) {
      std::cout << " (" << summary.finished_in_grace << " of the running ones finished within the stop grace of "
                << *run.stop_grace_seconds << " s)";
    }
    std::cout << "; run the same command again to resume\n";
  }
  if (summary.all_done()) return 0;
  if (later_stages) std::cout << "sweep " << sweep.spec.name << ": not every job is done, so the later stages did not run\n";
  return 1;
}

// Stages run in order, each expanded only after the ones before it ran (its jobs may start from
// the models they stored); a stage that is not all done stops the rest. The exit status.
int run_stages(const RunCommandLine& line, std::vector<SweepSpec>& stages, const JobKind& kind,
               const std::optional<ResultsStore>& cost_reference, RunOptions& run, const StopSignalScope& signals) {
  for (std::size_t s = 0; s < stages.size(); ++s) {
    if (stages[s].search) {
      if (const int status = run_search_stage(line, stages[s], kind, run, signals); status != 0) return status;
      continue;
    }
    ExpandedSweep sweep;
    if (!expand_run_stage(line, std::move(stages[s]), kind, cost_reference, run, sweep)) return 2;
    const std::string stage_text =
        stages.size() > 1 ? " (stage " + std::to_string(s + 1) + " of " + std::to_string(stages.size()) + ")" : "";
    print_stage_start(line, sweep, kind, run, stage_text);
    const RunSummary summary = run_sweep(sweep, kind.executor, run, signals.stop_requested());
    print_stage_counts(sweep, run, summary);
    if (const int status = finish_stage(sweep, run, summary, s + 1 < stages.size()); status != 0) return status;
  }
  return 0;
}

}  // namespace

RunFunction setup_run(CLI::App& parent) {
  auto line = std::make_shared<RunCommandLine>();
  CLI::App* app = parent.add_subcommand("run", "Run a sweep's jobs into a results database (resumes by default)");
  add_run_options(*app, *line);
  return [line, app] {
    if (app->count("--claim-timeout") > 0) {
      std::cerr << "armfarm: --claim-timeout is gone: the lease is the database's, one for every runner "
                   "(armfarm lease "
                << line->db << " SECONDS)\n";
      return 2;
    }
    if (!check_existing_database(*line)) return 2;
    const JobKind kind = make_job_kind(line->db);
    std::vector<SweepSpec> stages;
    RunOptions run;
    std::optional<ResultsStore> cost_reference;
    if (!load_run_inputs(*line, kind, stages, run, cost_reference)) return 2;
    StopSignalScope signals;
    fill_run_options(*line, signals, run);
    // Refused before any stage runs (a stage before the search would be half of a sharded run).
    for (const SweepSpec& stage : stages) {
      if (stage.search && run.shard.count > 1) {
        std::cerr << "armfarm: " << line->spec << ": sweep.search: " << kSearchNotShardedReason << "\n";
        return 2;
      }
    }
    return run_stages(*line, stages, kind, cost_reference, run, signals);
  };
}

}  // namespace armfarm::cli
