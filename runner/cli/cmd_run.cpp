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

}  // namespace

RunFunction setup_run(CLI::App& parent) {
  struct Options {
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
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand("run", "Run a sweep's jobs into a results database (resumes by default)");
  app->add_option("spec", options->spec, "Sweep spec (JSON)")->required();
  app->add_option("--db", options->db, "Results database (created if absent)")->capture_default_str();
  app->add_option("-j,--jobs", options->threads, "Jobs run in parallel (default: the number of cores)")
      ->check(make_non_negative_check());
  app->add_option("--timeout", options->timeout, "Stop a job after this many seconds of wall clock (0: none)")
      ->check(make_non_negative_check());
  app->add_option("--stop-grace", options->stop_grace,
                  "On a stop signal (Slurm's warning, Ctrl-C), let running jobs the cost model expects to end within "
                  "this many seconds finish, at most that long; the others stop at once and stay pending (0: all stop at once)")
      ->check(make_non_negative_check());
  app->add_flag("--force", options->force, "Run every job again, even those already done");
  app->add_flag("--keep-failed", options->keep_failed,
                "Failed, diverged and timed-out jobs are results: do not run them again (armfarm slurm's tasks)");
  app->add_option("--shard", options->shard,
                  "Run only shard I of N (I/N, 1-based), to split a sweep across machines; jobs are dealt by estimated cost");
  app->add_option("--shard-costs", options->shard_costs,
                  "With --shard: a results database whose finished jobs' wall times calibrate the costs (give every shard "
                  "the same file)");
  // Refused with a pointer to `armfarm lease`: a per-runner timeout let a runner with a shorter
  // one take over the live claims of another (issue 30). Hidden from --help.
  app->add_option("--claim-timeout", options->claim_timeout)->group("");
  app->add_flag("-q,--quiet", options->quiet, "No progress output; only the summary and errors");
  app->add_option("--heartbeat", options->heartbeat,
                  "When standard error is not a terminal: a progress line every this many seconds (0: none)")
      ->check(make_non_negative_check())
      ->capture_default_str();
  app->add_option("--max-jobs", options->limits.max_jobs, "Refuse a sweep of more jobs than this")
      ->capture_default_str()->check(make_positive_check());

  return [options, app] {
    if (app->count("--claim-timeout") > 0) {
      std::cerr << "armfarm: --claim-timeout is gone: the lease is the database's, one for every runner "
                   "(armfarm lease "
                << options->db << " SECONDS)\n";
      return 2;
    }
    // An existing file is checked as every reader checks it before anything is added to it: a
    // damaged one is refused in one line (exit 2), not run into. Opened writable, as the run
    // opens it: a file another runner is creating at this moment (empty, or its schema not yet
    // committed) is waited for and created once, never taken for a damaged one.
    if (std::filesystem::exists(options->db) &&
        !reports_input_errors(options->spec, [&] {
          verify_readable(ResultsStore::open(options->db, ResultsStore::Mode::read_write));
        })) {
      return 2;
    }
    const JobKind kind = make_job_kind(options->db);
    std::vector<SweepSpec> stages;
    RunOptions run;
    std::optional<ResultsStore> cost_reference;
    try {
      stages = load_sweep_stages(options->spec, kind.schema);
      if (!options->shard.empty()) run.shard = parse_shard(options->shard);
      if (!options->shard_costs.empty() && options->shard.empty()) {
        throw std::invalid_argument("--shard-costs " + options->shard_costs + ": only with --shard");
      }
      if (!options->shard_costs.empty()) {
        cost_reference = ResultsStore::open(options->shard_costs, ResultsStore::Mode::read_only);
      }
    } catch (const StoreError& e) {
      std::cerr << "armfarm: " << e.what() << "\n";
      return 2;
    } catch (const SpecError& e) {
      for (const std::string& line : e.lines()) std::cerr << "armfarm: " << line << "\n";
      return 2;
    } catch (const std::invalid_argument& e) {
      std::cerr << "armfarm: " << e.what() << "\n";
      return 2;
    }
    run.db_path = options->db;
    run.threads = options->threads > 0 ? options->threads
                                       : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    if (options->timeout > 0.0) run.timeout_seconds = options->timeout;
    if (options->stop_grace > 0.0) run.stop_grace_seconds = options->stop_grace;
    run.force = options->force;
    run.rerun_unsuccessful = !options->keep_failed;
    const bool terminal = isatty(STDERR_FILENO) != 0;
    run.progress.style = options->quiet ? ProgressStyle::quiet : terminal ? ProgressStyle::terminal : ProgressStyle::lines;
    run.progress.heartbeat_seconds = options->heartbeat;
    winsize size{};
    if (terminal && ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) run.progress.terminal_width = size.ws_col;
    run.progress_out = &std::cerr;
    run.provenance = make_provenance();
    StopSignalScope signals;
    run.stop_at_once = &signals.stop_at_once();

    // Refused before any stage runs (a stage before the search would be half of a sharded run).
    for (const SweepSpec& stage : stages) {
      if (stage.search && run.shard.count > 1) {
        std::cerr << "armfarm: " << options->spec << ": sweep.search: " << kSearchNotShardedReason << "\n";
        return 2;
      }
    }

    // Stages run in order, each expanded only after the ones before it ran (its jobs may start
    // from the models they stored); a stage that is not all done stops the rest.
    for (std::size_t s = 0; s < stages.size(); ++s) {
      if (stages[s].search) {
        const std::string name = stages[s].name;
        std::cout << "search " << name << ": " << to_string(stages[s].search->settings.method) << ", " << run.threads
                  << " threads, database " << run.db_path << std::endl;
        SearchRunSummary result;
        if (!reports_input_errors(options->spec, [&] {
              result = run_search(stages[s], kind, run, options->limits, signals.stop_requested());
            })) {
          return 2;
        }
        std::cout << "search " << name << ": " << result.steps << " steps (" << result.trials << " trials) in "
                  << result.rounds << " rounds, spent " << result.spent << " of "
                  << stages[s].search->budget << (stages[s].search->budget_unit == SpecSearch::BudgetUnit::jobs ? " jobs" : " cost units");
        if (result.best) std::cout << "; best " << stages[s].search->objective.metric << " " << *result.best << " (trial " << result.best_trial << ")";
        std::cout << (result.finished ? "; finished" : "; not finished: run the same command again to resume") << "\n";
        if (!result.finished) return 1;
        continue;
      }
      ExpandedSweep sweep;
      if (!reports_input_errors(options->spec, [&] {
            sweep = expand_sweep(std::move(stages[s]), kind.schema, options->limits);
            // The jobs' estimated costs deal the shards and weight the progress ETA.
            run.job_costs = calc_job_costs(sweep, kind.estimate_cost, cost_reference ? &*cost_reference : nullptr);
            // The stop grace goes by expected wall times, calibrated by what finished in this
            // file before (a resumed shard) unless a cost reference is given.
            if (run.stop_grace_seconds) {
              std::optional<ResultsStore> own;
              if (!cost_reference && std::filesystem::exists(run.db_path)) {
                own = ResultsStore::open(run.db_path, ResultsStore::Mode::read_only);
              }
              const ResultsStore* reference = cost_reference ? &*cost_reference : own ? &*own : nullptr;
              run.job_seconds = calc_job_seconds(sweep, kind.estimate_cost, reference);
            }
          })) {
        return 2;
      }
      const std::string stage_text = stages.size() > 1 ? " (stage " + std::to_string(s + 1) + " of " + std::to_string(stages.size()) + ")" : "";
      std::cout << "sweep " << sweep.spec.name << stage_text << ": " << sweep.jobs.size() << " jobs"
                << (run.shard.count > 1 ? " (shard " + options->shard + ")" : "") << ", " << run.threads
                << " threads, database " << run.db_path << (kind.name == "experiment" ? "" : ", " + kind.name + " jobs")
                << std::endl;
      const std::string changes = make_input_change_text(find_input_changes(sweep, run.db_path));
      if (!changes.empty()) std::cout << "sweep " << sweep.spec.name << ": " << changes << std::endl;
      const RunSummary summary = run_sweep(sweep, kind.executor, run, signals.stop_requested());

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
      if (!summary.all_done()) {
        if (s + 1 < stages.size()) {
          std::cout << "sweep " << sweep.spec.name << ": not every job is done, so the later stages did not run\n";
        }
        return 1;
      }
    }
    return 0;
  };
}

}  // namespace armfarm::cli
