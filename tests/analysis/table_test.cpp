// Tables: cells equal hand-computed aggregates; failed jobs are counted, never averaged in; through
// the command line, per-joint rows, suggestions for unknown names, pooling only across seeds and
// footnoted undefined cells.
#include "analysis/analysis_error.hpp"
#include "analysis/table.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace armfarm {
namespace {

JobResult make_job(double init_d, int seed, const std::string& status, std::map<MetricId, double> metrics) {
  JobResult job;
  job.key = "k" + std::to_string(init_d) + "_" + std::to_string(seed);
  job.status = status;
  job.seed = seed;
  job.params = {{"learning.lwpr.init_D", init_d}, {"seed", seed}};
  job.metrics = std::move(metrics);
  return job;
}

SweepData make_data() {
  SweepData data;
  data.name = "kernel";
  // init_D = 10: three seeds; test_nmse_j1 = 0.1, 0.2, 0.3 → mean 0.2, std 0.1.
  data.jobs.push_back(make_job(10, 1, "done", {{{"test_nmse", 1}, 0.1}, {{"test_nmse", 2}, 1.0}, {{"n_receptive_fields", {}}, 10}}));
  data.jobs.push_back(make_job(10, 2, "done", {{{"test_nmse", 1}, 0.2}, {{"test_nmse", 2}, 2.0}, {{"n_receptive_fields", {}}, 20}}));
  data.jobs.push_back(make_job(10, 3, "done", {{{"test_nmse", 1}, 0.3}, {{"test_nmse", 2}, 3.0}, {{"n_receptive_fields", {}}, 30}}));
  // init_D = 100: one done, one diverged whose (absurd) metric must not be averaged in.
  data.jobs.push_back(make_job(100, 1, "done", {{{"test_nmse", 1}, 0.05}, {{"test_nmse", 2}, 0.5}, {{"n_receptive_fields", {}}, 50}}));
  data.jobs.push_back(make_job(100, 2, "diverged", {{{"test_nmse", 1}, 1e9}}));
  data.varying_params = calc_varying_params(data.jobs);
  return data;
}

TEST(Table, CellsAreMeanStdAndCountOverRepeats) {
  const SweepData data = make_data();
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D"};
  spec.metrics = {"test_nmse", "n_receptive_fields"};
  const Table table = make_table(data, spec);
  ASSERT_EQ(table.rows.size(), 2u);
  ASSERT_EQ(table.columns.size(), 3u);  // test_nmse_j1, test_nmse_j2, n_receptive_fields
  EXPECT_EQ(table.columns[0].header, "test_nmse_j1");
  const TableRow& first = table.rows[0];
  EXPECT_EQ(first.labels[0], "10");
  EXPECT_EQ(first.jobs_done, 3);
  EXPECT_EQ(first.jobs_failed, 0);
  EXPECT_EQ(first.cells[0].count, 3);
  EXPECT_NEAR(first.cells[0].mean, 0.2, 1e-15);
  EXPECT_NEAR(first.cells[0].std_dev, 0.1, 1e-15);
  EXPECT_NEAR(first.cells[1].median, 2.0, 1e-15);
  EXPECT_NEAR(first.cells[2].mean, 20.0, 1e-12);
  const TableRow& second = table.rows[1];
  EXPECT_EQ(second.jobs_done, 1);
  EXPECT_EQ(second.jobs_failed, 1);
  EXPECT_EQ(second.cells[0].count, 1);
  EXPECT_DOUBLE_EQ(second.cells[0].mean, 0.05);  // the diverged job's 1e9 is not averaged in
}

TEST(Table, JointAsRowGivesThePerJointLayoutOfTheThesis) {
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D", "joint"};
  spec.metrics = {"test_nmse"};
  spec.where = {{"learning.lwpr.init_D", "10"}};
  const Table table = make_table(make_data(), spec);
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[1].labels[1], "2");
  EXPECT_NEAR(table.rows[1].cells[0].mean, 2.0, 1e-15);
}

TEST(Table, JointFilterAndAggregates) {
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D"};
  spec.metrics = {"test_nmse"};
  spec.joints = {2};
  const Table table = make_table(make_data(), spec);
  ASSERT_EQ(table.columns.size(), 1u);
  EXPECT_DOUBLE_EQ(table.rows[0].cells[0].value(Aggregate::min), 1.0);
  EXPECT_DOUBLE_EQ(table.rows[0].cells[0].value(Aggregate::max), 3.0);
}

