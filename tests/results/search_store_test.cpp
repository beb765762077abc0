// The search tables: a database of schema version 5 (before searches) migrates with its jobs
// kept; one of version 6 keeps its search, whose version-7 settings are empty until a writer
// fills them in (and then stay); one of version 7 gains TPE's rule as NULL (read as the per-axis
// rule; merge compares it so, a NULL against "joint" is a conflict); one of version 8 gains the
// joint rule's constants as NULL (read as version 8's; merge refuses other constants); a search, its rungs, trials and steps round-trip and are what a plain SQL
// reader sees (the search_promotions view); a step naming no job is refused; merge copies a
// search whole, extends one the file already has and refuses a disagreeing one (its settings,
// its rungs' checkpoints and costs, or a step).
#include "results/results_store.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"
#include "support/sqlite_rows.hpp"
#include "support/test_database.hpp"
#include <sqlite3.h>

#include <filesystem>
#include <string>
#include <vector>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class SearchStoreTest : public test_support::ScratchFolderTest {
 protected:
  SearchStoreTest() : ScratchFolderTest("search_store") {}
};

using test_support::query_rows;

// A step as the search runner inserts it: not committed, no objective yet (fields named, so that
// the record's later members need no initializers here).
SearchStepRecord new_step(std::int64_t step, std::int64_t trial, std::int64_t rung, std::int64_t visible,
                          const std::string& kind, double cost, const std::string& job_key) {
  SearchStepRecord r;
  r.step = step;
  r.trial = trial;
  r.rung = rung;
  r.visible = visible;
  r.kind = kind;
  r.cost = cost;
  r.job_key = job_key;
  return r;
}

SearchRecord make_search(const std::string& sweep) {
  SearchRecord search;
  search.sweep = sweep;
  search.method = "asha";
  search.sampler = "tpe";
  search.seed = 7;
  search.eta = 3;
  search.slots = 2;
  search.budget_unit = "cpu_seconds";
  search.budget = 3600.0;
  search.objective_metric = "heldout_test_nmse";
  search.objective_direction = "lower";
  search.objective_checkpoint = 200;
  search.rungs = {{0, 10, 12.5}, {1, 50, 60.0}, {2, 200, 240.0}};
  return search;
}

TEST_F(SearchStoreTest, AVersionFiveDatabaseMigratesKeepingItsJobs) {
  // A file of schema version 5: today's file without the search tables (migration 6 only adds them).
  {
    ResultsStore store = ResultsStore::open(path("v5.db"), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("old"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}});
  }
  query_rows(path("v5.db"), "DROP VIEW search_promotions; DROP TABLE search_steps; DROP TABLE search_trials; "
                       "DROP TABLE search_rungs; DROP TABLE searches; PRAGMA user_version = 5;");
  ASSERT_EQ(query_rows(path("v5.db"), "PRAGMA user_version"), std::vector<std::string>{"5"});
  {
    const ResultsStore reader = ResultsStore::open(path("v5.db"), ResultsStore::Mode::read_only);
    EXPECT_EQ(reader.schema_version(), kResultsSchemaVersion);  // a migrated in-memory copy
    EXPECT_FALSE(reader.find_search("old").has_value());
  }
  EXPECT_EQ(query_rows(path("v5.db"), "PRAGMA user_version"), std::vector<std::string>{"5"});  // untouched by a reader
  {
    ResultsStore writer = ResultsStore::open(path("v5.db"), ResultsStore::Mode::read_write);
    EXPECT_EQ(writer.schema_version(), kResultsSchemaVersion);
    EXPECT_TRUE(writer.find_job("k1").has_value());
    writer.insert_search(make_search("old"));
  }
  EXPECT_EQ(query_rows(path("v5.db"), "PRAGMA user_version"), std::vector<std::string>{std::to_string(kResultsSchemaVersion)});
  EXPECT_EQ(query_rows(path("v5.db"), "SELECT method, objective_metric FROM searches"), std::vector<std::string>{"asha|heldout_test_nmse"});
  EXPECT_TRUE(ResultsStore::open(path("v5.db"), ResultsStore::Mode::read_only).check_contents(true).empty());
}

