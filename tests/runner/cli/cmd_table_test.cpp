// `armfarm table` through the command line on small generated databases: per-joint rows show
// per-joint values, unknown names are refused with a suggestion, rows pool only across seeds,
// undefined cells are footnoted with their reason. The tables themselves:
// tests/analysis/table_test.cpp.
#include "analysis/sweep_data.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <utility>
#include <vector>

namespace armfarm {
namespace {

using testing::make_heldout_value;

// One row of the job_metrics view, read as a user would.
double query_job_metric(const std::string& db_path, const std::string& sql) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* statement = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
  double value = std::nan("");
  if (sqlite3_step(statement) == SQLITE_ROW) value = sqlite3_column_double(statement, 0);
  sqlite3_finalize(statement);
  sqlite3_close(db);
  return value;
}

TEST(TableCommand, PerJointRowsShowPerJointValues) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::write_test_sweep(db, "gains", testing::make_gain_jobs());
  const auto result = testing::run_armfarm("table " + db + " --rows control.gain_scale,joint --cols tracking_nmse --format json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto json = nlohmann::json::parse(result.output)["tables"].at(0);
  ASSERT_EQ(json["rows"].size(), 6u);  // 2 gains × 3 joints
  for (const auto& row : json["rows"]) {
    const std::string gain = row["params"]["control.gain_scale"], joint = row["params"]["joint"];
    const double expected = query_job_metric(
        db, "SELECT avg(value) FROM job_metrics WHERE sweep = 'gains' AND name = 'tracking_nmse' AND joint = " + joint +
                " AND json_extract(params, '$.\"control.gain_scale\"') = " + gain);
    EXPECT_NEAR(row["cells"]["tracking_nmse"]["mean"].get<double>(), expected, 1e-15) << gain << " joint " << joint;
    EXPECT_EQ(row["cells"]["tracking_nmse"]["n"].get<int>(), 2);
  }
  // Different joints, different values (the old table printed the job mean on every row).
  EXPECT_NE(json["rows"][0]["cells"]["tracking_nmse"]["mean"], json["rows"][1]["cells"]["tracking_nmse"]["mean"]);
}

TEST(TableCommand, UnknownNamesExitTwoWithASuggestion) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::write_test_sweep(db, "gains", testing::make_gain_jobs());
  const auto where = testing::run_armfarm("table " + db + " --where gain_scale=1");
  EXPECT_EQ(where.exit_code, 2) << where.output;
  EXPECT_NE(where.output.find("no parameter 'gain_scale'"), std::string::npos) << where.output;
  EXPECT_NE(where.output.find("did you mean 'control.gain_scale'"), std::string::npos) << where.output;
  const auto rows = testing::run_armfarm("table " + db + " --rows control.gain_scal");
  EXPECT_EQ(rows.exit_code, 2) << rows.output;
  EXPECT_NE(rows.output.find("did you mean 'control.gain_scale'"), std::string::npos) << rows.output;
  const auto cols = testing::run_armfarm("table " + db + " --cols tracking_nms");
  EXPECT_EQ(cols.exit_code, 2) << cols.output;
  EXPECT_NE(cols.output.find("did you mean 'tracking_nmse'"), std::string::npos) << cols.output;
  EXPECT_EQ(testing::run_armfarm("table " + db + " --where control.gain_scale=1").exit_code, 0);
}

TEST(TableCommand, RowsPoolOnlyJobsThatDifferInTheirSeed) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::write_test_sweep(db, "gains", testing::make_gain_jobs());
  // Rows by joint alone would pool both gain scales: refused, naming the parameter.
  const auto pooled = testing::run_armfarm("table " + db + " --rows joint --cols tracking_nmse");
  EXPECT_EQ(pooled.exit_code, 2) << pooled.output;
  EXPECT_NE(pooled.output.find("differ in control.gain_scale"), std::string::npos) << pooled.output;
  EXPECT_EQ(testing::run_armfarm("table " + db + " --rows joint --cols tracking_nmse --where control.gain_scale=1").exit_code, 0);
}

