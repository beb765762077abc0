#pragma once
// From the experiment job's JobOutcome to the store's JobResultRecord (engine/ and results/
// do not know each other; the runner translates).
#include "engine/experiment/job_outcome.hpp"
#include "results/results_store.hpp"

#include <string>
#include <vector>

namespace armfarm {

/// "xxh3-128:<32 hex>": the hash a stored model is known by (in `models`, in job keys).
std::string make_stored_model_hash(const std::string& bytes);

/// Moves the outcome's metrics, series and model file into a record of one attempt of job `key`.
JobResultRecord make_job_result_record(const std::string& key, JobOutcome outcome, double wall_seconds,
                                       const std::string& started_at, const std::string& finished_at);

/// The engine's metric catalog as the store's `metric_info` rows.
std::vector<MetricInfoRecord> make_metric_info_records();

}  // namespace armfarm