TEST_F(SearchStoreTest, AVersionSixSearchMigratesWithItsNewSettingsEmptyAndTheNextWriterFillsThemIn) {
  // A file of schema version 6: a search row without the columns migration 7 adds.
  {
    ResultsStore store = ResultsStore::open(path("v6.db"), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("old"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}});
    store.insert_search(make_search("old"));
  }
  query_rows(path("v6.db"), "ALTER TABLE searches DROP COLUMN max_trials; ALTER TABLE searches DROP COLUMN bracket_size; "
                            "ALTER TABLE searches DROP COLUMN tpe_startup; ALTER TABLE searches DROP COLUMN tpe_gamma; "
                            "ALTER TABLE searches DROP COLUMN tpe_max_good; ALTER TABLE searches DROP COLUMN tpe_candidates; "
                            "ALTER TABLE searches DROP COLUMN space; ALTER TABLE searches DROP COLUMN tpe_rule; "
                            "ALTER TABLE searches DROP COLUMN tpe_prior_weight; ALTER TABLE searches DROP COLUMN tpe_bandwidth; "
                            "ALTER TABLE searches DROP COLUMN tpe_liar_bandwidth; PRAGMA user_version = 6;");
  ASSERT_EQ(query_rows(path("v6.db"), "SELECT count(*) FROM pragma_table_info('searches')"), std::vector<std::string>{"14"});
  {
    const ResultsStore reader = ResultsStore::open(path("v6.db"), ResultsStore::Mode::read_only);
    const std::optional<SearchRecord> old = reader.find_search("old");
    ASSERT_TRUE(old.has_value());
    EXPECT_EQ(old->method, "asha");
    EXPECT_EQ(old->rungs.size(), 3u);
    EXPECT_FALSE(old->tpe_startup.has_value());  // not recorded by version 6
    EXPECT_FALSE(old->space.has_value());
  }
  EXPECT_EQ(query_rows(path("v6.db"), "PRAGMA user_version"), std::vector<std::string>{"6"});
  SearchRecord now = make_search("old");
  now.max_trials = 0;
  now.bracket_size = 0;
  now.tpe_startup = 4;
  now.tpe_gamma = 0.25;
  now.tpe_max_good = 25;
  now.tpe_candidates = 24;
  now.space = R"([{"path":"x"}])";
  {
    ResultsStore writer = ResultsStore::open(path("v6.db"), ResultsStore::Mode::read_write);
    writer.insert_search(now);  // the resumed runner: fills in what version 6 lacked
    SearchRecord later = now;
    later.tpe_startup = 9;
    writer.insert_search(later);  // a recorded value stays
  }
  EXPECT_EQ(query_rows(path("v6.db"), "PRAGMA user_version"), std::vector<std::string>{std::to_string(kResultsSchemaVersion)});
  EXPECT_EQ(query_rows(path("v6.db"), "SELECT count(*), method, seed, tpe_startup, tpe_gamma, tpe_max_good, tpe_candidates, "
                                      "max_trials, bracket_size, space FROM searches"),
            std::vector<std::string>{R"(1|asha|7|4|0.25|25|24|0|0|[{"path":"x"}])"});
  EXPECT_TRUE(ResultsStore::open(path("v6.db"), ResultsStore::Mode::read_only).check_contents(true).empty());
}

