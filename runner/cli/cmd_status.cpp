// `armfarm status DB [--check]`: job counts by status for each sweep, then the failures with
// their messages, then the live job claims of the runners working on the file (owner, host, pid,
// ages). --check first verifies the file row by row (integrity_check, dangling references,
// stored JSON, storage classes, series blobs) and exits 2 if it is damaged.
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"

#include <cstdio>

#include <iostream>
#include <memory>

namespace armfarm::cli {
namespace {

void print_claims(const ResultsStore& store, std::ostream& out) {
  const std::vector<JobClaimRecord> claims = store.find_job_claims(make_utc_timestamp(), false);
  const double lease = store.find_lease_seconds();
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
    char ages[96];
    std::snprintf(ages, sizeof ages, "running %.1f s, heartbeat %.1f s ago", claim->claim_age_seconds,
                  claim->heartbeat_age_seconds);
    out << "  " << claim->key.substr(0, 12) << " owner " << claim->owner << " host " << claim->host << " pid "
        << claim->pid << ": " << ages;
    if (claim->heartbeat_age_seconds > lease) {
      out << " (stale: no heartbeat within the file's lease of " << lease
          << " s, its runner stopped; the next run takes it over)";
    }
    out << "\n";
  }
  if (interrupted > 0) {
    out << "interrupted claims: " << interrupted << " (stale claims of stopped runners, taken over)\n";
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
      for (const std::string& finding : findings) std::cerr << "armfarm: " << *db_path << ": " << finding << "\n";
      if (!findings.empty()) return 2;
      std::cout << *db_path << ": check passed (integrity, references, stored JSON, value types, series)\n";
    } else {
      // Without --check, SQLite's quick_check still runs: a file `table` would call malformed
      // is not reported as fine.
      const std::string quick = store.check_integrity(true);
      if (quick != "ok") {
        std::cerr << "armfarm: " << *db_path << ": damaged armfarm database: quick_check: "
                  << quick.substr(0, quick.find('\n')) << " (armfarm status --check " << *db_path << " lists more)\n";
        return 2;
      }
    }
    const std::vector<SweepRecord> sweeps = store.find_sweeps();
    if (sweeps.empty()) std::cout << *db_path << ": no sweeps\n";
    bool any_failure = false;
    for (const SweepRecord& sweep : sweeps) {
      const std::map<std::string, int> counts = store.count_jobs_by_status(sweep.name);
      int total = 0;
      for (const auto& [status, count] : counts) total += count;
      std::cout << "sweep " << sweep.name << ": " << total << " jobs";
      for (const char* status : {"done", "failed", "diverged", "timeout", "running", "pending"}) {
        const auto found = counts.find(status);
        if (found != counts.end()) std::cout << ", " << found->second << " " << status;
      }
      std::cout << " (started " << sweep.started_at << ", "
                << (sweep.finished_at ? "finished " + *sweep.finished_at : std::string("not finished")) << ")\n";
      for (const JobRecord& job : store.find_jobs(sweep.name)) {
        if (job.status != "failed" && job.status != "diverged" && job.status != "timeout") continue;
        any_failure = true;
        std::cout << "  " << job.status << " " << job.key.substr(0, 12);
        for (const auto& [path, value] : job.params.items()) std::cout << " " << path << "=" << value.dump();
        std::cout << ": " << job.message << "\n";
      }
    }
    print_claims(store, std::cout);
    return any_failure ? 1 : 0;
  };
}

}  // namespace armfarm::cli