TEST(TableCommand, UndefinedCellsPrintADashWithTheirReason) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::TestJob job;
  job.params = {{"control.gain_scale", 0.2}};
  job.metrics = {{0, "tracking_nmse", 1, 0.02, ""},
                 {0, "tracking_nmse", 2, std::nullopt, "target std 1e-15 rad is below the nMSE floor 0.006 rad"},
                 {0, "tracking_nmse", std::nullopt, 0.02, "mean over 1 of 2 joints; left out: joint 2"}};
  testing::write_test_sweep(db, "still", {job});
  const auto joints = testing::run_armfarm("table " + db + " --rows joint --cols tracking_nmse");
  ASSERT_EQ(joints.exit_code, 0) << joints.output;
  EXPECT_NE(joints.output.find("| 2 | – [1] |"), std::string::npos) << joints.output;
  EXPECT_NE(joints.output.find("[1] tracking_nmse, joint 2: undefined in 1 of 1 jobs: target std 1e-15 rad"),
            std::string::npos)
      << joints.output;
  const auto mean = testing::run_armfarm("table " + db + " --cols tracking_nmse");
  ASSERT_EQ(mean.exit_code, 0) << mean.output;
  EXPECT_NE(mean.output.find("| 0.2 | 0.02 [1] |"), std::string::npos) << mean.output;
  EXPECT_NE(mean.output.find("[1] tracking_nmse: mean over 1 of 2 joints"), std::string::npos) << mean.output;
}

TEST(TableCommand, CheckpointRowsMatchTheStoredRows) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("results.db");
  std::vector<testing::TestJob> jobs;
  for (int seed = 1; seed <= 2; ++seed) {
    testing::TestJob job;
    job.params = {{"learning.lwpr.init_D", 10.0}, {"seed", seed}};
    for (std::int64_t checkpoint : {0, 2, 4}) {
      for (int joint = 1; joint <= 3; ++joint) {
        job.metrics.push_back({0, "heldout_ff_fb_ratio_avg", joint, make_heldout_value(10, joint, checkpoint, seed), "", checkpoint});
      }
    }
    job.metrics.push_back({0, "fb_abs_avg", 1, 0.01, "", std::nullopt});
    jobs.push_back(job);
  }
  testing::write_test_sweep(db, "heldout", jobs);

  // Expected cells straight from the stored rows: mean over seeds per (checkpoint, joint).
  std::map<std::pair<std::int64_t, int>, std::vector<double>> stored;
  {
    const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
    const SweepData data = load_sweep_data(store, "heldout");
    for (const JobResult& job : data.jobs) {
      for (const auto& [id, value] : job.metrics) {
        if (id.name == "heldout_ff_fb_ratio_avg") stored[{*id.checkpoint, *id.joint}].push_back(value);
      }
    }
  }
  ASSERT_EQ(stored.size(), 9u);

  const auto result = testing::run_armfarm("table " + db + " --rows checkpoint,joint --cols heldout_ff_fb_ratio_avg --format json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto json = nlohmann::json::parse(result.output)["tables"].at(0);
  ASSERT_EQ(json["rows"].size(), 9u);
  for (const auto& row : json["rows"]) {
    const std::int64_t checkpoint = std::stoll(row["params"]["checkpoint"].get<std::string>());
    const int joint = std::stoi(row["params"]["joint"].get<std::string>());
    const std::vector<double>& values = stored.at({checkpoint, joint});
    ASSERT_EQ(values.size(), 2u);
    EXPECT_NEAR(row["cells"]["heldout_ff_fb_ratio_avg"]["mean"].get<double>(), (values[0] + values[1]) / 2, 1e-12);
    EXPECT_NEAR(row["cells"]["heldout_ff_fb_ratio_avg"]["mean"].get<double>(),
                make_heldout_value(10, joint, checkpoint, 1) + 0.0005, 1e-12);
  }
  EXPECT_EQ(json["rows"][1]["params"]["checkpoint"], "0");
  EXPECT_EQ(json["rows"][1]["params"]["joint"], "2");

  const auto typo = testing::run_armfarm("table " + db + " --rows checkpoint --cols heldout_ff_fb_ratio_avgg");
  EXPECT_EQ(typo.exit_code, 2);
  EXPECT_NE(typo.output.find("did you mean 'heldout_ff_fb_ratio_avg'"), std::string::npos) << typo.output;
  const auto row_typo = testing::run_armfarm("table " + db + " --rows checkpoint,learning.lwpr.init_DD");
  EXPECT_EQ(row_typo.exit_code, 2);
  EXPECT_NE(row_typo.output.find("did you mean 'learning.lwpr.init_D'"), std::string::npos) << row_typo.output;
}