TEST_F(SearchStoreTest, ASearchRoundTripsAndPlainSqlSeesItsPromotions) {
  {
    ResultsStore store = ResultsStore::open(path("s.db"), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("s"), {{"ka", {{"x", 1}}, {{"x", 1}}, 0}, {"kb", {{"x", 2}}, {{"x", 2}}, 0},
                                             {"ka1", {{"x", 1}}, {{"x", 1}}, 0}});
    store.insert_search(make_search("s"));
    store.insert_search(make_search("s"));  // a resumed run: written once
    store.insert_search_step("s", new_step(0, 0, 0, 0, "new", 12.5, "ka"), SearchTrialRecord{0, 0, R"({"x":1})"});
    store.insert_search_step("s", new_step(1, 1, 0, 0, "new", 12.5, "kb"), SearchTrialRecord{1, 0, R"({"x":2})"});
    store.update_search_objective("s", 0, 0.25, "");
    store.update_search_objective("s", 1, std::nullopt, "diverged");
    store.insert_search_step("s", new_step(2, 0, 1, 2, "promotion", 47.5, "ka1"), std::nullopt);
    EXPECT_THROW(store.insert_search_step("s", new_step(3, 1, 1, 2, "promotion", 47.5, "nokey"), std::nullopt), StoreError);
  }
  const ResultsStore store = ResultsStore::open(path("s.db"), ResultsStore::Mode::read_only);
  const std::optional<SearchRecord> search = store.find_search("s");
  ASSERT_TRUE(search.has_value());
  EXPECT_EQ(search->seed, 7);
  EXPECT_EQ(search->objective_checkpoint, 200);
  EXPECT_FALSE(search->objective_joint.has_value());
  ASSERT_EQ(search->rungs.size(), 3u);
  EXPECT_EQ(search->rungs[1].checkpoint, 50);
  EXPECT_DOUBLE_EQ(search->rungs[2].cost, 240.0);
  const std::vector<SearchTrialRecord> trials = store.find_search_trials("s");
  ASSERT_EQ(trials.size(), 2u);
  EXPECT_EQ(trials[1].params, R"({"x":2})");
  const std::vector<SearchStepRecord> steps = store.find_search_steps("s");
  ASSERT_EQ(steps.size(), 3u);  // the refused step left nothing behind
  EXPECT_EQ(steps[0].objective, 0.25);
  EXPECT_TRUE(steps[0].committed);
  EXPECT_FALSE(steps[1].objective.has_value());
  EXPECT_EQ(steps[1].reason, "diverged");
  EXPECT_FALSE(steps[2].committed);
  EXPECT_EQ(steps[2].job_key, "ka1");
  EXPECT_EQ(steps[2].visible, 2);
  EXPECT_EQ(query_rows(path("s.db"), "SELECT trial, from_rung, to_rung, key FROM search_promotions"),
            std::vector<std::string>{"0|0|1|ka1"});
  EXPECT_THROW(store.find_search_steps("nosuch"), StoreError);
}

// File `name` with sweep "s" (its jobs registered in `keys` order, so their ids differ between
// files), the search, and steps 0 … steps−1 of the sequence ka (trial 0, rung 0), kb (trial 1,
// rung 0), ka1 (trial 0 promoted); `committed` of them with objectives 0.25, 0.5, 0.125.
void write_search_file(const std::string& file, const std::vector<std::string>& keys, int steps, int committed,
                       const std::string& step1_key = "kb") {
  ResultsStore store = ResultsStore::open(file, ResultsStore::Mode::read_write);
  std::vector<JobRegistration> jobs;
  for (const std::string& key : keys) jobs.push_back({key, {{"k", key}}, {{"k", key}}, 0});
  store.insert_sweep_run(testing::make_sweep_registration("s"), jobs);
  store.insert_search(make_search("s"));
  const std::vector<SearchStepRecord> sequence = {new_step(0, 0, 0, 0, "new", 12.5, "ka"),
                                                  new_step(1, 1, 0, 0, "new", 12.5, step1_key),
                                                  new_step(2, 0, 1, 2, "promotion", 47.5, "ka1")};
  const std::vector<std::optional<SearchTrialRecord>> trials = {SearchTrialRecord{0, 0, R"({"x":1})"},
                                                                SearchTrialRecord{1, 0, R"({"x":2})"}, std::nullopt};
  const std::vector<double> objectives = {0.25, 0.5, 0.125};
  for (int i = 0; i < steps; ++i) store.insert_search_step("s", sequence[i], trials[i]);
  for (int i = 0; i < committed; ++i) store.update_search_objective("s", i, objectives[i], "");
}

const char* const kMergedSteps =
    "SELECT st.step, st.trial, st.rung, st.kind, j.key, st.objective, st.committed FROM search_steps st "
    "JOIN jobs j ON j.id = st.job_id ORDER BY st.step";

