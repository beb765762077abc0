#pragma once
// The trajectories of a sweep's jobs, built once per distinct trajectory and shared read-only by
// the jobs that use it. A trajectory is a pure function of the model's content and the
// configuration keys the engine names trajectory inputs (is_trajectory_input,
// engine/experiment/heldout_evaluation.hpp), so those two make its key; run_experiment on a shared
// build gives the same outcome, bit for bit, as building in the job.
#include "engine/experiment/heldout_evaluation.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <future>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace armfarm {

/// The trajectory key of a recorded job configuration (with "inputs", or resolved without):
/// canonical JSON of the trajectory-input keys (recorded input paths replaced by their content
/// hash, runner/spec/input_files.hpp) and the model's content hash (its path when unrecorded).
std::string make_trajectory_key(const nlohmann::json& recorded);

/// Bytes held by a build (the sample matrices).
std::size_t calc_trajectory_bytes(const JobTrajectories& trajectories);

/// Builds on first use per key; later and concurrent users of the key wait for that build and
/// share it. Keeps the most recently used builds up to `byte_budget` bytes (a build in use stays
/// alive with its users). A build that throws is not kept: every waiter gets the exception.
/// Thread-safe.
class TrajectoryCache {
 public:
  static constexpr std::size_t kDefaultByteBudget = std::size_t{512} << 20;  ///< 512 MiB
  explicit TrajectoryCache(std::size_t byte_budget = kDefaultByteBudget) : byte_budget_(byte_budget) {}

  using Build = std::function<JobTrajectories()>;
  std::shared_ptr<const JobTrajectories> get(const std::string& key, const Build& build);

  long builds() const;  ///< builds started so far (for tests and diagnostics)

 private:
  using Shared = std::shared_future<std::shared_ptr<const JobTrajectories>>;
  struct Entry {
    Shared value;
    std::size_t bytes = 0;  ///< 0 while building
    std::list<std::string>::iterator recent;
  };
  void evict_over_budget();  ///< under mutex_

  const std::size_t byte_budget_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
  std::list<std::string> recent_;  ///< most recently used first
  std::size_t bytes_ = 0;
  long builds_ = 0;
};

}  // namespace armfarm
