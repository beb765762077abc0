// The `models` table: a job's learned model (the learner's versioned model file) as a BLOB.
#include "results/model_store.hpp"

#include "results/sqlite_connection.hpp"

namespace armfarm {
namespace {

std::vector<unsigned char> make_blob(const std::string& bytes) { return {bytes.begin(), bytes.end()}; }

}  // namespace

void replace_job_model(SqliteConnection& db, std::int64_t job_id, const std::optional<StoredModelRecord>& model) {
  db.prepare("DELETE FROM models WHERE job_id = ?").bind(1, job_id).execute();
  if (!model) return;
  if (model->data.empty()) throw StoreError(db.path() + ": job " + std::to_string(job_id) + ": an empty model file");
  db.prepare("INSERT INTO models (job_id, kind, hash, bytes, data) VALUES (?, ?, ?, ?, ?)")
      .bind(1, job_id)
      .bind(2, model->kind)
      .bind(3, model->hash)
      .bind(4, static_cast<std::int64_t>(model->data.size()))
      .bind(5, make_blob(model->data))
      .execute();
}

std::optional<StoredModelRecord> ResultsStore::find_job_model(std::int64_t job_id) const {
  SqliteStatement statement = db_->prepare("SELECT kind, hash, data FROM models WHERE job_id = ?");
  statement.bind(1, job_id);
  if (!statement.step()) return std::nullopt;
  StoredModelRecord record;
  record.kind = statement.column_text(0);
  record.hash = statement.column_text(1);
  const std::vector<unsigned char> blob = statement.column_blob(2);
  record.data.assign(blob.begin(), blob.end());
  return record;
}

std::vector<StoredModelInfo> ResultsStore::find_sweep_models(const std::string& sweep) const {
  SqliteStatement statement = db_->prepare(
      "SELECT j.key, m.kind, m.hash, m.bytes FROM sweep_jobs sj JOIN sweeps s ON s.id = sj.sweep_id "
      "JOIN jobs j ON j.id = sj.job_id JOIN models m ON m.job_id = j.id WHERE s.name = ? ORDER BY sj.position");
  statement.bind(1, sweep);
  std::vector<StoredModelInfo> models;
  while (statement.step()) {
    models.push_back({statement.column_text(0), statement.column_text(1), statement.column_text(2), statement.column_int(3)});
  }
  return models;
}

}  // namespace armfarm