TEST_F(SearchStoreTest, AVersionSevenSearchMigratesWithoutATpeRuleAndTheResumingWriterRecordsTheRuleItAdopted) {
  // A file of schema version 7 as the build before version 8 wrote it: every setting but the rule.
  SearchRecord recorded = make_search("seven");
  recorded.max_trials = 0;
  recorded.bracket_size = 0;
  recorded.tpe_startup = 4;
  recorded.tpe_gamma = 0.25;
  recorded.tpe_max_good = 25;
  recorded.tpe_candidates = 24;
  recorded.space = R"([{"path":"x"}])";
  {
    ResultsStore store = ResultsStore::open(path("v7.db"), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("seven"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}});
    store.insert_search(recorded);
    store.insert_search_step("seven", new_step(0, 0, 0, 0, "new", 12.5, "k1"), SearchTrialRecord{0, 0, R"({"x":1})"});
  }
  query_rows(path("v7.db"), "ALTER TABLE searches DROP COLUMN tpe_rule; ALTER TABLE searches DROP COLUMN tpe_prior_weight; "
                            "ALTER TABLE searches DROP COLUMN tpe_bandwidth; ALTER TABLE searches DROP COLUMN tpe_liar_bandwidth; "
                            "PRAGMA user_version = 7;");
  ASSERT_EQ(query_rows(path("v7.db"), "SELECT count(*) FROM pragma_table_info('searches')"), std::vector<std::string>{"21"});
  {
    const ResultsStore reader = ResultsStore::open(path("v7.db"), ResultsStore::Mode::read_only);  // a migrated copy
    const std::optional<SearchRecord> old = reader.find_search("seven");
    ASSERT_TRUE(old.has_value());
    EXPECT_FALSE(old->tpe_rule.has_value());  // NULL: the per-axis rule of the builds before version 8
    EXPECT_EQ(old->tpe_startup, 4);
    EXPECT_EQ(reader.find_search_steps("seven").size(), 1u);
  }
  EXPECT_EQ(query_rows(path("v7.db"), "PRAGMA user_version"), std::vector<std::string>{"7"});  // reading left it so
  {
    // The resumed runner adopts "per_axis" for NULL and writes it; a later writer's value does not replace it.
    ResultsStore writer = ResultsStore::open(path("v7.db"), ResultsStore::Mode::read_write);
    SearchRecord resumed = recorded;
    resumed.tpe_rule = "per_axis";
    writer.insert_search(resumed);
    resumed.tpe_rule = "joint";
    writer.insert_search(resumed);
  }
  EXPECT_EQ(query_rows(path("v7.db"), "PRAGMA user_version"), std::vector<std::string>{std::to_string(kResultsSchemaVersion)});
  EXPECT_EQ(query_rows(path("v7.db"), "SELECT count(*), method, tpe_startup, tpe_rule FROM searches"),
            std::vector<std::string>{"1|asha|4|per_axis"});
  EXPECT_EQ(query_rows(path("v7.db"), "SELECT count(*) FROM search_steps"), std::vector<std::string>{"1"});
  EXPECT_TRUE(ResultsStore::open(path("v7.db"), ResultsStore::Mode::read_only).check_contents(true).empty());
  // The column takes only the two rules (the CHECK refuses the update; the row keeps its rule).
  query_rows(path("v7.db"), "UPDATE searches SET tpe_rule = 'both'");
  EXPECT_EQ(query_rows(path("v7.db"), "SELECT tpe_rule FROM searches"), std::vector<std::string>{"per_axis"});
}

TEST_F(SearchStoreTest, MergeReadsANullTpeRuleAsPerAxisAndRefusesItAgainstAJointSearch) {
  const auto write = [&](const std::string& file, const std::optional<std::string>& rule) {
    ResultsStore store = ResultsStore::open(path(file), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("r"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}});
    SearchRecord search = make_search("r");
    search.tpe_rule = rule;
    store.insert_search(search);
  };
  write("null.db", std::nullopt);
  write("per_axis.db", std::string("per_axis"));
  write("joint.db", std::string("joint"));
  {
    ResultsStore store = ResultsStore::open(path("null.db"), ResultsStore::Mode::read_write);
    EXPECT_TRUE(store.merge_from(path("per_axis.db")).conflicts.empty());  // the same rule: NULL filled in
    const MergeReport report = store.merge_from(path("joint.db"));
    ASSERT_EQ(report.conflicts.size(), 1u);
    EXPECT_NE(report.conflicts[0].find("search r: different settings in " + path("joint.db")), std::string::npos) << report.conflicts[0];
  }
  EXPECT_EQ(query_rows(path("null.db"), "SELECT tpe_rule FROM searches"), std::vector<std::string>{"per_axis"});
}

