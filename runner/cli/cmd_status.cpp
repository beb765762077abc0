// `armfarm status DB [--check]`: job counts by status for each sweep, counted against the
// expansion of the sweep's stored spec ("20 of 40 jobs in this file", naming the missing ones: a
// shard not merged), then the failures with their messages (a search sweep: its budget spent and
// each rung's progress), then the live job claims and the `runs` rows still open, each said
// running, stale (no heartbeat within the file's lease) or died (its pid is gone on this host),
// with the runner's host and pid. --check first verifies the file row by row (integrity_check,
// dangling references, stored JSON, storage classes, series blobs) and exits 2 if it is damaged.
// Every text read from the file is printed without control characters (ANSI escapes, newlines):
// the file may be someone else's. Exit 1 when a job failed or the file lacks jobs of its spec.
#include "analysis/printable_text.hpp"
#include "analysis/search_summary.hpp"
#include "results/readable_check.hpp"
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/claim_keeper.hpp"
#include "runner/execution/job_kind.hpp"
#include "runner/execution/sweep_runner.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/sweep_stages.hpp"

#include <cstdio>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>

namespace armfarm::cli {
namespace {

// How many missing jobs a line names before "... and N more".
constexpr std::size_t kMissingShown = 3;
// The longest reason printed for a stored spec that does not expand here.
constexpr std::size_t kNoteLength = 200;

std::string shown(const std::string& text) { return make_printable_text(text); }

std::string make_seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", seconds);
  return text;
}

// Whether the runner of a live claim or open `runs` row still holds it.
enum class RunnerState { running, stale, died };

RunnerState find_runner_state(const std::string& host, std::int64_t pid, double heartbeat_age, double lease) {
  if (is_runner_gone(host, pid)) return RunnerState::died;
  return heartbeat_age > lease ? RunnerState::stale : RunnerState::running;
}

// "stale: no heartbeat for 12.0 s, over the file's lease of 3 s (...)" or "died: ..." for a
// runner that no longer holds what it claimed; "" for a running one.
std::string make_stopped_runner_text(RunnerState state, const std::string& host, std::int64_t pid,
                                     double heartbeat_age, double lease) {
  const std::string runner = "runner " + shown(host) + " pid " + std::to_string(pid);
  if (state == RunnerState::died) {
    return "died: " + runner + " is gone (no such process on this host), last heartbeat " +
           make_seconds_text(heartbeat_age) + " ago; not running, the next run takes it over";
  }
  char lease_text[32];
  std::snprintf(lease_text, sizeof lease_text, "%g s", lease);
  return "stale: no heartbeat for " + make_seconds_text(heartbeat_age) + ", over the file's lease of " + lease_text +
         " (" + runner + " stopped, was paused or lost the file); not running, the next run takes it over";
}

// What the expansion of a sweep's stored spec says of the jobs this file holds.
struct SpecCoverage {
  std::optional<std::size_t> expected;  ///< jobs of the spec (when it expands to the job list that was run)
  std::vector<std::string> missing;     ///< labels of the spec's jobs that are not in this file
  std::string note;                     ///< why `expected` is unknown ("" for a search: it decides its jobs)
};

// Unless the file holds the whole job list that was run: expands the stored spec with its
// relative paths resolved against the current folder, then the database's; the expansion counts only when its job list hashes to the stored spec_hash (the
// list that was run: no input file and no default changed since).
SpecCoverage calc_spec_coverage(const SweepRecord& sweep, const std::vector<JobRecord>& jobs, const JobKind& kind,
                                const std::string& db_path) {
  SpecCoverage coverage;
  // The file holds the whole job list that was run (spec_hash is the hash of its sorted keys,
  // runner/spec/sweep_expansion.cpp): complete, nothing to expand. Every run that is not a
  // shard registers its whole list, so only shard files and their partial merges expand.
  std::vector<std::string> keys;
  for (const JobRecord& job : jobs) keys.push_back(job.key);
  std::sort(keys.begin(), keys.end());
  if (calc_text_hash(calc_canonical_json(nlohmann::json(keys))) == sweep.spec_hash) return coverage;
  const std::string file = db_path + ": the stored spec of sweep " + sweep.name;
  const std::filesystem::path db_folder = std::filesystem::absolute(db_path).parent_path();
  for (const std::string& folder : {std::filesystem::current_path().string(), db_folder.string()}) {
    try {
      std::vector<SweepSpec> stages = parse_sweep_stages(sweep.spec_text, file, folder, kind.schema);
      bool found = false;
      for (SweepSpec& stage : stages) {
        if (stage.name != sweep.name) continue;
        found = true;
        if (stage.search) return coverage;  // a search decides its jobs as it runs
        const ExpandedSweep expanded = expand_sweep(std::move(stage), kind.schema);
        if (expanded.spec_hash != sweep.spec_hash) {
          coverage.note = "its stored spec now expands to other jobs than were run (an input file or armfarm changed)";
          break;
        }
        std::set<std::string> present;
        for (const JobRecord& job : jobs) present.insert(job.key);
        coverage.expected = expanded.jobs.size();
        for (const ExpandedJob& job : expanded.jobs) {
          if (!present.count(job.key)) coverage.missing.push_back(make_job_label(job));
        }
        return coverage;
      }
      if (!found) coverage.note = "its stored spec has no sweep of that name";
    } catch (const SpecError& e) {
      coverage.note = e.lines().empty() ? "its stored spec does not expand" : e.lines().front();
    } catch (const std::exception& e) {
      coverage.note = e.what();
    }
  }
  coverage.note = "this file holds part of the jobs that were run (a shard?), and " + coverage.note;
  if (coverage.note.size() > kNoteLength) coverage.note = coverage.note.substr(0, kNoteLength) + "...";
  return coverage;
}

void print_claims(const ResultsStore& store, const std::string& now, double lease, std::ostream& out) {
  const std::vector<JobClaimRecord> claims = store.find_job_claims(now, false);
  int interrupted = 0;
  std::vector<const JobClaimRecord*> live;
  for (const JobClaimRecord& claim : claims) {
    if (claim.state == "live") {
      live.push_back(&claim);
    } else {
      ++interrupted;
    }
  }
  if (!live.empty()) out << "live claims: " << live.size() << "\n";
  for (const JobClaimRecord* claim : live) {
    out << "  " << shown(claim->key.substr(0, 12)) << " owner " << shown(claim->owner) << " host " << shown(claim->host)
        << " pid " << claim->pid << ": ";
    const RunnerState state = find_runner_state(claim->host, claim->pid, claim->heartbeat_age_seconds, lease);
    if (state == RunnerState::running) {
      out << "running " << make_seconds_text(claim->claim_age_seconds) << ", heartbeat "
          << make_seconds_text(claim->heartbeat_age_seconds) << " ago";
    } else {
      out << make_stopped_runner_text(state, claim->host, claim->pid, claim->heartbeat_age_seconds, lease);
    }
    out << "\n";
  }
  if (interrupted > 0) {
    out << "interrupted claims: " << interrupted << " (stale claims of stopped runners, taken over)\n";
  }
}

// The `runs` rows still marked running: a SIGKILL leaves its row so until a later run marks it
// interrupted; here it is said died or stale.
void print_open_runs(const ResultsStore& store, const std::string& now, double lease, std::ostream& out) {
  const std::vector<RunningRunRecord> runs = store.find_running_runs(now);
  if (runs.empty()) return;
  out << "runs not closed: " << runs.size() << "\n";
  for (const RunningRunRecord& run : runs) {
    out << "  run " << run.id << " of sweep " << shown(run.sweep) << (run.shard ? " (shard " + shown(*run.shard) + ")" : "")
        << " host " << shown(run.host) << " pid " << run.pid << ", started " << shown(run.started_at) << ": ";
    const RunnerState state = find_runner_state(run.host, run.pid, run.heartbeat_age_seconds, lease);
    if (state == RunnerState::running) {
      out << "running, heartbeat " << make_seconds_text(run.heartbeat_age_seconds) << " ago";
    } else {
      out << make_stopped_runner_text(state, run.host, run.pid, run.heartbeat_age_seconds, lease);
    }
    out << "\n";
  }
}

}  // namespace

