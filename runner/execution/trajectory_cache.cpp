#include "runner/execution/trajectory_cache.hpp"

#include "engine/experiment/job_config.hpp"
#include "runner/spec/canonical_json.hpp"
#include "runner/spec/config_path.hpp"
#include "runner/spec/input_files.hpp"

namespace armfarm {

std::string make_trajectory_key(const nlohmann::json& recorded) {
  const nlohmann::json document = make_job_key_document(recorded);  // recorded paths → content hashes
  nlohmann::json key = nlohmann::json::object();
  for (const JobConfigKey& config_key : job_config_keys()) {
    if (!is_trajectory_input(config_key.path)) continue;
    std::string problem;
    const nlohmann::json* value = find_config_element(document, parse_config_path(config_key.path), problem);
    key[config_key.path] = value ? *value : nlohmann::json();
  }
  const auto model = document.find("model");
  key["model"] = model != document.end() ? *model : nlohmann::json();
  return calc_canonical_json(key);
}

std::size_t calc_trajectory_bytes(const JobTrajectories& trajectories) {
  const auto bytes = [](const JointTrajectory& t) {
    return sizeof(double) * static_cast<std::size_t>(t.q.size() + t.qd.size() + t.qdd.size() + t.task_position.size()) +
           sizeof(int) * t.segment_starts.size();
  };
  return bytes(trajectories.training) + (trajectories.heldout ? bytes(*trajectories.heldout) : 0);
}

std::shared_ptr<const JobTrajectories> TrajectoryCache::get(const std::string& key, const Build& build) {
  std::promise<std::shared_ptr<const JobTrajectories>> promise;
  Shared value;
  bool builds_here = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto found = entries_.find(key);
    if (found != entries_.end()) {
      recent_.splice(recent_.begin(), recent_, found->second.recent);
      value = found->second.value;
    } else {
      recent_.push_front(key);
      Entry entry;
      entry.value = promise.get_future().share();
      entry.recent = recent_.begin();
      value = entry.value;
      entries_.emplace(key, std::move(entry));
      ++builds_;
      builds_here = true;
    }
  }
  if (!builds_here) return value.get();  // waits for a build in progress; rethrows its failure

  std::shared_ptr<const JobTrajectories> built;
  try {
    built = std::make_shared<const JobTrajectories>(build());
  } catch (...) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const auto found = entries_.find(key);
      recent_.erase(found->second.recent);
      entries_.erase(found);
    }
    promise.set_exception(std::current_exception());
    throw;
  }
  promise.set_value(built);
  std::lock_guard<std::mutex> lock(mutex_);
  Entry& entry = entries_.at(key);
  entry.bytes = calc_trajectory_bytes(*built);
  bytes_ += entry.bytes;
  evict_over_budget();
  return built;
}

void TrajectoryCache::evict_over_budget() {
  // From the least recently used; builds in progress (bytes 0) and the newest entry stay.
  auto it = recent_.end();
  while (bytes_ > byte_budget_ && it != recent_.begin()) {
    --it;
    if (it == recent_.begin()) break;
    const auto found = entries_.find(*it);
    if (found->second.bytes == 0) continue;
    bytes_ -= found->second.bytes;
    entries_.erase(found);
    it = recent_.erase(it);
  }
}

long TrajectoryCache::builds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return builds_;
}

}  // namespace armfarm
