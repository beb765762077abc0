#pragma once
// The learned models that jobs stored in a results database (table `models`, written with
// learning.store_model), as later jobs name them in learning.initial_model:
//   {"job": "3f2a1b7c"}                                  a job key (or a unique prefix of one)
//   {"sweep": "reach_train", "params": {"seed": 2}}      the one job of that sweep whose swept
//                                                        values include these (params optional)
// A reference is resolved when the sweep expands: the configuration then names the model by its
// hash ("stored:xxh3-128:<hash>", so the hash is part of the job key) and records the source
// job under inputs["learning.initial_model (stored)"]; the bytes stay here, by hash, for the jobs
// that start from them. Thread-safe.
#include <nlohmann/json.hpp>

#include <map>
#include <mutex>
#include <string>

namespace armfarm {

/// The prefix of learning.initial_model once a stored model is resolved.
inline constexpr const char* kStoredModelPrefix = "stored:";

class StoredModels {
 public:
  /// Models of the database at `db_path` ("": none; every reference then fails).
  explicit StoredModels(std::string db_path) : db_path_(std::move(db_path)) {}

  struct Resolved {
    std::string job_key;  ///< the full key of the job that stored the model
    std::string hash;     ///< "xxh3-128:<32 hex digits>"
  };
  /// Resolves a reference (forms above) and keeps the model's bytes. Throws std::runtime_error
  /// with a one-line message: a malformed reference, no database, no or several matching jobs,
  /// a job not done or without a stored model, a model whose bytes do not match its hash.
  Resolved resolve(const nlohmann::json& reference);

  /// The bytes of a model resolved before, by hash; throws std::runtime_error if none was.
  std::string find_bytes(const std::string& hash) const;

  const std::string& db_path() const { return db_path_; }

 private:
  std::string db_path_;
  mutable std::mutex mutex_;
  std::map<std::string, std::string> bytes_by_hash_;
};

/// Rewrites config["learning"]["initial_model"] when it is a reference object (resolved by
/// `models`, or an error when `models` is null) as described above; leaves any other value alone.
/// Throws std::runtime_error "learning.initial_model: ...".
void resolve_stored_model_reference(nlohmann::json& config, StoredModels* models);

}  // namespace armfarm