TEST(Table, UnknownMetricOrParameterIsAnError) {
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D"};
  spec.metrics = {"no_such_metric"};
  EXPECT_THROW(make_table(make_data(), spec), AnalysisError);
  spec.metrics = {"test_nmse"};
  spec.rows = {"control.no_such"};
  EXPECT_THROW(make_table(make_data(), spec), AnalysisError);
}

TEST(Table, FormatsCarryTheNumbers) {
  TableSpec spec;
  spec.title = "kernel widths";
  spec.rows = {"learning.lwpr.init_D"};
  spec.metrics = {"test_nmse"};
  const Table table = make_table(make_data(), spec);
  const std::string markdown = format_table(table, TableFormat::markdown, Aggregate::mean);
  // 0.2 ∓ t(0.975, 2)·0.1/√3 = 0.2 ∓ 4.302653·0.057735 = 0.2 ∓ 0.248414.
  EXPECT_NE(markdown.find("| 10 | 0.2 [-0.04841, 0.4484] (n=3) |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("1, 1 failed"), std::string::npos) << markdown;
  const std::string latex = format_table(table, TableFormat::latex, Aggregate::mean);
  EXPECT_NE(latex.find("\\begin{tabular}"), std::string::npos);
  EXPECT_NE(latex.find("test\\_nmse\\_j1"), std::string::npos) << latex;
  EXPECT_NE(latex.find("0.2 [-0.04841, 0.4484]"), std::string::npos) << latex;
  const auto json = nlohmann::json::parse(format_table(table, TableFormat::json, Aggregate::median));
  EXPECT_DOUBLE_EQ(json["rows"][0]["cells"]["test_nmse_j1"]["value"].get<double>(), 0.2);
  EXPECT_EQ(json["rows"][1]["jobs_failed"].get<int>(), 1);
  const std::string csv = format_table(table, TableFormat::csv, Aggregate::mean);
  EXPECT_NE(csv.find("learning.lwpr.init_D,test_nmse_j1,test_nmse_j1 std,test_nmse_j1 n,test_nmse_j1 ci95_low,test_nmse_j1 ci95_high"),
            std::string::npos) << csv;
  EXPECT_NE(csv.find(",3,-0.048413"), std::string::npos) << csv;
}

// The interval against a hand computation: 1, 2, 3, 4, 5 have mean 3, std √2.5 = 1.581139,
// standard error 0.707107; t(0.975, 4) = 2.776445 (printed t tables), so 3 ∓ 1.963243.
TEST(SummaryStatistics, ConfidenceIntervalEqualsTheHandComputation) {
  const SummaryStatistics five = calc_summary_statistics({5.0, 1.0, 4.0, 2.0, 3.0});
  EXPECT_EQ(five.count, 5);
  ASSERT_TRUE(five.has_ci());
  EXPECT_NEAR(five.ci_low, 3.0 - 1.963243, 2e-6);
  EXPECT_NEAR(five.ci_high, 3.0 + 1.963243, 2e-6);
  // Two values: t(0.975, 1) = tan(0.475π) = 12.706205 in closed form; 0.5 ∓ 12.706205·0.5.
  const SummaryStatistics two = calc_summary_statistics({0.0, 1.0});
  EXPECT_NEAR(two.ci_high, 0.5 + 0.5 * std::tan(0.475 * M_PI), 1e-9);
  EXPECT_NEAR(two.ci_low, 0.5 - 0.5 * std::tan(0.475 * M_PI), 1e-9);
  // One value has no interval; equal values an empty one.
  const SummaryStatistics one = calc_summary_statistics({0.7});
  EXPECT_FALSE(one.has_ci());
  EXPECT_EQ(format_mean_ci(one), "0.7");
  const SummaryStatistics same = calc_summary_statistics({0.7, 0.7, 0.7});
  EXPECT_DOUBLE_EQ(same.ci_low, 0.7);
  EXPECT_DOUBLE_EQ(same.ci_high, 0.7);
  EXPECT_EQ(format_mean_ci(five), "3 [1.037, 4.963]");
}

// The quantile against closed forms (ν = 1: tan(π(p − ½)); ν = 2: (2p − 1)/√(2p(1 − p))) and
// against printed tables for larger ν (t(0.975, 9) = 2.262157, t(0.975, 29) = 2.045230); it
// tends to the normal 1.959964.
TEST(SummaryStatistics, StudentTQuantileMatchesClosedFormsAndTables) {
  for (double p : {0.6, 0.9, 0.975, 0.995}) {
    EXPECT_NEAR(calc_student_t_quantile(p, 1), std::tan(M_PI * (p - 0.5)), 1e-9 * std::tan(M_PI * (p - 0.5))) << p;
    EXPECT_NEAR(calc_student_t_quantile(p, 2), (2 * p - 1) / std::sqrt(2 * p * (1 - p)), 1e-10) << p;
  }
  EXPECT_NEAR(calc_student_t_quantile(0.975, 9), 2.262157, 1e-6);
  EXPECT_NEAR(calc_student_t_quantile(0.975, 29), 2.045230, 1e-6);
  EXPECT_NEAR(calc_student_t_quantile(0.975, 100000), 1.959964, 1e-4);
  EXPECT_NEAR(calc_student_t_quantile(0.025, 4), -2.776445, 1e-6);
  EXPECT_NEAR(calc_student_t_cdf(0.0, 7), 0.5, 1e-15);
}

// The one-sided sign test: 5 of 5 gives 1/32, 4 of 5 gives 6/32, 9 of 10 gives 11/1024.
TEST(SummaryStatistics, SignTestIsTheBinomialTail) {
  EXPECT_NEAR(calc_sign_test_p(5, 5), 1.0 / 32, 1e-15);
  EXPECT_NEAR(calc_sign_test_p(4, 5), 6.0 / 32, 1e-14);
  EXPECT_NEAR(calc_sign_test_p(9, 10), 11.0 / 1024, 1e-14);
  EXPECT_NEAR(calc_sign_test_p(0, 4), 1.0, 1e-14);
  EXPECT_EQ(calc_sign_test_p(0, 0), 1.0);
}

TEST(Table, NumbersUseScientificNotationWhereTheThesisDoes) {
  EXPECT_EQ(format_table_number(1.95e-3), "1.950e-03");
  EXPECT_EQ(format_table_number(9.38e-4, 3), "9.38e-04");
  EXPECT_EQ(format_table_number(0.890025), "0.89");
  EXPECT_EQ(format_table_number(137.0), "137");
}

TEST(Table, DefaultTablesFollowTheThesis) {
  SweepData data;
  data.name = "figure8";
  JobResult job = make_job(10, 1, "done",
                           {{{"ff_fb_ratio_avg", 1}, 0.9}, {{"ff_fb_ratio_var", 1}, 0.01}, {{"ff_abs_avg", 1}, 0.3},
                            {{"fb_abs_avg", 1}, 0.02}, {{"tracking_nmse_y", {}}, 1e-3}, {{"tracking_nmse_z", {}}, 2e-4}});
  data.jobs.push_back(job);
  data.varying_params = {"learning.lwpr.init_D"};
  const auto specs = make_default_table_specs(data);
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[0].rows.back(), "joint");
  EXPECT_EQ(specs[0].metrics.size(), 4u);
  EXPECT_EQ(specs[1].metrics, (std::vector<std::string>{"tracking_nmse_y", "tracking_nmse_z"}));
}

// Held-out metrics: per joint and as a job-level mean, at checkpoints 0 and 5, for two seeds
// of two kernel widths; value = init_D + 0.1 × joint + 0.01 × checkpoint + 0.001 × seed, so
// every cell names the (row, joint, checkpoint) it came from.
double make_heldout_value(double init_d, std::optional<int> joint, std::int64_t checkpoint, int seed) {
  return init_d + 0.1 * joint.value_or(0) + 0.01 * static_cast<double>(checkpoint) + 0.001 * seed;
}

SweepData make_heldout_data() {
  SweepData data;
  data.name = "heldout";
  for (double init_d : {10.0, 100.0}) {
    for (int seed = 1; seed <= 2; ++seed) {
      std::map<MetricId, double> metrics = {{{"ff_fb_ratio_avg", 1}, 0.5}, {{"n_receptive_fields", {}}, 7}};
      for (std::int64_t checkpoint : {0, 5}) {
        metrics[{"heldout_test_nmse", std::nullopt, checkpoint}] = make_heldout_value(init_d, std::nullopt, checkpoint, seed);
        for (int joint = 1; joint <= 2; ++joint) {
          metrics[{"heldout_test_nmse", joint, checkpoint}] = make_heldout_value(init_d, joint, checkpoint, seed);
          metrics[{"heldout_ff_fb_ratio_avg", joint, checkpoint}] = make_heldout_value(init_d, joint, checkpoint, seed);
        }
      }
      data.jobs.push_back(make_job(init_d, seed, "done", metrics));
    }
  }
  data.varying_params = calc_varying_params(data.jobs);
  return data;
}

TEST(Table, CheckpointAsRowGivesOneRowPerCheckpoint) {
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D", "checkpoint"};
  spec.metrics = {"heldout_test_nmse", "n_receptive_fields"};
  const Table table = make_table(make_heldout_data(), spec);
  ASSERT_EQ(table.rows.size(), 4u);
  ASSERT_EQ(table.columns.size(), 2u);
  EXPECT_EQ(table.columns[0].header, "heldout_test_nmse");
  EXPECT_EQ(table.rows[1].labels, (std::vector<std::string>{"10", "5"}));
  EXPECT_EQ(table.rows[1].checkpoint, 5);
  // Job-level mean at checkpoint 5 over seeds 1 and 2.
  EXPECT_NEAR(table.rows[1].cells[0].mean, 10.05 + 0.0015, 1e-12);
  EXPECT_EQ(table.rows[1].cells[0].count, 2);
  EXPECT_NEAR(table.rows[2].cells[0].mean, 100.0 + 0.0015, 1e-12);
  // A training-run metric has no value per checkpoint: "–" with a footnote.
  EXPECT_EQ(table.rows[1].cells[1].count, 0);
  ASSERT_NE(table.rows[1].footnotes[1], 0);
  EXPECT_NE(table.footnotes[static_cast<std::size_t>(table.rows[1].footnotes[1] - 1)].find("not evaluated per checkpoint"),
            std::string::npos);
}

TEST(Table, CsvCarriesNoCommentRowsUnlessNotesAreAskedFor) {
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D", "checkpoint"};
  spec.metrics = {"heldout_test_nmse", "n_receptive_fields"};
  const Table table = make_table(make_heldout_data(), spec);
  ASSERT_FALSE(table.footnotes.empty());  // the "not evaluated per checkpoint" cells
  const std::string plain = format_table(table, TableFormat::csv, Aggregate::mean);
  EXPECT_EQ(plain.find('#'), std::string::npos) << plain;
  // Every line has the header's number of fields: a CSV reader sees one rectangular table.
  std::istringstream lines(plain);
  std::string line;
  std::getline(lines, line);
  const auto fields = std::count(line.begin(), line.end(), ',');
  int n_lines = 0;
  while (std::getline(lines, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), fields) << line;
    ++n_lines;
  }
  EXPECT_EQ(n_lines, static_cast<int>(table.rows.size()));
  const std::string noted = format_table(table, TableFormat::csv, Aggregate::mean, CsvNotes::comment_lines);
  EXPECT_EQ(noted.substr(0, plain.size()), plain);
  EXPECT_NE(noted.find("\n# [1] "), std::string::npos) << noted;
  EXPECT_NE(noted.find("not evaluated per checkpoint"), std::string::npos) << noted;
}

