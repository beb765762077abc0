// The store's handle: opening, the schema version, integrity. Reads, writes, views, merge and
// the schema live in store_reads.cpp, store_writes.cpp, sweep_views.cpp, store_merge.cpp and
// store_schema.cpp.
#include "results/results_store.hpp"

#include "results/store_internal.hpp"

#include <chrono>
#include <cstdio>
#include <ctime>

namespace armfarm {

using namespace store_detail;

std::string make_utc_timestamp() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const auto millis =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%S", &utc);
  char result[40];
  std::snprintf(result, sizeof result, "%s.%03dZ", buffer, static_cast<int>(millis));
  return result;
}

ResultsStore::ResultsStore(std::string path, std::unique_ptr<SqliteConnection> connection)
    : path_(std::move(path)), db_(std::move(connection)) {}
ResultsStore::ResultsStore(ResultsStore&&) noexcept = default;
ResultsStore& ResultsStore::operator=(ResultsStore&&) noexcept = default;
ResultsStore::~ResultsStore() = default;

ResultsStore ResultsStore::open(const std::string& path, Mode mode) {
  return ResultsStore(path, open_checked(path, mode));
}

int ResultsStore::schema_version() const { return static_cast<int>(db_->query_int("PRAGMA user_version")); }

std::string ResultsStore::check_integrity(bool quick) const {
  SqliteStatement statement = db_->prepare(quick ? "PRAGMA quick_check" : "PRAGMA integrity_check");
  std::string findings;
  while (statement.step()) findings += (findings.empty() ? "" : "\n") + statement.column_text(0);
  return findings;
}

}  // namespace armfarm
