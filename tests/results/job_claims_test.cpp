// Job claims in the store, with the times given explicitly: one live claim per job, a fresh
// claim of another owner blocks, a stale one is taken over (marked interrupted with its run),
// heartbeats keep a claim fresh, a result releases its claim in the same transaction, abandoning
// a job another runner took over leaves it running there; and several connections creating one
// fresh file at once create the schema once.
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"
#include <sqlite3.h>

#include <atomic>
#include <filesystem>
#include <thread>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

std::string query_text(const std::string& db_path, const std::string& sql) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  std::string text;
  while (sqlite3_step(statement) == SQLITE_ROW) {
    const unsigned char* value = sqlite3_column_text(statement, 0);
    text += (text.empty() ? "" : ",") + std::string(value ? reinterpret_cast<const char*>(value) : "NULL");
  }
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return text;
}

class JobClaimsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = test_support::make_scratch_folder("claims_store");
    db_ = (folder_ / "claims.db").string();
    ResultsStore store = ResultsStore::open(db_, ResultsStore::Mode::read_write);
    SweepRegistration sweep;
    sweep.name = "s";
    sweep.spec_text = "{}";
    sweep.spec_hash = "h";
    sweep.started_at = "2026-01-01T00:00:00.000Z";
    store.update_lease_seconds(5.0, sweep.started_at);  // the file's lease, for every owner
    for (int runner = 0; runner < 2; ++runner) {
      run_ids_[runner] = store.insert_sweep_run(sweep, {{"k1", {}, {}, 0}, {"k2", {}, {}, 0}}).run_id;
      owners_[runner] = {"owner" + std::to_string(runner), "host", 100 + runner, run_ids_[runner], "s"};
    }
  }
  void TearDown() override { fs::remove_all(folder_); }
  ResultsStore open() const { return ResultsStore::open(db_, ResultsStore::Mode::read_write); }

  fs::path folder_;
  std::string db_;
  std::int64_t run_ids_[2] = {};
  ClaimOwner owners_[2];
};

TEST_F(JobClaimsTest, AFreshClaimBlocksAndAStaleOneIsTakenOver) {
  ResultsStore store = open();
  const ClaimAttempt first = store.claim_job("k1", owners_[0], "2026-01-01T00:00:10.000Z");
  EXPECT_EQ(first.result, ClaimResult::claimed);
  EXPECT_EQ(store.find_job("k1")->status, "running");
  EXPECT_EQ(store.find_job("k1")->attempts, 1);
  // 4.9 s later the claim is fresh: the other runner must leave it.
  const ClaimAttempt blocked = store.claim_job("k1", owners_[1], "2026-01-01T00:00:14.900Z");
  EXPECT_EQ(blocked.result, ClaimResult::claimed_elsewhere);
  EXPECT_EQ(blocked.other_owner, "owner0");
  // A heartbeat at 14 s keeps it fresh at 18 s.
  EXPECT_EQ(store.refresh_claims(owners_[0], "2026-01-01T00:00:14.000Z"), std::vector<std::string>{"k1"});
  EXPECT_EQ(store.claim_job("k1", owners_[1], "2026-01-01T00:00:18.000Z").result, ClaimResult::claimed_elsewhere);
  // 5.5 s after the last heartbeat it is stale: taken over, the old claim and its run interrupted.
  const ClaimAttempt taken = store.claim_job("k1", owners_[1], "2026-01-01T00:00:19.500Z");
  EXPECT_EQ(taken.result, ClaimResult::claimed);
  EXPECT_EQ(taken.taken_over, "owner0");
  EXPECT_EQ(store.find_job("k1")->attempts, 2);
  const std::vector<JobClaimRecord> claims = store.find_job_claims("2026-01-01T00:00:20.000Z", false);
  ASSERT_EQ(claims.size(), 2u);
  EXPECT_EQ(claims[0].state, "live");
  EXPECT_EQ(claims[0].owner, "owner1");
  EXPECT_EQ(claims[0].pid, 101);
  EXPECT_NEAR(claims[0].heartbeat_age_seconds, 0.5, 1e-3);  // julianday() keeps about 10 µs
  EXPECT_EQ(claims[1].state, "interrupted");
  EXPECT_EQ(claims[1].owner, "owner0");
  EXPECT_EQ(query_text(db_, "SELECT status FROM runs WHERE id = " + std::to_string(run_ids_[0])), "interrupted");
  EXPECT_EQ(query_text(db_, "SELECT status FROM runs WHERE id = " + std::to_string(run_ids_[1])), "running");
  // The first owner lost it: its heartbeat no longer lists the job.
  EXPECT_TRUE(store.refresh_claims(owners_[0], "2026-01-01T00:00:21.000Z").empty());
}