TEST_F(SearchStoreTest, AVersionEightJointSearchMigratesWithItsConstantsEmptyReadAsThoseOfVersionEight) {
  // A file of schema version 8 as its builds wrote it: a joint TPE search with every setting
  // but the joint rule's constants.
  SearchRecord recorded = make_search("eight");
  recorded.max_trials = 0;
  recorded.bracket_size = 0;
  recorded.tpe_startup = 4;
  recorded.tpe_gamma = 0.25;
  recorded.tpe_max_good = 25;
  recorded.tpe_candidates = 24;
  recorded.space = R"([{"path":"x"}])";
  recorded.tpe_rule = "joint";
  {
    ResultsStore store = ResultsStore::open(path("v8.db"), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("eight"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}});
    store.insert_search(recorded);
    store.insert_search_step("eight", new_step(0, 0, 0, 0, "new", 12.5, "k1"), SearchTrialRecord{0, 0, R"({"x":1})"});
  }
  query_rows(path("v8.db"), "ALTER TABLE searches DROP COLUMN tpe_prior_weight; ALTER TABLE searches DROP COLUMN tpe_bandwidth; "
                            "ALTER TABLE searches DROP COLUMN tpe_liar_bandwidth; PRAGMA user_version = 8;");
  ASSERT_EQ(query_rows(path("v8.db"), "SELECT count(*) FROM pragma_table_info('searches')"), std::vector<std::string>{"22"});
  {
    const ResultsStore reader = ResultsStore::open(path("v8.db"), ResultsStore::Mode::read_only);  // a migrated copy
    const std::optional<SearchRecord> old = reader.find_search("eight");
    ASSERT_TRUE(old.has_value());
    EXPECT_EQ(old->tpe_rule, "joint");
    EXPECT_FALSE(old->tpe_prior_weight.has_value());
    EXPECT_FALSE(old->tpe_bandwidth.has_value());
    EXPECT_FALSE(old->tpe_liar_bandwidth.has_value());
    // NULL is read as the constants every build of version 8 proposed with.
    const TpeJointConstants constants = read_tpe_constants(*old);
    EXPECT_EQ(constants.prior_weight, 1.0);
    EXPECT_EQ(constants.bandwidth, 0.2);
    EXPECT_EQ(constants.liar_bandwidth, 0.7);
    EXPECT_EQ(reader.find_search_steps("eight").size(), 1u);
  }
  EXPECT_EQ(query_rows(path("v8.db"), "PRAGMA user_version"), std::vector<std::string>{"8"});  // reading left it so
  {
    // The resumed runner writes its constants (equal to version 8's); a later writer's do not replace them.
    ResultsStore writer = ResultsStore::open(path("v8.db"), ResultsStore::Mode::read_write);
    SearchRecord resumed = recorded;
    resumed.tpe_prior_weight = 1.0;
    resumed.tpe_bandwidth = 0.2;
    resumed.tpe_liar_bandwidth = 0.7;
    writer.insert_search(resumed);
    resumed.tpe_bandwidth = 0.3;
    writer.insert_search(resumed);
  }
  EXPECT_EQ(query_rows(path("v8.db"), "PRAGMA user_version"), std::vector<std::string>{"9"});
  EXPECT_EQ(query_rows(path("v8.db"), "SELECT count(*), tpe_rule, tpe_prior_weight, tpe_bandwidth, tpe_liar_bandwidth FROM searches"),
            std::vector<std::string>{"1|joint|1.0|0.2|0.7"});
  EXPECT_EQ(query_rows(path("v8.db"), "SELECT count(*) FROM search_steps"), std::vector<std::string>{"1"});
  EXPECT_TRUE(ResultsStore::open(path("v8.db"), ResultsStore::Mode::read_only).check_contents(true).empty());
  // The columns take positive values only (the CHECK refuses the update; the row keeps its value).
  query_rows(path("v8.db"), "UPDATE searches SET tpe_bandwidth = 0");
  query_rows(path("v8.db"), "UPDATE searches SET tpe_liar_bandwidth = -0.7");
  EXPECT_EQ(query_rows(path("v8.db"), "SELECT tpe_bandwidth, tpe_liar_bandwidth FROM searches"), std::vector<std::string>{"0.2|0.7"});
}