TEST(Table, CsvNumbersAreTheShortestTextThatReadsBack) {
  SweepData data;
  data.name = "short";
  data.jobs.push_back(make_job(10, 1, "done", {{{"test_nmse", 1}, 0.1}}));
  data.jobs.push_back(make_job(20, 1, "done", {{{"test_nmse", 1}, 1.0 / 3.0}}));
  data.varying_params = calc_varying_params(data.jobs);
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D"};
  spec.metrics = {"test_nmse"};
  const std::string csv = format_table(make_table(data, spec), TableFormat::csv, Aggregate::mean);
  EXPECT_NE(csv.find("\n10,0.1,"), std::string::npos) << csv;  // %.17g would print 0.10000000000000001
  EXPECT_NE(csv.find("\n20,0.3333333333333333,"), std::string::npos) << csv;
}

TEST(Table, CheckpointAndJointRowsNestInTheOrderGiven) {
  const SweepData data = make_heldout_data();
  for (const auto& rows : {std::vector<std::string>{"learning.lwpr.init_D", "checkpoint", "joint"},
                           std::vector<std::string>{"joint", "checkpoint", "learning.lwpr.init_D"}}) {
    TableSpec spec;
    spec.rows = rows;
    spec.metrics = {"heldout_ff_fb_ratio_avg", "heldout_test_nmse"};
    const Table table = make_table(data, spec);
    ASSERT_EQ(table.rows.size(), 8u);  // 2 kernel widths × 2 checkpoints × 2 joints
    for (const TableRow& row : table.rows) {
      ASSERT_TRUE(row.joint && row.checkpoint);
      const double init_d = std::stod(row.labels[rows[0] == "joint" ? 2 : 0]);
      const double expected = make_heldout_value(init_d, row.joint, *row.checkpoint, 1) + 0.0005;  // mean of seeds 1, 2
      EXPECT_NEAR(row.cells[0].mean, expected, 1e-12) << row.labels[0] << " " << row.labels[1] << " " << row.labels[2];
      EXPECT_NEAR(row.cells[1].mean, expected, 1e-12);
    }
  }
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D", "checkpoint", "joint"};
  spec.metrics = {"heldout_ff_fb_ratio_avg"};
  const Table table = make_table(data, spec);
  EXPECT_EQ(table.rows[1].labels, (std::vector<std::string>{"10", "0", "2"}));
  EXPECT_EQ(table.rows[2].labels, (std::vector<std::string>{"10", "5", "1"}));
  // Swept parameters group first; joint and checkpoint expand inside a group, in the order given.
  spec.rows = {"joint", "checkpoint", "learning.lwpr.init_D"};
  EXPECT_EQ(make_table(data, spec).rows[1].labels, (std::vector<std::string>{"1", "5", "10"}));
  EXPECT_EQ(make_table(data, spec).rows[2].labels, (std::vector<std::string>{"2", "0", "10"}));
}