TEST(TableCommand, ReadsADatabaseAndAggregatesRepeats) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("results.db");
  std::vector<testing::TestJob> jobs;
  for (int seed = 1; seed <= 2; ++seed) {
    testing::TestJob job;
    job.params = {{"control.gain_scale", 0.2}, {"seed", seed}};
    job.metrics = {{0, "ff_fb_ratio_avg", 2, seed == 1 ? 0.8 : 0.9, ""}, {0, "fb_abs_avg", 2, 0.01, ""}};
    jobs.push_back(job);
  }
  testing::write_test_sweep(db, "gains", jobs);
  const auto result = testing::run_armfarm("table " + db + " --format json");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto json = nlohmann::json::parse(result.output)["tables"].at(0);
  EXPECT_NEAR(json["rows"][0]["cells"]["ff_fb_ratio_avg"]["mean"].get<double>(), 0.85, 1e-12);
  EXPECT_EQ(json["rows"][0]["cells"]["ff_fb_ratio_avg"]["n"].get<int>(), 2);
  EXPECT_EQ(json["rows"][0]["params"]["joint"], "2");

  const auto bad = testing::run_armfarm("table " + db + " --cols no_such_metric");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("no metric 'no_such_metric'"), std::string::npos) << bad.output;
  const auto missing = testing::run_armfarm("table " + directory.file("absent.db"));
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
}

// Issue 29: several tables printed several JSON documents (one per table), which no JSON
// reader takes; and a newline in a value ended a Markdown row in the middle.
TEST(TableCommand, JsonIsOneDocumentForEveryTableAndMarkdownRowsStayOneLine) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("results.db");
  std::vector<testing::TestJob> jobs(2);
  jobs[0].params = {{"trajectory.recorded.file", "two\nlines|piped"}};
  jobs[0].metrics = {{0, "tracking_nmse", std::nullopt, 0.25, ""}};
  jobs[1].params = {{"trajectory.recorded.file", "plain"}};
  jobs[1].metrics = {{0, "tracking_nmse", std::nullopt, 0.5, ""}};
  testing::write_test_sweep(db, "first", jobs);
  testing::write_test_sweep(db, "second", jobs);

  const auto json = testing::run_armfarm("table " + db + " --cols tracking_nmse --format json");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const auto document = nlohmann::json::parse(json.output);  // throws on a second document
  ASSERT_EQ(document["tables"].size(), 2u) << json.output;
  EXPECT_EQ(document["tables"][0]["sweep"], "first");
  EXPECT_EQ(document["tables"][1]["sweep"], "second");
  EXPECT_EQ(document["tables"][1]["rows"].size(), 2u);
  const auto& rows_of_first = document["tables"][0]["rows"];
  EXPECT_TRUE(std::any_of(rows_of_first.begin(), rows_of_first.end(), [](const nlohmann::json& row) {
    return row["params"]["trajectory.recorded.file"] == "two\nlines|piped";  // exact in JSON
  })) << rows_of_first;

  const auto md = testing::run_armfarm("table " + db + " --sweep first --cols tracking_nmse --format md");
  ASSERT_EQ(md.exit_code, 0) << md.output;
  std::istringstream lines(md.output);
  std::size_t rows = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] != '|') {
      EXPECT_TRUE(line.empty() || line.rfind("### ", 0) == 0) << "a line outside the table: " << line << "\n" << md.output;
      continue;
    }
    ++rows;
    EXPECT_EQ(line.back(), '|') << line;
  }
  EXPECT_EQ(rows, 4u) << md.output;  // header, rule, two rows
  EXPECT_NE(md.output.find("| two<br>lines\\|piped |"), std::string::npos) << md.output;
}

}  // namespace
}  // namespace armfarm
