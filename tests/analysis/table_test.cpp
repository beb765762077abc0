// Tables: cells equal hand-computed aggregates; failed jobs are counted, never averaged in.
#include "analysis/analysis_error.hpp"
#include "analysis/table.hpp"
#include "test_database.hpp"

#include <gtest/gtest.h>

#include <cmath>

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
  // init_D = 10: three seeds; test_nmse j1 = 0.1, 0.2, 0.3 → mean 0.2, std 0.1.
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
  ASSERT_EQ(table.columns.size(), 3u);  // test_nmse j1, test_nmse j2, n_receptive_fields
  EXPECT_EQ(table.columns[0].header, "test_nmse j1");
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
  EXPECT_NE(markdown.find("| 10 | 0.2 ± 0.1 (n=3) |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("1, 1 failed"), std::string::npos) << markdown;
  const std::string latex = format_table(table, TableFormat::latex, Aggregate::mean);
  EXPECT_NE(latex.find("\\begin{tabular}"), std::string::npos);
  EXPECT_NE(latex.find("test\\_nmse j1"), std::string::npos) << latex;
  EXPECT_NE(latex.find("0.2 $\\pm$ 0.1"), std::string::npos) << latex;
  const auto json = nlohmann::json::parse(format_table(table, TableFormat::json, Aggregate::median));
  EXPECT_DOUBLE_EQ(json["rows"][0]["cells"]["test_nmse j1"]["value"].get<double>(), 0.2);
  EXPECT_EQ(json["rows"][1]["jobs_failed"].get<int>(), 1);
  const std::string csv = format_table(table, TableFormat::csv, Aggregate::mean);
  EXPECT_NE(csv.find("learning.lwpr.init_D,test_nmse j1,test_nmse j1 std,test_nmse j1 n"), std::string::npos) << csv;
}

TEST(Table, NumbersUseScientificNotationWhereTheThesisDoes) {
  EXPECT_EQ(format_number(1.95e-3), "1.950e-03");
  EXPECT_EQ(format_number(9.38e-4, 3), "9.38e-04");
  EXPECT_EQ(format_number(0.890025), "0.89");
  EXPECT_EQ(format_number(137.0), "137");
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
  const auto json = nlohmann::json::parse(result.output);
  EXPECT_NEAR(json["rows"][0]["cells"]["ff_fb_ratio_avg"]["mean"].get<double>(), 0.85, 1e-12);
  EXPECT_EQ(json["rows"][0]["cells"]["ff_fb_ratio_avg"]["n"].get<int>(), 2);
  EXPECT_EQ(json["rows"][0]["params"]["joint"], "2");

  const auto bad = testing::run_armfarm("table " + db + " --cols no_such_metric");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("no metric 'no_such_metric'"), std::string::npos) << bad.output;
  const auto missing = testing::run_armfarm("table " + directory.file("absent.db"));
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
}

}  // namespace
}  // namespace armfarm