RunFunction setup_status(CLI::App& parent) {
  auto db_path = std::make_shared<std::string>();
  auto check = std::make_shared<bool>(false);
  CLI::App* app = parent.add_subcommand("status", "Count a database's jobs by status and list the failures");
  app->add_option("db", *db_path, "Results database")->required();
  app->add_flag("--check", *check, "Verify the file row by row first (integrity, references, types, series)");

  return [db_path, check] {
    const ResultsStore store = ResultsStore::open(*db_path, ResultsStore::Mode::read_only);
    if (*check) {
      const std::vector<std::string> findings = store.check_contents(true, 50);
      for (const std::string& finding : findings) std::cerr << "armfarm: " << *db_path << ": " << shown(finding) << "\n";
      if (!findings.empty()) return 2;
      std::cout << *db_path << ": check passed (integrity, references, stored JSON, value types, series)\n";
    } else {
      // Without --check, the readers' check still runs (quick_check, dangling rows, series
      // checksums): a file `table` would call damaged is not reported as fine.
      verify_readable(store);
    }
    const std::string now = make_utc_timestamp();
    const double lease = store.find_lease_seconds();
    // Keys of jobs whose live claim's runner no longer holds it: not counted as running.
    std::set<std::string> stopped_claims;
    for (const JobClaimRecord& claim : store.find_job_claims(now, true)) {
      if (find_runner_state(claim.host, claim.pid, claim.heartbeat_age_seconds, lease) != RunnerState::running) {
        stopped_claims.insert(claim.key);
      }
    }
    const JobKind kind = make_job_kind(*db_path);
    const std::vector<SweepRecord> sweeps = store.find_sweeps();
    if (sweeps.empty()) std::cout << *db_path << ": no sweeps\n";
    bool any_failure = false;
    for (const SweepRecord& sweep : sweeps) {
      const std::vector<JobRecord> jobs = store.find_jobs(sweep.name);
      std::map<std::string, int> counts;
      for (const JobRecord& job : jobs) {
        ++counts[job.status == "running" && stopped_claims.count(job.key) ? "stale (runner stopped)" : job.status];
      }
      const SpecCoverage coverage = calc_spec_coverage(sweep, jobs, kind, *db_path);
      std::cout << "sweep " << shown(sweep.name) << ": ";
      if (coverage.expected && (jobs.size() != *coverage.expected || !coverage.missing.empty())) {
        std::cout << jobs.size() << " of " << *coverage.expected << " jobs in this file";
      } else {
        std::cout << jobs.size() << " jobs";
      }
      for (const char* status : {"done", "failed", "diverged", "timeout", "running", "stale (runner stopped)", "pending"}) {
        const auto found = counts.find(status);
        if (found != counts.end()) std::cout << ", " << found->second << " " << status;
      }
      std::cout << " (started " << shown(sweep.started_at) << ", "
                << (sweep.finished_at ? "finished " + shown(*sweep.finished_at) : std::string("not finished")) << ")\n";
      if (!coverage.missing.empty()) {
        any_failure = true;
        std::cout << "  missing: " << coverage.missing.size() << " jobs of its spec are not in this file (a shard not merged?): ";
        for (std::size_t i = 0; i < std::min(kMissingShown, coverage.missing.size()); ++i) {
          std::cout << (i ? ", " : "") << shown(coverage.missing[i]);
        }
        if (coverage.missing.size() > kMissingShown) std::cout << " ... and " << coverage.missing.size() - kMissingShown << " more";
        std::cout << "\n";
      } else if (!coverage.note.empty()) {
        std::cout << "  (not counted against its spec: " << shown(coverage.note) << ")\n";
      }
      if (const std::optional<SearchSummary> summary = load_search_summary(store, sweep.name)) {
        std::cout << make_printable_text(format_search_progress(*summary), /*keep_newlines=*/true);
      }
      for (const JobRecord& job : jobs) {
        if (job.status != "failed" && job.status != "diverged" && job.status != "timeout") continue;
        any_failure = true;
        std::cout << "  " << shown(job.status) << " " << shown(job.key.substr(0, 12));
        for (const auto& [path, value] : job.params.items()) std::cout << " " << shown(path) << "=" << shown(value.dump());
        std::cout << ": " << shown(job.message) << "\n";
      }
    }
    print_claims(store, now, lease, std::cout);
    print_open_runs(store, now, lease, std::cout);
    return any_failure ? 1 : 0;
  };
}

}  // namespace armfarm::cli