TEST(Table, WithoutCheckpointRowsACheckpointedMetricGetsAColumnPerCheckpoint) {
  const SweepData data = make_heldout_data();
  TableSpec spec;
  spec.rows = {"learning.lwpr.init_D"};
  spec.metrics = {"heldout_test_nmse", "heldout_ff_fb_ratio_avg"};
  spec.joints = {2};
  const Table table = make_table(data, spec);
  std::vector<std::string> headers;
  for (const TableColumn& column : table.columns) headers.push_back(column.header);
  EXPECT_EQ(headers, (std::vector<std::string>{"heldout_test_nmse_c0", "heldout_test_nmse_c5", "heldout_ff_fb_ratio_avg_j2_c0",
                                               "heldout_ff_fb_ratio_avg_j2_c5"}));
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_NEAR(table.rows[1].cells[1].mean, make_heldout_value(100, std::nullopt, 5, 1) + 0.0005, 1e-12);
  EXPECT_NEAR(table.rows[1].cells[3].mean, make_heldout_value(100, 2, 5, 1) + 0.0005, 1e-12);

  TableSpec joints;
  joints.rows = {"learning.lwpr.init_D", "joint"};
  joints.metrics = {"heldout_ff_fb_ratio_avg"};
  const Table per_joint = make_table(data, joints);
  ASSERT_EQ(per_joint.columns.size(), 2u);
  EXPECT_EQ(per_joint.columns[1].header, "heldout_ff_fb_ratio_avg_c5");
  EXPECT_NEAR(per_joint.rows[1].cells[1].mean, make_heldout_value(10, 2, 5, 1) + 0.0005, 1e-12);
}