TEST_F(JobClaimsTest, AResultReleasesItsClaimAndADoneJobIsNotClaimedAgain) {
  ResultsStore store = open();
  ASSERT_EQ(store.claim_job("k1", owners_[0], "2026-01-01T00:00:10.000Z").result, ClaimResult::claimed);
  JobBatch batch;
  batch.claim_owner = "owner0";
  JobResultRecord result;
  result.key = "k1";
  result.status = "done";
  result.started_at = "2026-01-01T00:00:10.000Z";
  result.finished_at = "2026-01-01T00:00:11.000Z";
  result.claim_generation = 1;  // the job's first claim
  batch.finished.push_back(result);
  EXPECT_TRUE(store.insert_job_batch(batch, "s").empty());
  EXPECT_TRUE(store.find_job_claims("2026-01-01T00:00:12.000Z", false).empty());
  EXPECT_EQ(store.claim_job("k1", owners_[1], "2026-01-01T00:00:12.000Z").result, ClaimResult::done);
  // --force: done before this run started (12 s) is claimed again; done after it is not.
  EXPECT_EQ(store.claim_job("k1", owners_[1], "2026-01-01T00:00:12.000Z", "2026-01-01T00:00:10.500Z").result,
            ClaimResult::done);
  EXPECT_EQ(store.claim_job("k1", owners_[1], "2026-01-01T00:00:12.000Z", "2026-01-01T00:00:11.500Z").result,
            ClaimResult::claimed);
}

// Issue 30, case 1 in the store: the paused owner's result arrives after the take-over and is
// discarded by the fence, whatever it says, in the same transaction as the new owner's result
// that commits; a claim's token grows with every claim; a token from an earlier claim of the
// same owner does not pass either.
TEST_F(JobClaimsTest, AResultUnderATakenOverClaimIsDiscardedByTheFence) {
  ResultsStore store = open();
  const ClaimAttempt first = store.claim_job("k1", owners_[0], "2026-01-01T00:00:10.000Z");
  ASSERT_EQ(first.result, ClaimResult::claimed);
  EXPECT_EQ(first.generation, 1);
  const ClaimAttempt second = store.claim_job("k1", owners_[1], "2026-01-01T00:00:16.000Z");  // 6 s > 5 s lease
  ASSERT_EQ(second.result, ClaimResult::claimed);
  EXPECT_EQ(second.generation, 2);
  const auto make_result = [](const std::string& status, std::int64_t generation) {
    JobResultRecord result;
    result.key = "k1";
    result.status = status;
    result.started_at = "2026-01-01T00:00:10.000Z";
    result.finished_at = "2026-01-01T00:00:20.000Z";
    result.claim_generation = generation;
    result.metrics.push_back({0, "m", std::nullopt, status == "done" ? 1.0 : 2.0, "", std::nullopt});
    return result;
  };
  JobBatch winner;
  winner.claim_owner = "owner1";
  winner.finished.push_back(make_result("done", second.generation));
  EXPECT_TRUE(store.insert_job_batch(winner, "s").empty());
  // The paused owner wakes up with a timeout (as `--timeout` makes it) and with a done result.
  for (const std::string status : {"timeout", "done"}) {
    JobBatch stale;
    stale.claim_owner = "owner0";
    stale.finished.push_back(make_result(status, first.generation));
    EXPECT_EQ(store.insert_job_batch(stale, "s"), std::vector<std::string>{"k1"}) << status;
  }
  const JobRecord job = *store.find_job("k1");
  EXPECT_EQ(job.status, "done");
  const std::vector<MetricRecord> metrics = store.find_metrics(job.id);
  ASSERT_EQ(metrics.size(), 1u);
  EXPECT_EQ(metrics[0].value, 1.0);  // the winner's, not overwritten
  // A forced rerun by owner0 gets token 3; its old token 1 still does not pass.
  const ClaimAttempt third = store.claim_job("k1", owners_[0], "2026-01-01T00:00:30.000Z", "2026-01-01T00:00:29.000Z");
  ASSERT_EQ(third.result, ClaimResult::claimed);
  EXPECT_EQ(third.generation, 3);
  JobBatch old_token;
  old_token.claim_owner = "owner0";
  old_token.finished.push_back(make_result("timeout", first.generation));
  EXPECT_EQ(store.insert_job_batch(old_token, "s"), std::vector<std::string>{"k1"});
  EXPECT_EQ(store.find_job("k1")->status, "running");
}

