// Issue 11 ("numbers users can trust") through the command line on small generated databases:
// per-joint rows show per-joint values, unknown names are refused with a suggestion, repeats
// pool only across seeds, undefined cells are footnoted, merges ignore timings, and sweeps
// whose names sanitise alike get their own pages.
#include "analysis/figure.hpp"
#include "analysis/plots.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include <algorithm>
#include <filesystem>

namespace armfarm {
namespace {

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

// Two gain scales × two seeds; tracking_nmse per joint 1–3 plus its job mean (as the job writes it).
std::vector<testing::TestJob> make_gain_jobs(bool with_timing_of = false, double microseconds = 20.0) {
  std::vector<testing::TestJob> jobs;
  for (double gain : {0.2, 1.0}) {
    for (int seed = 1; seed <= 2; ++seed) {
      testing::TestJob job;
      job.params = {{"control.gain_scale", gain}, {"seed", seed}};
      double sum = 0.0;
      for (int joint = 1; joint <= 3; ++joint) {
        const double value = 0.01 * joint / gain + 0.001 * seed;
        sum += value;
        job.metrics.push_back({0, "tracking_nmse", joint, value, ""});
      }
      job.metrics.push_back({0, "tracking_nmse", std::nullopt, sum / 3.0, "mean over 3 of 3 joints"});
      if (with_timing_of) job.metrics.push_back({0, "learner_us_per_update", std::nullopt, microseconds, ""});
      jobs.push_back(job);
    }
  }
  return jobs;
}

TEST(TrustedNumbers, PerJointRowsShowPerJointValues) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::write_test_sweep(db, "gains", make_gain_jobs());
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

TEST(TrustedNumbers, UnknownNamesExitTwoWithASuggestion) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::write_test_sweep(db, "gains", make_gain_jobs());
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

TEST(TrustedNumbers, RowsPoolOnlyJobsThatDifferInTheirSeed) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::write_test_sweep(db, "gains", make_gain_jobs());
  // Rows by joint alone would pool both gain scales: refused, naming the parameter.
  const auto pooled = testing::run_armfarm("table " + db + " --rows joint --cols tracking_nmse");
  EXPECT_EQ(pooled.exit_code, 2) << pooled.output;
  EXPECT_NE(pooled.output.find("differ in control.gain_scale"), std::string::npos) << pooled.output;
  EXPECT_EQ(testing::run_armfarm("table " + db + " --rows joint --cols tracking_nmse --where control.gain_scale=1").exit_code, 0);
}

TEST(TrustedNumbers, UndefinedCellsPrintADashWithTheirReason) {
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

TEST(TrustedNumbers, MergeOfRunsDifferingOnlyInTimingExitsZero) {
  testing::TemporaryDirectory directory;
  testing::write_test_sweep(directory.file("a.db"), "gains", make_gain_jobs(true, 20.0));
  testing::write_test_sweep(directory.file("b.db"), "gains", make_gain_jobs(true, 31.0));
  const auto merged = testing::run_armfarm("merge " + directory.file("out.db") + " " + directory.file("a.db") + " " +
                                           directory.file("b.db"));
  EXPECT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(merged.output.find("conflict:"), std::string::npos) << merged.output;
  EXPECT_NE(merged.output.find("4 identical, 0 conflicts"), std::string::npos) << merged.output;
  // compare agrees: timing is not a result.
  EXPECT_EQ(testing::run_armfarm("compare " + directory.file("a.db") + " " + directory.file("b.db")).exit_code, 0);
}

TEST(TrustedNumbers, SweepsNamedAlikeGetTwoPages) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::write_test_sweep(db, "a-b", make_gain_jobs());
  testing::write_test_sweep(db, "a_b", make_gain_jobs());
  const auto report = testing::run_armfarm("report " + db + " --out " + directory.file("report"));
  ASSERT_EQ(report.exit_code, 0) << report.output;
  int pages = 0;
  for (const auto& entry : std::filesystem::directory_iterator(directory.file("report"))) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("sweep_a", 0) == 0 && entry.path().extension() == ".html") ++pages;  // sweep_a-b, sweep_a_b
  }
  EXPECT_EQ(pages, 2) << report.output;
}

}  // namespace
}  // namespace armfarm

