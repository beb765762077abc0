// Damaged databases are refused with the file named, before anything is written: a table or
// column removed (refused at open), rows armfarm never writes (dangling references, broken
// JSON, a text where a number belongs, a series blob that does not decode) found by
// check_contents and refused by merge, and typed reads that never coerce 'abc' to 0.
#include "results/readable_check.hpp"
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"
#include "support/test_database.hpp"
#include <sqlite3.h>

#include <sys/mount.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include <filesystem>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class DamagedDatabaseTest : public test_support::ScratchFolderTest {
 protected:
  DamagedDatabaseTest() : ScratchFolderTest("damaged") {}
  void SetUp() override { write_sound_database(path("sound.db")); }

  // Two jobs of one sweep, one done with metrics and a series.
  static void write_sound_database(const std::string& file) {
    ResultsStore store = ResultsStore::open(file, ResultsStore::Mode::read_write);
    const SweepRegistration sweep = testing::make_sweep_registration("s");
    std::vector<JobRegistration> jobs = {{"0123456789abcdef0123456789abcdef", {{"a", 1}}, {{"a", 1}}, 1},
                                         {"fedcba9876543210fedcba9876543210", {{"a", 2}}, {{"a", 2}}, 2}};
    const RegisteredRun run = store.insert_sweep_run(sweep, jobs);
    JobResultRecord result;
    result.key = jobs[0].key;
    result.status = "done";
    result.end_time = 1.0;
    result.wall_seconds = 0.5;
    result.started_at = result.finished_at = make_utc_timestamp();
    result.metrics = {{0, "tracking_nmse", 1, 0.25, ""}};
    Eigen::MatrixXd rows(2, 2);
    rows << 0.0, 1.0, 0.1, 2.0;
    result.series = {{0, "POS", {"t", "q1"}, rows}};
    store.insert_job_batch({{jobs[0].key}, {result}, {}}, "s");
    store.update_run_finished(run.run_id, "complete", 1, 0, make_utc_timestamp());
  }

  // Copies the sound file and changes it with plain sqlite3, as a careless script would
  // (foreign keys off, as the sqlite3 shell has them).
  std::string damage(const std::string& sql) {
    const std::string file = path("damaged.db");
    fs::remove(file);
    fs::copy_file(path("sound.db"), file);
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open(file.c_str(), &db), SQLITE_OK);
    char* error = nullptr;
    EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << (error ? error : "");
    sqlite3_free(error);
    sqlite3_close(db);
    return file;
  }

  // The message of the StoreError `action` throws ("" when it does not throw).
  template <typename Action>
  static std::string error_of(Action action) {
    try {
      action();
    } catch (const StoreError& e) {
      return e.what();
    }
    return "";
  }

  // Merging `damaged` into a fresh output fails naming `damaged` and leaves the output empty.
  void expect_merge_refused(const std::string& damaged, const std::string& expected_problem) {
    const std::string out = path("out.db");
    fs::remove(out);
    ResultsStore store = ResultsStore::open(out, ResultsStore::Mode::read_write);
    const std::string message = error_of([&] { store.merge_from(damaged); });
    EXPECT_EQ(message.rfind(damaged + ": damaged armfarm database: ", 0), 0u) << message;
    EXPECT_NE(message.find(expected_problem), std::string::npos) << message;
    EXPECT_TRUE(store.find_sweeps().empty());
    EXPECT_TRUE(store.find_job_keys("").empty());
  }
};

TEST_F(DamagedDatabaseTest, ASoundFileHasNoFindingsAndVerifies) {
  const ResultsStore store = ResultsStore::open(path("sound.db"), ResultsStore::Mode::read_only);
  EXPECT_TRUE(store.check_contents(true).empty());
  EXPECT_EQ(error_of([&] { ResultsStore::verify_file(path("sound.db")); }), "");
}

TEST_F(DamagedDatabaseTest, AMissingTableOrColumnIsRefusedAtOpen) {
  const std::string no_metrics = damage("DROP TABLE metrics");
  EXPECT_EQ(error_of([&] { ResultsStore::open(no_metrics, ResultsStore::Mode::read_only); }),
            no_metrics + ": damaged armfarm database (schema version " + std::to_string(kResultsSchemaVersion) +
                "): table metrics is missing");
  EXPECT_NE(error_of([&] { ResultsStore::open(no_metrics, ResultsStore::Mode::read_write); }).find("table metrics is missing"),
            std::string::npos);
  const std::string no_seed = damage("DROP VIEW sweep_job_status; DROP VIEW job_metrics; DROP VIEW sweep_s; ALTER TABLE jobs DROP COLUMN message");
  EXPECT_NE(error_of([&] { ResultsStore::open(no_seed, ResultsStore::Mode::read_only); }).find("column jobs.message is missing"),
            std::string::npos);
  const std::string no_view = damage("DROP VIEW job_metrics");
  EXPECT_NE(error_of([&] { ResultsStore::open(no_view, ResultsStore::Mode::read_only); }).find("view job_metrics is missing"),
            std::string::npos);
}