TEST(Table, CheckpointRowsNeedCheckpointedMetrics) {
  TableSpec spec;
  spec.rows = {"checkpoint"};
  spec.metrics = {"n_receptive_fields"};
  try {
    make_table(make_data(), spec);
    FAIL() << "expected an AnalysisError";
  } catch (const AnalysisError& error) {
    EXPECT_NE(std::string(error.what()).find("no checkpointed"), std::string::npos) << error.what();
  }
}

TEST(Table, DefaultTablesAddTheHeldOutEvaluation) {
  const auto specs = make_default_table_specs(make_heldout_data());
  ASSERT_EQ(specs.size(), 4u);
  EXPECT_EQ(specs[0].title.rfind("Training run", 0), 0u) << specs[0].title;
  EXPECT_EQ(specs[1].title.rfind("Training run", 0), 0u) << specs[1].title;
  EXPECT_EQ(specs[2].rows, (std::vector<std::string>{"learning.lwpr.init_D", "checkpoint"}));
  EXPECT_EQ(specs[2].metrics, (std::vector<std::string>{"heldout_test_nmse"}));
  EXPECT_EQ(specs[3].rows, (std::vector<std::string>{"learning.lwpr.init_D", "checkpoint", "joint"}));
  EXPECT_EQ(specs[3].metrics, (std::vector<std::string>{"heldout_ff_fb_ratio_avg"}));
  // Without held-out metrics there is no held-out table.
  for (const TableSpec& spec : make_default_table_specs(make_data())) {
    EXPECT_EQ(spec.title.find("Held-out"), std::string::npos) << spec.title;
  }
}

// Through the command line on small generated databases: per-joint rows show per-joint values,
// unknown names are refused with a suggestion, rows pool only across seeds, undefined cells are
// footnoted with their reason.

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
