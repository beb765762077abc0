// Tables: cells equal hand-computed aggregates; failed jobs are counted, never averaged in. Through
// the command line: tests/runner/cli/cmd_table_test.cpp; the aggregates themselves:
// tests/analysis/summary_statistics_test.cpp.
#include "analysis/analysis_error.hpp"
#include "analysis/table.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>

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
// of two kernel widths (values: testing::make_heldout_value).
using testing::make_heldout_value;

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

}  // namespace
}  // namespace armfarm