TEST_F(DamagedDatabaseTest, DeletedSweepsLeaveDanglingRowsThatMergeRefuses) {
  const std::string damaged = damage("DELETE FROM sweeps");
  const ResultsStore store = ResultsStore::open(damaged, ResultsStore::Mode::read_only);
  const std::vector<std::string> findings = store.check_contents(false);
  ASSERT_FALSE(findings.empty());
  EXPECT_NE(findings.front().find("refers to a missing row of sweeps"), std::string::npos) << findings.front();
  expect_merge_refused(damaged, "refers to a missing row of sweeps");
}

TEST_F(DamagedDatabaseTest, BrokenStoredJsonIsFoundAndMergeRefusesIt) {
  const std::string damaged = damage("UPDATE jobs SET config = '{'");
  const ResultsStore store = ResultsStore::open(damaged, ResultsStore::Mode::read_only);
  const std::vector<std::string> findings = store.check_contents(false);
  ASSERT_EQ(findings.size(), 2u);  // both jobs
  EXPECT_NE(findings[0].find("config is not a JSON object"), std::string::npos) << findings[0];
  expect_merge_refused(damaged, "config is not a JSON object");
}

// Issue 30, case 6: `status --check` passed a jobs.status of 'weird' (written with the CHECKs off).
TEST_F(DamagedDatabaseTest, AnUnknownStatusValueIsFound) {
  const std::string damaged = damage(
      "PRAGMA ignore_check_constraints = ON; UPDATE jobs SET status = 'weird' WHERE id = 1; "
      "UPDATE runs SET status = 'lost'");
  const ResultsStore store = ResultsStore::open(damaged, ResultsStore::Mode::read_only);
  const std::vector<std::string> findings = store.check_contents(false);
  ASSERT_GE(findings.size(), 2u);
  EXPECT_NE(findings[0].find("status 'weird' is not a job status"), std::string::npos) << findings[0];
  EXPECT_NE(findings[1].find("status 'lost' is not a run status"), std::string::npos) << findings[1];
  expect_merge_refused(damaged, "is not a job status");
}

TEST_F(DamagedDatabaseTest, ATextWhereANumberBelongsIsNeverReadAsZero) {
  // The CHECK constraint refuses the write; a script that switches checks off gets it in.
  EXPECT_NE(error_of([&] {
              sqlite3* db = nullptr;
              sqlite3_open(path("sound.db").c_str(), &db);
              const int rc = sqlite3_exec(db, "UPDATE metrics SET value = 'abc'", nullptr, nullptr, nullptr);
              sqlite3_close(db);
              if (rc != SQLITE_OK) throw StoreError("refused");
            }),
            "");
  const std::string damaged = damage("PRAGMA ignore_check_constraints = ON; UPDATE metrics SET value = 'abc'");
  const ResultsStore store = ResultsStore::open(damaged, ResultsStore::Mode::read_only);
  const JobRecord job = *store.find_job("0123456789abcdef0123456789abcdef");
  EXPECT_EQ(error_of([&] { store.find_metrics(job.id); }),
            damaged + ": damaged armfarm database: column value holds text where a number belongs");
  EXPECT_NE(store.check_contents(false).at(0).find("value is text, not a real or NULL"), std::string::npos);
  expect_merge_refused(damaged, "value is text");

  const std::string end_time = damage("UPDATE jobs SET end_time = 'abc'");
  EXPECT_NE(error_of([&] { ResultsStore::open(end_time, ResultsStore::Mode::read_only).find_jobs("s"); })
                .find("end_time holds text"),
            std::string::npos);
}

TEST_F(DamagedDatabaseTest, ASeriesBlobThatDoesNotDecodeIsFound) {
  const std::string damaged = damage("UPDATE series SET data = x'0011223344'");
  const std::vector<std::string> findings =
      ResultsStore::open(damaged, ResultsStore::Mode::read_only).check_contents(false);
  ASSERT_EQ(findings.size(), 1u);
  EXPECT_NE(findings[0].find("series of job row 1 (POS)"), std::string::npos) << findings[0];
  const std::string wrong_size = damage("UPDATE series SET raw_bytes = 8");
  EXPECT_NE(ResultsStore::open(wrong_size, ResultsStore::Mode::read_only).check_contents(false).at(0).find(
                "rows or raw_bytes disagree"),
            std::string::npos);
  expect_merge_refused(damaged, "series of job row 1 (POS)");
}