TEST_F(SearchStoreTest, MergeReadsNullJointConstantsAsVersionEightsAndRefusesOtherConstants) {
  const auto write = [&](const std::string& file, const std::optional<std::string>& rule, const std::optional<double>& bandwidth) {
    ResultsStore store = ResultsStore::open(path(file), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("c"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}});
    SearchRecord search = make_search("c");
    search.tpe_rule = rule;
    search.tpe_bandwidth = bandwidth;
    store.insert_search(search);
  };
  write("null.db", std::string("joint"), std::nullopt);        // a joint row of version 8: h is 0.2
  write("same.db", std::string("joint"), 0.2);                 // the same constant, recorded
  write("other.db", std::string("joint"), 0.3);                // another build's constant
  write("axis_null.db", std::string("per_axis"), std::nullopt);
  write("axis_other.db", std::string("per_axis"), 0.3);        // the per-axis rule does not use it
  {
    ResultsStore store = ResultsStore::open(path("null.db"), ResultsStore::Mode::read_write);
    EXPECT_TRUE(store.merge_from(path("same.db")).conflicts.empty());  // NULL agrees with 0.2 and is filled in
    const MergeReport report = store.merge_from(path("other.db"));
    ASSERT_EQ(report.conflicts.size(), 1u);
    EXPECT_NE(report.conflicts[0].find("search c: different settings in " + path("other.db") + "; kept this file's"), std::string::npos)
        << report.conflicts[0];
  }
  EXPECT_EQ(query_rows(path("null.db"), "SELECT tpe_bandwidth FROM searches"), std::vector<std::string>{"0.2"});
  write("null2.db", std::string("joint"), std::nullopt);
  {
    // A NULL against 0.3 is a conflict too (NULL is 0.2, not "any value").
    ResultsStore store = ResultsStore::open(path("null2.db"), ResultsStore::Mode::read_write);
    EXPECT_EQ(store.merge_from(path("other.db")).conflicts.size(), 1u);
  }
  EXPECT_EQ(query_rows(path("null2.db"), "SELECT tpe_bandwidth IS NULL FROM searches"), std::vector<std::string>{"1"});
  {
    ResultsStore store = ResultsStore::open(path("axis_null.db"), ResultsStore::Mode::read_write);
    EXPECT_TRUE(store.merge_from(path("axis_other.db")).conflicts.empty());
  }
}

// A rung's cost is the build's estimate times its cost factor: two runners of one search with
// other factors (or cost models) decided other steps within the budget, so a merge refuses a
// search whose rungs differ in cost or checkpoint, and accepts the same rungs.
TEST_F(SearchStoreTest, MergeRefusesASearchWhoseRungsCostOtherwise) {
  const auto write = [&](const std::string& file, const std::vector<SearchRungRecord>& rungs) {
    ResultsStore store = ResultsStore::open(path(file), ResultsStore::Mode::read_write);
    store.insert_sweep_run(testing::make_sweep_registration("c"), {{"k1", {{"a", 1}}, {{"a", 1}}, 0}});
    SearchRecord search = make_search("c");
    search.rungs = rungs;
    store.insert_search(search);
  };
  const std::vector<SearchRungRecord> rungs = make_search("c").rungs;  // costs 12.5, 60, 240
  std::vector<SearchRungRecord> halved = rungs;  // the same jobs at half the factor
  for (SearchRungRecord& r : halved) r.cost *= 0.5;
  std::vector<SearchRungRecord> moved = rungs;
  moved[1].checkpoint = 60;
  write("mine.db", rungs);
  write("same.db", rungs);
  write("halved.db", halved);
  write("moved.db", moved);
  write("fewer.db", {rungs[0], rungs[2]});
  ResultsStore store = ResultsStore::open(path("mine.db"), ResultsStore::Mode::read_write);
  EXPECT_TRUE(store.merge_from(path("same.db")).conflicts.empty());
  for (const char* other : {"halved.db", "moved.db", "fewer.db"}) {
    const MergeReport report = store.merge_from(path(other));
    ASSERT_EQ(report.conflicts.size(), 1u) << other;
    EXPECT_EQ(report.conflicts[0], "search c: different settings in " + path(other) + "; kept this file's");
  }
  EXPECT_EQ(query_rows(path("mine.db"), "SELECT rung, checkpoint, cost FROM search_rungs ORDER BY rung"),
            (std::vector<std::string>{"0|10|12.5", "1|50|60.0", "2|200|240.0"}));
}

