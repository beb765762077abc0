#pragma once
// Internal to results/: the `models` table (results/README.md; created by migration 3 in
// store_schema.cpp), the learned model a job stored, one row per job, its bytes as a BLOB with
// their hash. The ResultsStore methods that read it are in model_store.cpp; this helper is what
// the writes call inside their transaction.
#include "results/results_store.hpp"

#include <cstdint>

namespace armfarm {

class SqliteConnection;

/// Replaces the job's stored model with `model` (none: deletes it), in the caller's transaction.
void replace_job_model(SqliteConnection& db, std::int64_t job_id, const std::optional<StoredModelRecord>& model);

}  // namespace armfarm
