// `armfarm export DB --sweep NAME`: a whole sweep as one long-form CSV that Python's csv module
// reads back with every value equal (bit for bit) to the database's, string parameters with
// commas and quotes intact; numbers in their shortest round-trip form; CSV fields per RFC 4180.
#include "results/results_store.hpp"
#include "runner/io/csv_writing.hpp"
#include "runner/io/sweep_export.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "support/csv_export_check.hpp"

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

TEST(CsvWriting, ShortestNumbersReadBackExactly) {
  EXPECT_EQ(make_shortest_number_text(0.1), "0.1");
  EXPECT_EQ(make_shortest_number_text(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(make_shortest_number_text(3.0 * 0.1 / 3.0 - 1e-17), make_shortest_number_text(3.0 * 0.1 / 3.0 - 1e-17));
  EXPECT_EQ(make_shortest_number_text(1e-300), "1e-300");
  EXPECT_EQ(make_shortest_number_text(-0.0), "-0");
  EXPECT_EQ(make_shortest_number_text(std::nan("")), "nan");
  EXPECT_EQ(make_shortest_number_text(-HUGE_VAL), "-inf");
  std::mt19937_64 bits(42);  // test data only
  for (int i = 0; i < 20000; ++i) {
    std::uint64_t word = bits();
    double value;
    std::memcpy(&value, &word, sizeof value);
    if (!std::isfinite(value)) continue;
    const std::string text = make_shortest_number_text(value);
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), value) << text;
    char longest[40];
    std::snprintf(longest, sizeof longest, "%.17g", value);
    EXPECT_LE(text.size(), std::string(longest).size() + 1) << text << " vs " << longest;  // +1: to_chars may add "e+"
  }
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

TEST(LongFormSignal, PerJointColumnsGiveTheJointOthersTheirName) {
  EXPECT_EQ(make_long_form_signal("PHI", "j3").joint, 3);
  EXPECT_EQ(make_long_form_signal("PHI", "j3").signal, "PHI");
  EXPECT_EQ(make_long_form_signal("PHI", "j12").joint, 12);
  EXPECT_FALSE(make_long_form_signal("POS", "x").joint);
  EXPECT_EQ(make_long_form_signal("POS", "x").signal, "POS.x");
  EXPECT_EQ(make_long_form_signal("TRIAL", "fb_abs_avg").signal, "TRIAL.fb_abs_avg");
  EXPECT_FALSE(make_long_form_signal("X", "j0").joint);
  EXPECT_FALSE(make_long_form_signal("X", "j").joint);
  EXPECT_FALSE(make_long_form_signal("X", "jx1").joint);
}

}  // namespace
}  // namespace armfarm
