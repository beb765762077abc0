// `armfarm lease DB [SECONDS]`: shows, or sets, the lease of a results database's job claims
// (results/job_claims.hpp): how long a claim may go without a heartbeat before another runner
// takes its job over. It is the file's, not a runner's, so that every runner judges by the same
// one; a runner heartbeats at a sixth of it and reads it again at every beat.
#include "results/results_store.hpp"
#include "runner/cli/number_checks.hpp"
#include "runner/cli/subcommand.hpp"

#include <iostream>
#include <memory>

namespace armfarm::cli {

RunFunction setup_lease(CLI::App& parent) {
  struct Options {
    std::string db;
    double seconds = 0.0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "lease", "Show or set how long a job claim may go without a heartbeat before another runner takes it over");
  app->add_option("db", options->db, "Results database (created if absent when SECONDS is given)")->required();
  app->add_option("seconds", options->seconds, "The new lease, s (every runner of the file uses it; default 60)")
      ->check(make_positive_check());

  return [options, app] {
    const bool set = app->count("seconds") > 0;
    ResultsStore store =
        ResultsStore::open(options->db, set ? ResultsStore::Mode::read_write : ResultsStore::Mode::read_only);
    if (set) store.update_lease_seconds(options->seconds, make_utc_timestamp());
    std::cout << options->db << ": lease " << store.find_lease_seconds()
              << " s (a claim without a heartbeat for longer is taken over; runners heartbeat every "
              << store.find_lease_seconds() / 6.0 << " s)\n";
    return 0;
  };
}

}  // namespace armfarm::cli