TEST_F(SearchStoreTest, MergeCopiesASearchWholeAndExtendsTheSameSearchStepByStep) {
  write_search_file(path("short.db"), {"ka", "kb", "ka1"}, 2, 1);
  write_search_file(path("long.db"), {"ka1", "kc", "kb", "ka"}, 3, 2);
  const std::vector<std::string> expected = {"0|0|0|new|ka|0.25|1", "1|1|0|new|kb|0.5|1", "2|0|1|promotion|ka1|NULL|0"};
  {
    // The same search, further on in the other file: its third step added, step 1's objective taken.
    ResultsStore store = ResultsStore::open(path("short.db"), ResultsStore::Mode::read_write);
    const MergeReport report = store.merge_from(path("long.db"));
    EXPECT_TRUE(report.conflicts.empty()) << report.conflicts.front();
  }
  EXPECT_EQ(query_rows(path("short.db"), kMergedSteps), expected);
  EXPECT_EQ(query_rows(path("short.db"), "SELECT trial, params FROM search_trials ORDER BY trial"),
            (std::vector<std::string>{R"(0|{"x":1})", R"(1|{"x":2})"}));
  {
    // A file without the search takes it whole: settings, rungs, trials, steps.
    ResultsStore store = ResultsStore::open(path("empty.db"), ResultsStore::Mode::read_write);
    const MergeReport report = store.merge_from(path("short.db"));
    EXPECT_TRUE(report.conflicts.empty());
  }
  EXPECT_EQ(query_rows(path("empty.db"), kMergedSteps), expected);
  const ResultsStore merged = ResultsStore::open(path("empty.db"), ResultsStore::Mode::read_only);
  ASSERT_TRUE(merged.find_search("s").has_value());
  EXPECT_EQ(merged.find_search("s")->rungs.size(), 3u);
  EXPECT_EQ(merged.find_search("s")->seed, 7);
  EXPECT_EQ(query_rows(path("empty.db"), "SELECT trial, from_rung, to_rung, key FROM search_promotions"),
            std::vector<std::string>{"0|0|1|ka1"});
}

TEST_F(SearchStoreTest, MergeRefusesASearchWhoseStepsDisagreeAndKeepsThisFilesSearch) {
  write_search_file(path("mine.db"), {"ka", "kb", "ka1", "kc"}, 2, 0);
  write_search_file(path("other.db"), {"ka", "kb", "ka1", "kc"}, 3, 3, "kc");  // step 1 ran another job
  ResultsStore store = ResultsStore::open(path("mine.db"), ResultsStore::Mode::read_write);
  const MergeReport report = store.merge_from(path("other.db"));
  ASSERT_EQ(report.conflicts.size(), 1u);
  EXPECT_NE(report.conflicts[0].find("search s: step 1 runs a different trial, rung or job in " + path("other.db")),
            std::string::npos)
      << report.conflicts[0];
  // Nothing of the other file's search: step 0's objective, taken before step 1 disagreed, was
  // taken back with it, and step 2 was not added.
  EXPECT_EQ(query_rows(path("mine.db"), kMergedSteps),
            (std::vector<std::string>{"0|0|0|new|ka|NULL|0", "1|1|0|new|kb|NULL|0"}));
}

}  // namespace
}  // namespace armfarm