namespace armfarm {
namespace {

// Figures: nMSE over decades gets a log axis whose error bars stay above zero, and an unplotted
// swept parameter splits the curves instead of being pooled into the error bars.
TEST(TrustedFigures, LogAxesPositiveErrorBarsAndNoSilentPooling) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  std::vector<testing::TestJob> jobs;
  for (const char* mode : {"online", "batch"}) {
    for (double init_d : {0.01, 0.1, 1.0}) {
      for (int seed = 1; seed <= 2; ++seed) {
        testing::TestJob job;
        job.params = {{"learning.mode", mode}, {"learning.lwpr.init_D", init_d}, {"seed", seed}};
        // Spread over seeds larger than the mean's half: mean − std < 0 on a linear axis.
        const double value = (std::string(mode) == "online" ? 1.0 : 100.0) * init_d * (seed == 1 ? 0.1 : 1.9);
        job.metrics = {{0, "tracking_nmse", std::nullopt, value, ""}};
        jobs.push_back(job);
      }
    }
  }
  testing::write_test_sweep(db, "modes", jobs);
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  PlotRequest request;
  request.kind = PlotKind::metric_vs_param;
  request.metric = "tracking_nmse";
  request.param = "learning.lwpr.init_D";
  const Figure figure = make_plot_figure(store, request);
  ASSERT_EQ(figure.panels.size(), 1u);
  const Panel& panel = figure.panels[0];
  EXPECT_TRUE(panel.log_x);
  EXPECT_TRUE(panel.log_y);
  EXPECT_EQ(panel.y_label, "tracking nMSE");  // readable; unit "1" of metric_info: dimensionless, no unit
  ASSERT_EQ(panel.curves.size(), 2u);          // online and batch, not pooled
  EXPECT_EQ(panel.curves[0].title, "mode=online");
  // The mean and its 95 % Student-t interval, as the tables print them: the two seeds' values
  // a = 0.1 v and b = 1.9 v have mean v and half-width t(0.975, 1) · |b − a| / 2 = 12.7062 · 0.9 v.
  ASSERT_TRUE(panel.y_min.has_value());  // the low ends are below zero: clipped at the axis
  EXPECT_GT(*panel.y_min, 0.0);
  for (const Curve& curve : panel.curves) {
    ASSERT_EQ(curve.x.size(), 3u);
    for (std::size_t i = 0; i < curve.y.size(); ++i) {
      const double v = curve.x[i] * (curve.title == "mode=online" ? 1.0 : 100.0);
      EXPECT_NEAR(curve.y[i], v, 1e-12 * v);
      EXPECT_NEAR(curve.y_high[i], v + 12.7062047 * 0.9 * v, 1e-6 * v);
      EXPECT_DOUBLE_EQ(curve.y_low[i], *panel.y_min);  // on the axis, never at or below zero
      EXPECT_LT(curve.y_low[i], 0.01);                 // below every mean drawn
    }
  }
  request.log_y = false;  // forced linear: the interval reaches below zero, the bar stops at zero
  const Figure linear = make_plot_figure(store, request);
  EXPECT_FALSE(linear.panels[0].log_y);
  EXPECT_FALSE(linear.panels[0].y_min.has_value());
  EXPECT_EQ(linear.panels[0].curves[0].y_low[0], 0.0);
  // Twelve colours before line styles repeat; one legend entry per title.
  Figure many;
  many.panels.resize(2);
  for (Panel& p : many.panels) {
    for (int c = 0; c < 13; ++c) p.curves.push_back(Curve{"curve " + std::to_string(c), {0, 1}, {0, 1}, {}, {}});
  }
  const std::string script = make_gnuplot_script(many, TerminalSettings{"set terminal svg"}, "out.svg", "/tmp");
  EXPECT_NE(script.find("lc rgb '" + figure_colours()[0] + "' dt 2"), std::string::npos);  // the 13th curve: first colour, dashed
  EXPECT_NE(script.find("notitle"), std::string::npos);                // second panel repeats no legend
  std::size_t titled = 0;
  for (auto at = script.find(" title 'curve "); at != std::string::npos; at = script.find(" title 'curve ", at + 1)) ++titled;
  EXPECT_EQ(titled, 13u);
  // The same group keeps its colour in every panel, whatever the order it is drawn in.
  Figure swapped;
  swapped.panels.resize(2);
  swapped.panels[0].curves = {Curve{"online", {0, 1}, {0, 1}, {}, {}}, Curve{"batch", {0, 1}, {1, 0}, {}, {}}};
  swapped.panels[1].curves = {Curve{"batch", {0, 1}, {0, 1}, {}, {}}};
  const std::string two = make_gnuplot_script(swapped, TerminalSettings{"set terminal svg"}, "out.svg", "/tmp");
  const std::string batch = "lc rgb '" + figure_colours()[1] + "'";
  const auto batch_colour = two.find(batch);
  ASSERT_NE(batch_colour, std::string::npos);
  EXPECT_NE(two.find(batch, batch_colour + 1), std::string::npos) << two;  // batch twice, one colour
}

// Log x for log-spaced swept values even within one decade (0.02, 0.05, 0.2, the quick start's
// init_D), not for evenly spaced ones; a diverged job is a mark on the top edge at its x.
TEST(TrustedFigures, LogSpacedValuesGetALogAxisAndUnfinishedJobsAMark) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  const auto write = [&](const std::string& sweep, const std::vector<double>& values) {
    std::vector<testing::TestJob> jobs;
    for (double value : values) {
      testing::TestJob job;
      job.params = {{"learning.lwpr.init_D", value}};
      job.metrics = {{0, "tracking_nmse", std::nullopt, 0.01 + value / 100, ""}};
      jobs.push_back(job);
    }
    jobs.back().status = "diverged";
    jobs.back().metrics.clear();
    testing::write_test_sweep(db, sweep, jobs);
  };
  write("log", {0.02, 0.05, 0.2, 0.5});
  write("even", {1.0, 2.0, 3.0, 4.0});
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  PlotRequest request;
  request.kind = PlotKind::metric_vs_param;
  request.metric = "tracking_nmse";
  request.param = "learning.lwpr.init_D";
  request.sweep = "log";
  const Figure log = make_plot_figure(store, request);
  EXPECT_TRUE(log.panels[0].log_x);
  EXPECT_EQ(log.panels[0].edge_marks_x, std::vector<double>{0.5});
  EXPECT_NE(std::find(log.caption.begin(), log.caption.end(), "marked on the top edge: 1 diverged"), log.caption.end());
  request.sweep = "even";
  const Figure even = make_plot_figure(store, request);
  EXPECT_FALSE(even.panels[0].log_x);
  EXPECT_EQ(even.panels[0].edge_marks_x, std::vector<double>{4.0});
  // The mark is drawn on the frame in graph coordinates, with one legend entry.
  const std::string script = make_gnuplot_script(even, TerminalSettings{"set terminal svg"}, "out.svg", "/tmp");
  EXPECT_NE(script.find("set label 1 '' at first 4, graph 1 point pt 11"), std::string::npos) << script;
  EXPECT_NE(script.find("keyentry with points pt 11 ps 1.4 lc rgb '#CC3311' title 'not finished (1 diverged), at its init_D'"),
            std::string::npos)
      << script;
}

}  // namespace
}  // namespace armfarm