// Issue 30, case 6: `table`, `compare` and the other readers read on through metric rows whose
// job was deleted and through a series blob with a flipped bit (0 exit). The readers' check
// (verify_readable: quick_check, then the row checks and every series checksum) refuses both.
TEST_F(DamagedDatabaseTest, ReadersRefuseDanglingMetricsAndAFlippedSeriesBit) {
  EXPECT_EQ(error_of([&] { verify_readable(ResultsStore::open(path("sound.db"), ResultsStore::Mode::read_only)); }), "");

  const std::string dangling = damage("DELETE FROM sweep_jobs WHERE job_id = 1; DELETE FROM jobs WHERE id = 1");
  const std::string message =
      error_of([&] { verify_readable(ResultsStore::open(dangling, ResultsStore::Mode::read_only)); });
  EXPECT_EQ(message.rfind(dangling + ": damaged armfarm database: ", 0), 0u) << message;
  EXPECT_NE(message.find("refers to a missing row of jobs"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  // One bit of the stored frame flipped, in its middle (the samples), with the sqlite3 C API.
  const std::string flipped = damage("SELECT 1");
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(flipped.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* read = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT data FROM series", -1, &read, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(read), SQLITE_ROW);
  const auto* bytes = static_cast<const unsigned char*>(sqlite3_column_blob(read, 0));
  std::vector<unsigned char> blob(bytes, bytes + sqlite3_column_bytes(read, 0));
  sqlite3_finalize(read);
  blob[blob.size() / 2] ^= 0x01;
  sqlite3_stmt* write = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "UPDATE series SET data = ?", -1, &write, nullptr), SQLITE_OK);
  sqlite3_bind_blob(write, 1, blob.data(), static_cast<int>(blob.size()), SQLITE_TRANSIENT);
  EXPECT_EQ(sqlite3_step(write), SQLITE_DONE);
  sqlite3_finalize(write);
  sqlite3_close(db);
  const ResultsStore store = ResultsStore::open(flipped, ResultsStore::Mode::read_only);
  const std::string series_message = error_of([&] { verify_readable(store); });
  EXPECT_NE(series_message.find("series of job row 1 (POS): corrupt series data"), std::string::npos) << series_message;
  const std::optional<JobRecord> job = store.find_job("0123456789abcdef0123456789abcdef");
  ASSERT_TRUE(job);
  EXPECT_NE(error_of([&] { store.find_series(job->id, "POS"); }).find("corrupt series data"), std::string::npos);
}

// Issue 30, case 6: a database on a read-only filesystem could not be read at all ("unable to
// open database file": a WAL reader needs its -shm). It now opens immutable there. The
// read-only filesystem is a read-only bind mount, which needs root (CAP_SYS_ADMIN).
TEST_F(DamagedDatabaseTest, ADatabaseOnAReadOnlyFilesystemIsReadable) {
  const fs::path mounted = folder_ / "ro";
  fs::create_directories(folder_ / "src");
  fs::create_directories(mounted);
  fs::copy_file(path("sound.db"), folder_ / "src" / "results.db");
  if (::mount((folder_ / "src").c_str(), mounted.c_str(), nullptr, MS_BIND, nullptr) != 0) {
    GTEST_SKIP() << "cannot bind-mount (needs root): " << std::strerror(errno);
  }
  const bool read_only = ::mount(nullptr, mounted.c_str(), nullptr, MS_REMOUNT | MS_BIND | MS_RDONLY, nullptr) == 0;
  const std::string file = (mounted / "results.db").string();
  std::string error;
  std::size_t n_sweeps = 0, n_rows = 0;
  try {
    const ResultsStore store = ResultsStore::open(file, ResultsStore::Mode::read_only);
    n_sweeps = store.find_sweeps().size();
    const std::optional<JobRecord> job = store.find_job("0123456789abcdef0123456789abcdef");
    if (job) n_rows = static_cast<std::size_t>(store.find_series(job->id, "POS")->rows.rows());
    EXPECT_TRUE(store.check_contents(true).empty());
  } catch (const StoreError& e) {
    error = e.what();
  }
  // Nothing was created beside the file (the mount refuses it anyway) and nothing can write.
  const bool wrote_beside = fs::exists(folder_ / "src" / "results.db-shm");
  EXPECT_THROW(ResultsStore::open(file, ResultsStore::Mode::read_write), StoreError);
  ::umount(mounted.c_str());
  ASSERT_TRUE(read_only) << "remounting read-only failed";
  EXPECT_EQ(error, "");
  EXPECT_EQ(n_sweeps, 1u);
  EXPECT_EQ(n_rows, 2u);
  EXPECT_FALSE(wrote_beside);
}

}  // namespace
}  // namespace armfarm

namespace armfarm {
namespace {

// Issue 30, case 7: a FIFO given as the database blocked every command in open(); now it is
// refused, read-only and writable, before SQLite opens it (a hang here is ended by ctest's timeout).
TEST(DamagedDatabase, AFifoIsRefusedBeforeItIsOpened) {
  const std::filesystem::path folder = test_support::make_scratch_folder("fifo");
  const std::string fifo = (folder / "results.db").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const ResultsStore::Mode mode : {ResultsStore::Mode::read_only, ResultsStore::Mode::read_write}) {
    try {
      ResultsStore::open(fifo, mode);
      ADD_FAILURE() << "a FIFO was opened";
    } catch (const StoreError& e) {
      EXPECT_EQ(std::string(e.what()), fifo + ": not a regular file (a FIFO, device or socket), not a database file");
    }
  }
  EXPECT_THROW(ResultsStore::verify_file(fifo), StoreError);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace armfarm