TEST_F(JobClaimsTest, TheLeaseIsTheFilesAndChangesWithOneCall) {
  ResultsStore store = open();
  EXPECT_EQ(store.find_lease_seconds(), 5.0);
  ASSERT_EQ(store.claim_job("k1", owners_[0], "2026-01-01T00:00:10.000Z").result, ClaimResult::claimed);
  // 8 s without a heartbeat: fresh under a 10 s lease, stale under the 5 s one.
  store.update_lease_seconds(10.0, "2026-01-01T00:00:11.000Z");
  EXPECT_EQ(store.claim_job("k1", owners_[1], "2026-01-01T00:00:18.000Z").result, ClaimResult::claimed_elsewhere);
  store.update_lease_seconds(5.0, "2026-01-01T00:00:12.000Z");
  EXPECT_EQ(store.claim_job("k1", owners_[1], "2026-01-01T00:00:18.000Z").result, ClaimResult::claimed);
  EXPECT_THROW(store.update_lease_seconds(0.0, "2026-01-01T00:00:12.000Z"), StoreError);
  EXPECT_THROW(store.update_lease_seconds(-1.0, "2026-01-01T00:00:12.000Z"), StoreError);
  EXPECT_EQ(store.find_lease_seconds(), 5.0);
  // A fresh file starts at 60 s.
  const std::string other = (folder_ / "fresh.db").string();
  EXPECT_EQ(ResultsStore::open(other, ResultsStore::Mode::read_write).find_lease_seconds(), 60.0);
}

TEST_F(JobClaimsTest, AbandoningATakenOverJobLeavesItRunningForItsNewOwner) {
  ResultsStore store = open();
  ASSERT_EQ(store.claim_job("k1", owners_[0], "2026-01-01T00:00:10.000Z").result, ClaimResult::claimed);
  ASSERT_EQ(store.claim_job("k1", owners_[1], "2026-01-01T00:00:20.000Z").result, ClaimResult::claimed);
  JobBatch late;  // the first owner stops it after all
  late.claim_owner = "owner0";
  late.abandoned.push_back("k1");
  store.insert_job_batch(late, "s");
  EXPECT_EQ(store.find_job("k1")->status, "running");
  ASSERT_EQ(store.find_job_claims("2026-01-01T00:00:21.000Z").size(), 1u);
  JobBatch own;  // its owner's own abandonment puts it back to pending
  own.claim_owner = "owner1";
  own.abandoned.push_back("k1");
  store.insert_job_batch(own, "s");
  EXPECT_EQ(store.find_job("k1")->status, "pending");
  EXPECT_TRUE(store.find_job_claims("2026-01-01T00:00:21.000Z").empty());
}

TEST_F(JobClaimsTest, TheStartOfARunInterruptsStaleClaimsRunsAndOrphanedJobs) {
  ResultsStore store = open();
  ASSERT_EQ(store.claim_job("k1", owners_[0], "2026-01-01T00:00:10.000Z").result, ClaimResult::claimed);
  store.refresh_claims(owners_[0], "2026-01-01T00:00:10.000Z");
  store.refresh_claims(owners_[1], "2026-01-01T00:00:18.000Z");
  // k2 "running" with no claim: left by a build without claims.
  {
    JobBatch legacy;
    legacy.started.push_back("k2");
    store.insert_job_batch(legacy, "s");
  }
  EXPECT_EQ(store.find_job("k2")->status, "running");
  const StaleClaimReport report = store.interrupt_stale_claims("2026-01-01T00:00:20.000Z", "owner1");
  EXPECT_EQ(report.claims_interrupted, 1);
  EXPECT_EQ(report.runs_interrupted, 0);  // run 0 already interrupted through its claim; run 1 is fresh
  EXPECT_EQ(store.find_job("k1")->status, "pending");
  EXPECT_EQ(store.find_job("k2")->status, "pending");
  EXPECT_EQ(query_text(db_, "SELECT status FROM runs ORDER BY id"), "interrupted,running");
  EXPECT_EQ(query_text(db_, "SELECT interrupted_by FROM job_claims"), "owner1");
  // Run 1 stops refreshing: 30 s later its row is interrupted too.
  EXPECT_EQ(store.interrupt_stale_claims("2026-01-01T00:00:48.000Z", "owner2").runs_interrupted, 1);
}

