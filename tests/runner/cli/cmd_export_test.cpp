// `armfarm export DB --sweep NAME`: a whole sweep as one long-form CSV that Python's csv module
// reads back with every value equal (bit for bit) to the database's, string parameters with
// commas and quotes intact; numbers in their shortest round-trip form; CSV fields per RFC 4180.
#include "results/results_store.hpp"
#include "runner/io/csv_writing.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

#include "support/csv_export_check.hpp"
#include "support/test_database.hpp"

using armfarm::test_support::CommandResult;

namespace armfarm {
namespace {

namespace fs = std::filesystem;

// The rows' checks (after test_support::kCsvCheckerStart): each row against its expected JSON line
// (job, params as CSV would hold them, time/value as C99 hex floats, joint, signal).
const char* kRowChecks = R"py(
n_params = len(header) - 5
for number, (row, want) in enumerate(zip(rows, expected), start=2):
    assert len(row) == len(header), (number, row)
    assert row[0] == want["job"], (number, row[0])
    for i, p in enumerate(want["params"]):
        got = row[1 + i]
        if isinstance(p, str):
            assert got == p, (number, got, p)
        elif isinstance(p, bool):
            assert got == json.dumps(p), (number, got, p)
        else:
            assert float(got) == p, (number, got, p)
    t, joint, signal, value = row[1 + n_params:]
    assert (t == "" and want["time"] is None) or float(t) == float.fromhex(want["time"]), (number, t, want["time"])
    assert joint == ("" if want["joint"] is None else str(want["joint"])), (number, joint)
    assert signal == want["signal"], (number, signal)
    v = float(value)
    w = float.fromhex(want["value"])
    assert v == w or (math.isnan(v) and math.isnan(w)), (number, value, want["value"])
    assert shortest(value) and (t == "" or shortest(t)), (number, t, value)
)py";

TEST(ExportSweep, ALongFormCsvReadsBackInPythonWithEveryValueEqualToTheDatabase) {
  const fs::path folder = fs::temp_directory_path() / ("armfarm_export_" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  const auto path = [&](const std::string& name) { return (folder / name).string(); };
  // String parameters with a comma and a quote, floats whose %.17g forms are long, a failed job.
  std::ofstream(path("e.json")) << R"({"name": "e", "base": {"fake": {"sleep_ms": 0},
      "simulation": {"samples": 9, "duration": 0.9}},
      "sweep": {"grid": {"model": ["arm, \"v2\".urdf", "plain.urdf"], "learning.lwpr.init_D": [0.1, 0.3]},
                "zip": {"fake.fail": [false, true]}}})";
  const std::string db = path("e.db");
  const CommandResult run = test_support::run_armfarm_with_fake_jobs("run " + path("e.json") + " --db " + db + " --quiet");
  ASSERT_EQ(run.exit_code, 1) << run.output;  // half the jobs asked to fail

  const CommandResult exported = test_support::run_armfarm_with_fake_jobs("export " + db + " --sweep e -o " + path("e.csv"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_NE(exported.output.find("from 4 done jobs (4 jobs not done, left out)"), std::string::npos) << exported.output;

  // The expected rows, straight from the store.
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  std::vector<std::string> params;
  std::ofstream expected(path("expected.jsonl"));
  long rows = 0;
  for (const JobRecord& job : store.find_jobs("e")) {
    if (params.empty()) {
      for (const auto& item : job.params.items()) params.push_back(item.key());
    }
    if (job.status != "done") continue;
    nlohmann::json param_values = nlohmann::json::array();
    for (const std::string& p : params) param_values.push_back(job.params.at(p));
    for (const std::string& name : store.find_series_names(job.id)) {
      const SeriesRecord series = *store.find_series(job.id, name);
      ASSERT_EQ(series.columns.front(), "t");
      for (Eigen::Index r = 0; r < series.rows.rows(); ++r) {
        for (std::size_t c = 1; c < series.columns.size(); ++c) {
          const std::string& column = series.columns[c];  // fake job: q1.., tau1..: not per-joint names
          const nlohmann::json row = {{"job", job.key},
                                      {"params", param_values},
                                      {"time", test_support::make_hex(series.rows(r, 0))},
                                      {"joint", nullptr},
                                      {"signal", name + "." + column},
                                      {"value", test_support::make_hex(series.rows(r, static_cast<Eigen::Index>(c)))}};
          expected << row.dump() << "\n";
          ++rows;
        }
      }
    }
  }
  expected.close();
  ASSERT_GT(rows, 0);
  nlohmann::json header = {"job"};
  for (const std::string& p : params) header.push_back(p);
  for (const char* column : {"time", "joint", "signal", "value"}) header.push_back(column);
  std::ofstream(path("header.json")) << header.dump();
  const CommandResult checked =
      test_support::run_csv_checker(path("check.py"), kRowChecks, path("e.csv"), path("expected.jsonl"), path("header.json"));
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  EXPECT_EQ(checked.output, "checked " + std::to_string(rows) + " rows\n");

  // The quoted field as written, and no %.17g tails.
  std::ifstream in(path("e.csv"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find(",\"arm, \"\"v2\"\".urdf\","), std::string::npos);
  EXPECT_NE(text.find(",0.1,"), std::string::npos);
  EXPECT_EQ(text.find("0.10000000000000001"), std::string::npos) << "%.17g of 0.1";

  // One series only; an unknown series is refused naming what there is, and no file appears.
  ASSERT_EQ(test_support::run_armfarm_with_fake_jobs("export " + db + " --sweep e --series TOR -o " + path("tor.csv")).exit_code, 0);
  std::ifstream tor(path("tor.csv"));
  std::string line;
  std::getline(tor, line);
  int tor_rows = 0;
  while (std::getline(tor, line)) {
    EXPECT_NE(line.find(",TOR.tau"), std::string::npos) << line;
    ++tor_rows;
  }
  EXPECT_EQ(tor_rows, 4 * 9 * 2);  // 4 done jobs × 9 samples × 2 joints
  const CommandResult unknown = test_support::run_armfarm_with_fake_jobs("export " + db + " --sweep e --series PHI -o " + path("phi.csv"));
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.output.find("sweep e has no recorded series PHI (it has: POS, TOR)"), std::string::npos) << unknown.output;
  EXPECT_FALSE(fs::exists(path("phi.csv")));
  EXPECT_FALSE(fs::exists(path("phi.csv.partial")));
  EXPECT_EQ(test_support::run_armfarm_with_fake_jobs("export " + db + " --sweep nope").exit_code, 2);
  EXPECT_EQ(test_support::run_armfarm_with_fake_jobs("export " + db).exit_code, 2);
  fs::remove_all(folder);
}

TEST(CsvWriting, FieldsAreQuotedPerRfc4180) {
  EXPECT_EQ(make_csv_field("plain"), "plain");
  EXPECT_EQ(make_csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(make_csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(make_csv_field("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(make_csv_field("cr\r"), "\"cr\r\"");
  EXPECT_EQ(make_csv_value_field(nlohmann::json(3)), "3");
  EXPECT_EQ(make_csv_value_field(nlohmann::json(0.25)), "0.25");
  EXPECT_EQ(make_csv_value_field(nlohmann::json::array({1, 2})), "\"[1,2]\"");
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/cli/cmd_export_metrics_test.cpp:
// `armfarm export DB --metrics`: a sweep's scalar metrics as one long-form CSV that Python's csv
// module reads back equal to the database (values bit for bit, empty where NULL with the stored
// reason beside, joints 1-based, checkpoints, units from metric_info), hostile parameter strings
// intact, a diverged job's metrics marked by its status.

namespace armfarm {
namespace {

using testing::TemporaryDirectory;
using testing::TestJob;

// The rows' checks (after test_support::kCsvCheckerStart): each row against its expected JSON line.
const char* kMetricRowChecks = R"py(
n_params = len(header) - 8
for number, (row, want) in enumerate(zip(rows, expected), start=2):
    assert len(row) == len(header), (number, row)
    assert row[0] == want["job"] and row[1] == want["status"], (number, row[:2])
    for i, p in enumerate(want["params"]):
        got = row[2 + i]
        assert (got == p) if isinstance(p, str) else (float(got) == p), (number, got, p)
    name, joint, checkpoint, value, unit, reason = row[2 + n_params:]
    assert name == want["name"], (number, name)
    assert joint == ("" if want["joint"] is None else str(want["joint"])), (number, joint)
    assert checkpoint == ("" if want["checkpoint"] is None else str(want["checkpoint"])), (number, checkpoint)
    if want["value"] is None:
        assert value == "" and reason != "", (number, value, reason)
    else:
        assert float(value) == float.fromhex(want["value"]), (number, value, want["value"])
        assert shortest(value), (number, value)
    assert unit == want["unit"], (number, unit, want["unit"])
    assert want["reason"] == "" or reason == want["reason"], (number, reason, want["reason"])
)py";

TEST(ExportMetrics, ALongFormCsvReadsBackInPythonEqualToTheDatabase) {
  TemporaryDirectory folder;
  const std::string db = folder.file("m.db");
  const std::string hostile = "arm, \"v2\"\nline two.urdf";
  std::vector<TestJob> jobs(3);
  jobs[0].params = {{"model", hostile}, {"learning.lwpr.init_D", 0.1}};
  jobs[0].metrics = {{0, "tracking_nmse", 1, 0.30000000000000004, ""},
                     {0, "tracking_nmse", 2, std::nullopt, "nMSE undefined: the target did not vary"},
                     {0, "tracking_nmse", std::nullopt, 0.30000000000000004, "mean over 1 of 2 joints"},
                     {0, "heldout_test_nmse", std::nullopt, 1e-300, "", 0},
                     {0, "heldout_test_nmse", std::nullopt, 2.5e-3, "", 200},
                     {0, "heldout_ff_fb_ratio_avg", 2, std::nullopt, "no feedback at this checkpoint", 200},
                     {0, "a_metric_without_info", std::nullopt, -7.25e-5, ""}};
  jobs[1].params = {{"model", "plain.urdf"}, {"learning.lwpr.init_D", 1.0 / 3.0}};
  jobs[1].status = "diverged";
  jobs[1].message = "state not finite at t = 0.2 s";
  jobs[1].metrics = {{0, "tracking_nmse", 1, 1e12, ""}};
  jobs[2].params = {{"model", "plain.urdf"}, {"learning.lwpr.init_D", 3.0}};
  jobs[2].status = "failed";
  jobs[2].message = "model not found";
  testing::write_test_sweep(db, "m", jobs);

  const testing::CommandResult exported = testing::run_armfarm("export " + db + " --metrics -o " + folder.file("m.csv"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_NE(exported.output.find("sweep m: 8 metric rows from 2 jobs (1 jobs without metrics)"), std::string::npos)
      << exported.output;

  // The expected rows, straight from the store.
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  std::map<std::string, std::string> units;
  for (const MetricInfoRecord& info : store.find_metric_info()) units[info.name] = info.unit;
  std::map<std::int64_t, JobRecord> job_by_id;
  for (const JobRecord& job : store.find_jobs("m")) job_by_id[job.id] = job;
  std::ofstream expected(folder.file("expected.jsonl"));
  int rows = 0;
  for (const MetricRecord& metric : store.find_sweep_metrics("m")) {
    const JobRecord& job = job_by_id.at(metric.job_id);
    nlohmann::json row = {{"job", job.key},
                          {"status", job.status},
                          {"params", {job.params.at("learning.lwpr.init_D"), job.params.at("model")}},
                          {"name", metric.name},
                          {"joint", metric.joint ? nlohmann::json(*metric.joint) : nlohmann::json()},
                          {"checkpoint", metric.checkpoint ? nlohmann::json(*metric.checkpoint) : nlohmann::json()},
                          {"value", metric.value ? nlohmann::json(test_support::make_hex(*metric.value)) : nlohmann::json()},
                          {"unit", units.count(metric.name) ? units.at(metric.name) : ""},
                          {"reason", metric.reason}};
    expected << row.dump() << "\n";
    ++rows;
  }
  expected.close();
  ASSERT_EQ(rows, 8);
  const nlohmann::json header = {"job", "status", "learning.lwpr.init_D", "model", "name", "joint", "checkpoint",
                                 "value", "unit", "reason"};
  std::ofstream(folder.file("header.json")) << header.dump();
  const test_support::CommandResult checked = test_support::run_csv_checker(
      folder.file("check.py"), kMetricRowChecks, folder.file("m.csv"), folder.file("expected.jsonl"), folder.file("header.json"));
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  EXPECT_EQ(checked.output, "checked 8 rows\n");

  // Spot checks on the text itself, independent of the store read above.
  std::ifstream in(folder.file("m.csv"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find(",tracking_nmse,2,,,1,nMSE undefined: the target did not vary\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",heldout_test_nmse,,200,0.0025,1,\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",heldout_test_nmse,,0,1e-300,1,\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",tracking_nmse,1,,0.30000000000000004,1,\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",a_metric_without_info,,,-7.25e-05,,\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",diverged,0.3333333333333333,plain.urdf,tracking_nmse,1,,1e+12,1,\n"), std::string::npos)
      << text;
}

TEST(ExportMetrics, AnUnknownSweepIsOneLineExitTwoAndNoFile) {
  TemporaryDirectory folder;
  const std::string db = folder.file("m.db");
  std::vector<TestJob> jobs(1);
  jobs[0].params = {{"seed", 1}};
  testing::write_test_sweep(db, "m", jobs);
  const testing::CommandResult result =
      testing::run_armfarm("export " + db + " --metrics --sweep nosuch -o " + folder.file("out.csv"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("nosuch"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(folder.file("out.csv")));
  EXPECT_FALSE(std::filesystem::exists(folder.file("out.csv.partial")));
  const testing::CommandResult both = testing::run_armfarm("export " + db + " --metrics --series POS");
  EXPECT_EQ(both.exit_code, 2) << both.output;
}

}  // namespace
}  // namespace armfarm
