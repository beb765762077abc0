#include "runner/execution/stored_models.hpp"

#include "runner/spec/config_error.hpp"

#include "results/results_store.hpp"
#include "runner/execution/outcome_record.hpp"

#include <filesystem>
#include <stdexcept>

namespace armfarm {
namespace {

std::string describe(const nlohmann::json& reference) { return reference.dump(); }

// Whether every swept value `wanted` names is the job's (numbers compare by value: 25 == 25.0).
bool has_params(const nlohmann::json& job_params, const nlohmann::json& wanted) {
  for (const auto& [path, value] : wanted.items()) {
    const auto found = job_params.find(path);
    if (found == job_params.end() || *found != value) return false;
  }
  return true;
}

}  // namespace

StoredModels::Resolved StoredModels::resolve(const nlohmann::json& reference) {
  if (!reference.is_object()) throw std::runtime_error("a stored-model reference is an object, {\"job\": KEY} or {\"sweep\": NAME, \"params\": {...}}");
  for (const auto& [name, value] : reference.items()) {
    if (name != "job" && name != "sweep" && name != "params") {
      throw std::runtime_error(describe(reference) + ": unknown key \"" + name + "\" (a stored-model reference has job, or sweep and params)");
    }
  }
  const bool by_job = reference.contains("job"), by_sweep = reference.contains("sweep");
  if (by_job == by_sweep) throw std::runtime_error(describe(reference) + ": give either \"job\" or \"sweep\"");
  if (by_job && (!reference["job"].is_string() || reference["job"].get<std::string>().size() < 4)) {
    throw std::runtime_error(describe(reference) + ": \"job\" is a job key or a prefix of at least 4 hex digits");
  }
  if (by_sweep && (!reference["sweep"].is_string() || reference["sweep"].get<std::string>().empty())) {
    throw std::runtime_error(describe(reference) + ": \"sweep\" is a sweep name");
  }
  if (reference.contains("params") && (!by_sweep || !reference["params"].is_object())) {
    throw std::runtime_error(describe(reference) + ": \"params\" is an object of swept values and goes with \"sweep\"");
  }
  if (db_path_.empty()) throw std::runtime_error(describe(reference) + ": a stored model needs a results database (--db of armfarm run, expand or job)");
  if (!std::filesystem::exists(db_path_)) throw std::runtime_error(describe(reference) + ": " + db_path_ + ": no such database file");

  const ResultsStore store = ResultsStore::open(db_path_, ResultsStore::Mode::read_only);
  std::optional<JobRecord> job;
  if (by_job) {
    const std::vector<std::string> keys = store.find_job_keys(reference["job"].get<std::string>());
    if (keys.empty()) throw std::runtime_error(describe(reference) + ": " + db_path_ + " has no job with that key");
    if (keys.size() > 1) throw std::runtime_error(describe(reference) + ": " + std::to_string(keys.size()) + " jobs of " + db_path_ + " start with that key");
    job = store.find_job(keys.front());
  } else {
    const std::string sweep = reference["sweep"].get<std::string>();
    if (!store.find_sweep(sweep)) throw std::runtime_error(describe(reference) + ": " + db_path_ + " has no sweep " + sweep);
    const nlohmann::json wanted = reference.value("params", nlohmann::json::object());
    std::vector<JobRecord> matches;
    for (JobRecord& candidate : store.find_jobs(sweep)) {
      if (has_params(candidate.params, wanted)) matches.push_back(std::move(candidate));
    }
    if (matches.size() != 1) {
      throw std::runtime_error(describe(reference) + ": " + std::to_string(matches.size()) + " jobs of sweep " + sweep +
                               " match these params (one must; add the swept values that tell them apart)");
    }
    job = std::move(matches.front());
  }
  if (!job) throw std::runtime_error(describe(reference) + ": the job vanished from " + db_path_);
  if (job->status != "done") {
    throw std::runtime_error(describe(reference) + ": job " + job->key.substr(0, 8) + " is " + job->status + ", not done (run its sweep first)");
  }
  std::optional<StoredModelRecord> model = store.find_job_model(job->id);
  if (!model) {
    throw std::runtime_error(describe(reference) + ": job " + job->key.substr(0, 8) +
                             " stored no model (its sweep needs learning.store_model: true)");
  }
  if (make_stored_model_hash(model->data) != model->hash) {
    throw std::runtime_error(describe(reference) + ": the model of job " + job->key.substr(0, 8) + " in " + db_path_ +
                             " does not match its stored hash (corrupt database)");
  }
  std::lock_guard<std::mutex> lock(mutex_);
  bytes_by_hash_[model->hash] = std::move(model->data);
  return {job->key, model->hash};
}

std::string StoredModels::find_bytes(const std::string& hash) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto found = bytes_by_hash_.find(hash);
  if (found == bytes_by_hash_.end()) {
    throw std::runtime_error("stored model " + hash + " is not loaded (a stored model is resolved from the results database when the sweep expands)");
  }
  return found->second;
}

void resolve_stored_model_reference(nlohmann::json& config, StoredModels* models) {
  if (!config.contains("learning") || !config["learning"].is_object()) return;
  nlohmann::json& value = config["learning"]["initial_model"];
  if (value.is_null()) {
    config["learning"].erase("initial_model");
    return;
  }
  if (!value.is_object()) return;
  try {
    if (models == nullptr) throw std::runtime_error("a stored model needs a results database (--db of armfarm run, expand or job)");
    const StoredModels::Resolved resolved = models->resolve(value);
    config["inputs"]["learning.initial_model (stored)"] = {
        {"kind", "stored_model"}, {"reference", value}, {"job", resolved.job_key}, {"hash", resolved.hash}};
    value = std::string(kStoredModelPrefix) + resolved.hash;
  } catch (const std::runtime_error& error) {
    throw ConfigError("learning.initial_model", error.what());
  }
}

}  // namespace armfarm