TEST(JobClaimsSchema, ConnectionsCreatingOneFreshFileAtOnceCreateTheSchemaOnce) {
  const fs::path folder = fs::temp_directory_path() / ("armfarm_fresh_" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  for (int trial = 0; trial < 5; ++trial) {
    const std::string db = (folder / ("fresh" + std::to_string(trial) + ".db")).string();
    std::atomic<bool> go{false};
    std::atomic<int> failures{0};
    std::vector<std::thread> threads;
    for (int i = 0; i < 4; ++i) {
      threads.emplace_back([&] {
        while (!go.load()) std::this_thread::yield();
        try {
          ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_write);
          if (store.schema_version() != kResultsSchemaVersion) ++failures;
        } catch (const StoreError& e) {
          ADD_FAILURE() << e.what();
          ++failures;
        }
      });
    }
    go = true;
    for (std::thread& t : threads) t.join();
    EXPECT_EQ(failures.load(), 0);
    EXPECT_EQ(query_text(db, "SELECT count(*) FROM sqlite_master WHERE name = 'sweeps'"), "1");
  }
  fs::remove_all(folder);
}

}  // namespace
}  // namespace armfarm

namespace armfarm {
namespace {

// Schema 4 -> 5 (issue 30): a version 4 file, made here by undoing migration 5 by hand on a
// fresh file with one live claim (and undoing migration 6, the search tables), reads through a migrated copy and migrates when written: the
// lease starts at 60 s, existing claims and jobs carry token 0, and the next claim of a job
// gets token 1; the job's data stays as it was.
TEST(JobClaimsSchema, VersionFourMigratesToFencedClaims) {
  const fs::path folder = test_support::make_scratch_folder("claims_v4");
  const std::string db = (folder / "v4.db").string();
  {
    ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_write);
    SweepRegistration sweep;
    sweep.name = "s";
    sweep.spec_text = "{}";
    sweep.spec_hash = "h";
    sweep.started_at = "2026-01-01T00:00:00.000Z";
    const std::int64_t run = store.insert_sweep_run(sweep, {{"k1", nlohmann::json::object(), nlohmann::json::object(), 0},
                                                           {"k2", nlohmann::json::object(), nlohmann::json::object(), 0}})
                                .run_id;
    ASSERT_EQ(store.claim_job("k1", {"old", "host", 1, run, "s"}, "2026-01-01T00:00:01.000Z").result,
              ClaimResult::claimed);
  }
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &raw), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(raw,
                         "DROP VIEW search_promotions; DROP TABLE search_steps; DROP TABLE search_trials; "
                         "DROP TABLE search_rungs; DROP TABLE searches; "
                         "DROP TABLE claim_lease; ALTER TABLE jobs DROP COLUMN claim_generation; "
                         "ALTER TABLE job_claims DROP COLUMN generation; PRAGMA user_version = 4;",
                         nullptr, nullptr, nullptr),
            SQLITE_OK)
      << sqlite3_errmsg(raw);
  sqlite3_close(raw);
  {
    const ResultsStore reader = ResultsStore::open(db, ResultsStore::Mode::read_only);
    EXPECT_EQ(reader.schema_version(), kResultsSchemaVersion);
    EXPECT_EQ(reader.find_lease_seconds(), 60.0);
  }
  EXPECT_EQ(query_text(db, "PRAGMA user_version"), "4");  // reading left the file as it was
  {
    ResultsStore writer = ResultsStore::open(db, ResultsStore::Mode::read_write);
    EXPECT_EQ(writer.schema_version(), kResultsSchemaVersion);
    EXPECT_EQ(writer.find_lease_seconds(), 60.0);
    EXPECT_EQ(query_text(db, "SELECT key || ':' || status || ':' || claim_generation FROM jobs ORDER BY key"),
              "k1:running:0,k2:pending:0");
    EXPECT_EQ(query_text(db, "SELECT owner || ':' || generation FROM job_claims"), "old:0");
    const ClaimAttempt next = writer.claim_job("k2", {"new", "host", 2, 1, "s"}, "2026-01-01T00:00:02.000Z");
    ASSERT_EQ(next.result, ClaimResult::claimed);
    EXPECT_EQ(next.generation, 1);
    const std::vector<std::string> findings = writer.check_contents(true);
    EXPECT_TRUE(findings.empty()) << findings.front();
  }
  fs::remove_all(folder);
}

}  // namespace
}  // namespace armfarm
