// Plots and the report render from a small database: valid SVG/PNG files with the expected
// series, one-line errors when the sweep lacks what a plot needs; log axes where values span
// decades, error bars above zero there, no silent pooling, marks for unfinished jobs.
#include "analysis/analysis_error.hpp"
#include "analysis/figure.hpp"
#include "analysis/plots.hpp"
#include "analysis/report.hpp"
#include "svg_text_boxes.hpp"
#include "support/test_database.hpp"

#include "support/text_file.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace armfarm {
namespace {


using testing::make_series;

// Figure 6.1's sweep as the thesis runs it (sweeps/thesis/fig6_1_kernel_width.json): init_D
// from 0.01 to 3 against update_D, 5 seeds, 60 jobs, each with a recorded path; receptive
// fields in the thousands for narrow kernels.
void write_kernel_width_sweep(const std::string& db) {
  std::vector<testing::TestJob> jobs;
  for (bool update_d : {false, true}) {
    for (double init_d : {0.01, 0.03, 0.1, 0.3, 1.0, 3.0}) {
      for (int seed = 1; seed <= 5; ++seed) {
        testing::TestJob job;
        job.params = {{"learning.lwpr.update_D", update_d}, {"learning.lwpr.init_D", init_d}, {"seed", seed}};
        const double nmse = 0.002 / std::sqrt(init_d) * (update_d ? 0.7 : 1.0) * (1 + 0.05 * seed);
        job.metrics = {{0, "same_run_test_nmse", 1, nmse, ""}, {0, "same_run_test_nmse", 2, 1.5 * nmse, ""},
                       {0, "n_receptive_fields", std::nullopt, std::round(1500 * std::pow(init_d, 0.6) + 7 * seed), ""}};
        constexpr int n = 40;
        for (const char* name : {"POS_D", "POS"}) {
          const double error = std::string(name) == "POS" ? 0.002 * init_d + 0.0001 * seed : 0.0;
          job.series.push_back(make_series(name, {"t", "x", "y", "z"}, n, [&](int r, int c) {
            const double t = 7.5 * r / n;
            return c == 0 ? t : c == 1 ? 0.5 : c == 2 ? 0.15 * std::sin(0.8378 * t) + error : 0.6 + 0.1 * std::sin(1.6755 * t);
          }));
        }
        jobs.push_back(job);
      }
    }
  }
  testing::write_test_sweep(db, "fig6_1_kernel_width", jobs);
}

// Sweep "kernel": init_D 1, 10, 100 against update_D, 2 seeds; nMSE of two joints and receptive fields.
void write_kernel_sweep(const std::string& db) {
  std::vector<testing::TestJob> kernel_jobs;
  for (bool update_d : {false, true}) {
    for (double init_d : {1.0, 10.0, 100.0}) {
      for (int seed = 1; seed <= 2; ++seed) {
        testing::TestJob job;
        job.params = {{"learning.lwpr.init_D", init_d}, {"learning.lwpr.update_D", update_d}, {"seed", seed}};
        const double nmse = 0.1 / std::sqrt(init_d) + (update_d ? 0.02 : 0.0) + 0.001 * seed;
        job.metrics = {{0, "same_run_test_nmse", 1, nmse, ""}, {0, "same_run_test_nmse", 2, 2 * nmse, ""},
                       {0, "n_receptive_fields", std::nullopt, 5 * init_d + (update_d ? 10 : 0), ""}};
        kernel_jobs.push_back(job);
      }
    }
  }
  testing::write_test_sweep(db, "kernel", kernel_jobs);
}

// Sweep "tracking": feedback against composite control, one job each, with desired and actual
// paths (200 rows), the torque series F, FF and TOR, receptive fields per trial and ff_fb_ratio_avg.
void write_tracking_sweep(const std::string& db) {
  std::vector<testing::TestJob> tracking_jobs;
  for (const char* mode : {"feedback", "composite"}) {
    testing::TestJob job;
    job.params = {{"control.mode", mode}};
    const double error = std::string(mode) == "feedback" ? 0.05 : 0.005;
    constexpr int n = 200;  // a constant: read inside the lambda without a capture
    auto time = [](int r) { return 4.0 * r / n; };
    job.series.push_back(make_series("POS_D", {"t", "x", "y", "z"}, n, [&](int r, int c) {
      const double t = time(r);
      return c == 0 ? t : c == 1 ? 0.5 : c == 2 ? 0.2 * std::sin(M_PI * t) : 0.4 + 0.1 * std::sin(2 * M_PI * t);
    }));
    job.series.push_back(make_series("POS", {"t", "x", "y", "z"}, n, [&](int r, int c) {
      const double t = time(r);
      return c == 0 ? t : c == 1 ? 0.5 : c == 2 ? 0.2 * std::sin(M_PI * t) + error : 0.4 + 0.1 * std::sin(2 * M_PI * t) - error;
    }));
    for (const char* name : {"F", "FF", "TOR"}) {
      job.series.push_back(make_series(name, {"t", "joint 1", "joint 2"}, n, [&](int r, int c) {
        return c == 0 ? time(r) : (std::string(name) == "F" ? 0.1 : 1.0) * std::cos(time(r) * c);
      }));
    }
    job.series.push_back(make_series("RF", {"trial", "n_receptive_fields"}, 20, [](int r, int c) {
      return c == 0 ? r + 1 : 40.0 * (1 - std::exp(-0.2 * (r + 1)));
    }));
    job.metrics = {{0, "ff_fb_ratio_avg", 1, std::string(mode) == "feedback" ? 0.0 : 0.9, ""}};
    tracking_jobs.push_back(job);
  }
  testing::write_test_sweep(db, "tracking", tracking_jobs);
}

// Sweep "fixed": init_D 1, 10, 100, 2 seeds, update_D fixed (in every config, not swept); one job
// diverged (no metrics), and a held-out nMSE at checkpoint 1.
void write_fixed_sweep(const std::string& db) {
  std::vector<testing::TestJob> fixed_jobs;
  for (double init_d : {1.0, 10.0, 100.0}) {
    for (int seed = 1; seed <= 2; ++seed) {
      testing::TestJob job;
      job.params = {{"learning.lwpr.init_D", init_d}, {"seed", seed}};
      const double nmse = 0.1 / std::sqrt(init_d) + 0.001 * seed;
      job.metrics = {{0, "same_run_test_nmse", 1, nmse, ""}, {0, "n_receptive_fields", std::nullopt, 5 * init_d, ""}};
      MetricRecord heldout{0, "heldout_test_nmse", 1, nmse / 2, ""};
      heldout.checkpoint = 1;
      job.metrics.push_back(heldout);
      if (init_d == 100.0 && seed == 2) {
        job.status = "diverged";
        job.metrics.clear();
      }
      fixed_jobs.push_back(job);
    }
  }
  testing::write_test_sweep(db, "fixed", fixed_jobs);
}

// Sweep "seven": a 7-joint arm, online and batch against four init_D: seven panels of nMSE and
// torques, long legend entries, narrow tick spacing.
void write_seven_joint_sweep(const std::string& db) {
  std::vector<testing::TestJob> seven_jobs;
  for (const char* mode : {"online", "batch"}) {
    for (double init_d : {0.5, 5.0, 50.0, 500.0}) {
      testing::TestJob job;
      job.params = {{"learning.mode", mode}, {"learning.lwpr.init_D", init_d}};
      for (int j = 1; j <= 7; ++j) job.metrics.push_back({0, "same_run_test_nmse", j, 0.01 * j / std::sqrt(init_d), ""});
      job.metrics.push_back({0, "n_receptive_fields", std::nullopt, 3 * init_d, ""});
      std::vector<std::string> columns{"t"};
      for (int j = 1; j <= 7; ++j) columns.push_back("joint " + std::to_string(j));
      for (const char* name : {"F", "FF", "TOR"}) {
        job.series.push_back(make_series(name, columns, 120, [&](int r, int c) {
          return c == 0 ? 0.24 + 0.0004 * r : 12.5 * std::sin(0.05 * r * c) / c;
        }));
      }
      job.series.push_back(make_series("POS_D", {"t", "x", "y", "z"}, 120, [](int r, int c) {
        return c == 0 ? 0.01 * r : c == 2 ? 0.2 * std::sin(0.05 * r) : c == 3 ? 0.4 + 0.1 * std::cos(0.05 * r) : 0.5;
      }));
      job.series.push_back(make_series("POS", {"t", "x", "y", "z"}, 120, [&](int r, int c) {
        return c == 0 ? 0.01 * r : c == 2 ? 0.2 * std::sin(0.05 * r) + 0.001 * init_d : c == 3 ? 0.4 + 0.1 * std::cos(0.05 * r) : 0.5;
      }));
      job.series.push_back(make_series("RF", {"trial", "n_receptive_fields"}, 20, [&](int r, int c) {
        return c == 0 ? r + 1 : (std::string(mode) == "online" ? r * init_d : init_d);
      }));
      seven_jobs.push_back(job);
    }
  }
  testing::write_test_sweep(db, "seven", seven_jobs);
}

class PlotTest : public ::testing::Test {
 protected:
  // The four sweeps the plots draw from, in one database.
  void SetUp() override {
    db_ = directory_.file("results.db");
    write_kernel_sweep(db_);
    write_tracking_sweep(db_);
    write_fixed_sweep(db_);
    write_seven_joint_sweep(db_);
  }

  std::string render(const std::string& arguments, const std::string& out) {
    const auto result = testing::run_armfarm("plot " + db_ + " " + arguments + " --out " + out);
    EXPECT_EQ(result.exit_code, 0) << arguments << ": " << result.output;
    keep_for_inspection(out);
    const std::string svg = test_support::read_text_file(out);
    EXPECT_NE(svg.find("<svg"), std::string::npos) << arguments;
    EXPECT_NE(svg.find("</svg>"), std::string::npos) << arguments;
    return svg;
  }

  // ARMFARM_KEEP_PLOTS=DIR keeps a copy of every rendered plot, to look at them.
  static void keep_for_inspection(const std::string& path) {
    if (const char* keep = std::getenv("ARMFARM_KEEP_PLOTS")) {
      std::error_code ignored;
      std::filesystem::copy_file(path, std::filesystem::path(keep) / std::filesystem::path(path).filename(),
                                 std::filesystem::copy_options::overwrite_existing, ignored);
    }
  }

  testing::TemporaryDirectory directory_;
  std::string db_;
};

TEST_F(PlotTest, NmseAgainstKernelWidthHasBothAdaptationCurvesPerJoint) {
  const std::string svg = render("nmse-vs-kernel --sweep kernel", directory_.file("nmse.svg"));
  EXPECT_NE(svg.find("update_D=true"), std::string::npos);
  EXPECT_NE(svg.find("update_D=false"), std::string::npos);
  EXPECT_NE(svg.find("joint 2"), std::string::npos);
  EXPECT_NE(svg.find("receptive fields"), std::string::npos);
}

TEST_F(PlotTest, MetricAgainstParamWithErrorBars) {
  const std::string svg = render("metric-vs-param --sweep kernel --metric same_run_test_nmse --joint 1 --param learning.lwpr.init_D "
                                 "--group learning.lwpr.update_D",
                                 directory_.file("metric.svg"));
  EXPECT_NE(svg.find("same_run_test_nmse_j1"), std::string::npos);  // the caption names the column
  EXPECT_NE(svg.find("update_D=true"), std::string::npos);
  // The title in the catalog's words, not the column's spelling (review of 2026-12-03, section 2).
  const auto boxes = testing::find_text_boxes(svg);
  ASSERT_FALSE(boxes.empty());
  EXPECT_EQ(boxes.front().text, "same-run test nMSE, joint 1 against init_D (sweep kernel)");
}

TEST(ShortParamNames, ReadTheLastKeyOfTheParsedPath) {
  EXPECT_EQ(make_short_param_name("learning.lwpr.init_D"), "init_D");
  EXPECT_EQ(make_short_param_name("control.kp[1]"), "kp[1]");  // an index stays with its key
  EXPECT_EQ(make_short_param_name("trajectory.waypoints[2][0]"), "waypoints[2][0]");
  EXPECT_EQ(make_short_param_name("seed"), "seed");
  EXPECT_EQ(make_short_param_name("a..b"), "a..b");  // not a path: shown as it is
}

// The report's and the plot's nmse-vs-kernel draw the held-out nMSE where the sweep recorded it
// (the metric thesis-figure 6.1 draws), and say so; --metric same_run_test_nmse the same-run one.
TEST_F(PlotTest, NmseAgainstKernelWidthDrawsTheHeldOutMetricWhereRecorded) {
  const ResultsStore store = ResultsStore::open(db_, ResultsStore::Mode::read_only);
  PlotRequest request;
  request.kind = PlotKind::nmse_vs_kernel;
  request.sweep = "fixed";
  const Figure heldout = make_plot_figure(store, request);
  ASSERT_EQ(heldout.panels.size(), 2u);  // joint 1, receptive fields
  EXPECT_EQ(heldout.panels[0].y_label, "held-out test nMSE");
  ASSERT_FALSE(heldout.panels[0].curves.empty());
  // init_D 1 over seeds 1, 2: (0.1 + 0.001·seed) / 2, the held-out values, not the same-run ones.
  EXPECT_NEAR(heldout.panels[0].curves[0].y[0], (0.1 + 0.0015) / 2, 1e-12);
  ASSERT_FALSE(heldout.caption.empty());
  EXPECT_EQ(heldout.caption[0].rfind("nMSE: held-out test nMSE (heldout_test_nmse) at checkpoint 1, the last", 0), 0u) << heldout.caption[0];
  request.metric = "same_run_test_nmse";
  const Figure same_run = make_plot_figure(store, request);
  EXPECT_NEAR(same_run.panels[0].curves[0].y[0], 0.1 + 0.0015, 1e-12);
  request.metric.clear();
  request.checkpoint = 3;
  EXPECT_THROW(make_plot_figure(store, request), AnalysisError);  // recorded at checkpoint 1 only
  // The report's figure is the held-out one, its caption under it in the page.
  const std::string out = directory_.file("report_fixed");
  ASSERT_EQ(testing::run_armfarm("report " + db_ + " --sweep fixed --out " + out).exit_code, 0);
  const std::string page = test_support::read_text_file(out + "/sweep_fixed.html");
  EXPECT_NE(page.find("<p class=\"caption\">nMSE: held-out test nMSE (heldout_test_nmse) at checkpoint 1"), std::string::npos);
}

// rf-growth against reaches where the jobs recorded the TRIAL series (as figure 6.7), on a log
// axis when the curves end decades apart (the small ones were squashed onto the x axis).
TEST_F(PlotTest, ReceptiveFieldGrowthIsPerReachAndLogWhereTheCurvesSpanDecades) {
  const std::string db = directory_.file("growth.db");
  std::vector<testing::TestJob> jobs;
  for (double init_d : {0.05, 2.0}) {
    testing::TestJob job;
    job.params = {{"learning.lwpr.init_D", init_d}};
    const double scale = init_d == 2.0 ? 4000.0 : 4.0;
    job.series.push_back(make_series("TRIAL", {"segment", "t", "n_receptive_fields"}, 50, [&](int r, int c) {
      return c == 0 ? r + 1.0 : c == 1 ? 2.0 * r : std::ceil(scale * std::sqrt((r + 1) / 50.0));
    }));
    job.series.push_back(make_series("RF", {"t", "n_receptive_fields"}, 50, [&](int r, int c) { return c == 0 ? 2.0 * r : scale; }));
    jobs.push_back(job);
  }
  testing::write_test_sweep(db, "growth", jobs);
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  PlotRequest request;
  request.kind = PlotKind::rf_growth;
  const Figure figure = make_plot_figure(store, request);
  ASSERT_EQ(figure.panels.size(), 1u);
  const Panel& panel = figure.panels[0];
  EXPECT_EQ(panel.x_label, "reaches");
  EXPECT_TRUE(panel.log_y);
  ASSERT_EQ(panel.curves.size(), 2u);
  EXPECT_EQ(panel.curves[1].x.front(), 1.0);
  EXPECT_EQ(panel.curves[1].y.back(), 4000.0);
  ASSERT_FALSE(figure.caption.empty());
  EXPECT_NE(figure.caption.back().find("log y: the final counts span more than a factor 20"), std::string::npos) << figure.caption.back();
  request.log_y = false;
  const Figure linear = make_plot_figure(store, request);
  EXPECT_FALSE(linear.panels[0].log_y);
  EXPECT_NE(linear.caption.back().find("linear y (--liny)"), std::string::npos) << linear.caption.back();
  // Without the TRIAL series: the RF series against its own x column, here "trial".
  const ResultsStore tracking = ResultsStore::open(db_, ResultsStore::Mode::read_only);
  request.sweep = "tracking";
  request.log_y.reset();
  const Figure by_trial = make_plot_figure(tracking, request);
  EXPECT_EQ(by_trial.panels[0].x_label, "trial");
  EXPECT_FALSE(by_trial.panels[0].log_y);  // both end at the same count
}

TEST_F(PlotTest, SignalsTrackingAndReceptiveFieldGrowth) {
  const std::string signals = render("signals --sweep tracking", directory_.file("signals.svg"));
  for (const char* title : {"feedback", "feed-forward", "composite", "torque (N·m)"}) {
    EXPECT_NE(signals.find(title), std::string::npos) << title;
  }
  const std::string tracking = render("tracking --sweep tracking", directory_.file("tracking.svg"));
  for (const char* title : {"desired", "mode=feedback", "mode=composite", "y (m)", "z (m)"}) {
    EXPECT_NE(tracking.find(title), std::string::npos) << title;
  }
  const std::string growth = render("rf-growth --sweep tracking", directory_.file("rf.svg"));
  EXPECT_NE(growth.find("receptive fields (count)"), std::string::npos);
}

// Found on fig6_12_13_reaching_model.test (review of 2026-12-03): each test job names the model
// it starts from, {"params":{"seed":s},"sweep":"….train"}. `tracking` drew no legend at paper
// style (ten entries of raw JSON did not fit, gnuplot left the key out) and `signals` printed that
// JSON as a title line wider than the image.
TEST_F(PlotTest, TwoStageSweepsNameTheirModelReadablyAndTrackingKeepsItsLegend) {
  std::vector<testing::TestJob> jobs;
  for (const char* file : {"data/picking_synthetic.csv", "data/sphere_synthetic.csv"}) {
    for (int seed = 0; seed < 3; ++seed) {
      testing::TestJob job;
      job.params = {{"learning.initial_model", {{"params", {{"seed", seed}}}, {"sweep", "two_stage.train"}}},
                    {"seed", seed},
                    {"trajectory.recorded.file", file}};
      const double offset = file[5] == 'p' ? 0.0 : 0.2;
      for (const char* name : {"POS_D", "POS"}) {
        job.series.push_back(make_series(name, {"t", "x", "y", "z"}, 50, [&](int r, int c) {
          return c == 0 ? 0.1 * r : c == 1 ? 0.5 : c == 2 ? 0.4 + offset + 0.002 * r : 0.1 + offset + 0.05 * std::sin(0.1 * r);
        }));
      }
      for (const char* name : {"F", "FF"}) {
        job.series.push_back(make_series(name, {"t", "j1", "j2"}, 50, [&](int r, int c) { return c == 0 ? 0.1 * r : std::cos(0.1 * r * c); }));
      }
      jobs.push_back(job);
    }
  }
  testing::write_test_sweep(db_, "two_stage.test", jobs);
  const auto inside_the_image = [](const std::string& svg) {
    double width = 0;
    EXPECT_EQ(std::sscanf(svg.c_str() + svg.find("viewBox=\"") + 9, "0 0 %lf", &width), 1);
    std::vector<std::string> outside;
    for (const auto& box : testing::find_text_boxes(svg)) {
      if (box.left < 0 || box.right > width) outside.push_back(box.text);
      EXPECT_EQ(box.text.find('{'), std::string::npos) << box.text;
    }
    return outside;
  };
  const std::string tracking = render("tracking --sweep two_stage.test --style paper", directory_.file("two_stage_tracking.svg"));
  std::size_t picking = 0, sphere = 0, desired = 0;
  for (const auto& box : testing::find_text_boxes(tracking)) {
    picking += box.text.find("picking_synthetic.csv") != std::string::npos;
    sphere += box.text.find("sphere_synthetic.csv") != std::string::npos;
    desired += box.text == "desired";
  }
  EXPECT_EQ(picking, 1u);  // one entry per recording: the seeds (and their models' seeds) are repeats
  EXPECT_EQ(sphere, 1u);
  EXPECT_EQ(desired, 1u);
  EXPECT_EQ(inside_the_image(tracking), std::vector<std::string>());
  const std::string signals = render("signals --sweep two_stage.test --style paper", directory_.file("two_stage_signals.svg"));
  EXPECT_NE(signals.find("seed 0 of two_stage.train"), std::string::npos);
  EXPECT_EQ(inside_the_image(signals), std::vector<std::string>());
}

TEST_F(PlotTest, PngOutputIsAPng) {
  const std::string out = directory_.file("signals.png");
  const auto result = testing::run_armfarm("plot " + db_ + " signals --sweep tracking --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  keep_for_inspection(out);
  const std::string png = test_support::read_text_file(out);
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
}

TEST_F(PlotTest, MissingDataIsAOneLineErrorAndNoFile) {
  const std::string out = directory_.file("none.svg");
  const auto result = testing::run_armfarm("plot " + db_ + " signals --sweep kernel --out " + out);
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("no done job recorded the F and FF series"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  EXPECT_EQ(testing::run_armfarm("plot " + db_ + " signals --out " + out).exit_code, 2);  // two sweeps, none chosen
}

TEST_F(PlotTest, PdfIsOnePageAtPaperWidth) {
  const std::string out = directory_.file("nmse.pdf");
  const auto result = testing::run_armfarm("plot " + db_ + " nmse-vs-kernel --sweep kernel --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  keep_for_inspection(out);
  const std::string pdf = test_support::read_text_file(out);
  ASSERT_EQ(pdf.substr(0, 4), "%PDF");
  std::size_t pages = 0;
  for (auto at = pdf.find("/Type /Page"); at != std::string::npos; at = pdf.find("/Type /Page", at + 1)) {
    if (pdf.compare(at, 12, "/Type /Pages") != 0) ++pages;
  }
  EXPECT_EQ(pages, 1u);
  // Three panels in two columns: one column of a paper, 3.5 in = 252 pt wide.
  EXPECT_NE(pdf.find("/MediaBox [ 0 0 252 "), std::string::npos) << pdf.substr(0, 2000);
  EXPECT_EQ(testing::run_armfarm("plot " + db_ + " nmse-vs-kernel --sweep kernel --out " + directory_.file("n.eps")).exit_code, 2);
}

TEST_F(PlotTest, StyleSizeFontAndLabelOverrides) {
  const std::string svg = render("metric-vs-param --sweep kernel --metric same_run_test_nmse --joint 1 --param learning.lwpr.init_D "
                                 "--style paper --size 5,3 --font-size 9 --title 'My title' --xlabel 'width' --ylabel 'error'",
                                 directory_.file("styled.svg"));
  EXPECT_NE(svg.find("width=\"360\""), std::string::npos);  // 5 in at 72 units per inch
  EXPECT_NE(svg.find("height=\"216\""), std::string::npos);
  EXPECT_NE(svg.find("font-size=\"9.00\""), std::string::npos);
  for (const char* text : {"My title", ">width<", ">error<"}) EXPECT_NE(svg.find(text), std::string::npos) << text;
  EXPECT_EQ(testing::run_armfarm("plot " + db_ + " tracking --sweep tracking --style poster --out " + directory_.file("p.svg")).exit_code,
            2);
}

TEST_F(PlotTest, LegendListsExactlyTheVaryingParametersAndDivergedJobsAreCounted) {
  const std::string svg = render("nmse-vs-kernel --sweep fixed", directory_.file("fixed.svg"));
  EXPECT_EQ(svg.find("update_D"), std::string::npos);  // in every config, never swept: not a legend entry
  EXPECT_NE(svg.find("marked on the top edge: 1 diverged"), std::string::npos);
  const std::string kernel = render("nmse-vs-kernel --sweep kernel", directory_.file("kernel.svg"));
  EXPECT_NE(kernel.find("update_D=true"), std::string::npos);
  EXPECT_EQ(kernel.find("seed="), std::string::npos);  // repeats are error bars, not curves
  EXPECT_EQ(kernel.find("jobs not shown"), std::string::npos);
  const std::string metric = render("metric-vs-param --sweep fixed --metric same_run_test_nmse --joint 1 --param learning.lwpr.init_D",
                                    directory_.file("fixed_metric.svg"));
  EXPECT_NE(metric.find("marked on the top edge: 1 diverged"), std::string::npos);
}

TEST_F(PlotTest, HeldOutMetricNeedsAndTakesACheckpoint) {
  const std::string base = "plot " + db_ + " metric-vs-param --sweep fixed --metric heldout_test_nmse --joint 1 --param learning.lwpr.init_D";
  const auto refused = testing::run_armfarm(base + " --out " + directory_.file("h.svg"));
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("--checkpoint"), std::string::npos) << refused.output;
  const auto absent = testing::run_armfarm(base + " --checkpoint 7 --out " + directory_.file("h7.svg"));
  EXPECT_EQ(absent.exit_code, 2);
  EXPECT_NE(absent.output.find("recorded at checkpoints 1, not 7; choose one with --checkpoint N"), std::string::npos) << absent.output;
  const std::string svg = render("metric-vs-param --sweep fixed --metric heldout_test_nmse --joint 1 --param learning.lwpr.init_D --checkpoint 1",
                                 directory_.file("heldout.svg"));
  EXPECT_NE(svg.find("heldout_test_nmse_j1_c1"), std::string::npos);
  EXPECT_NE(svg.find("held-out test nMSE, joint 1, checkpoint 1 against init_D (sweep fixed)"), std::string::npos);
}

TEST_F(PlotTest, MissingSeriesSaysWhatToSet) {
  for (const char* kind : {"signals", "tracking", "rf-growth"}) {
    const auto result = testing::run_armfarm("plot " + db_ + " " + kind + " --sweep kernel --out " + directory_.file("x.svg"));
    EXPECT_EQ(result.exit_code, 2) << kind;
    EXPECT_NE(result.output.find("recording.series"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find("\"recording\": {\"series\": [\""), std::string::npos) << result.output;
  }
}

// The quick start's batch jobs learn one model at every gain (the collection runs at full gain),
// so their curves are equal and the later hid the earlier: the legend listed a curve no panel
// showed (issue 24). The caption says which curve lies under which.
TEST_F(PlotTest, ACurveHiddenUnderAnEqualOneIsNamedInTheCaption) {
  const std::string db = directory_.file("hidden.db");
  std::vector<testing::TestJob> jobs;
  for (const char* mode : {"online", "batch"}) {
    for (double gain : {0.2, 1.0}) {
      for (double init_d : {0.02, 0.05, 0.2}) {
        testing::TestJob job;
        job.params = {{"learning.mode", mode}, {"control.gain_scale", gain}, {"learning.lwpr.init_D", init_d}};
        const double nmse = std::string(mode) == "batch" ? 0.1 * init_d : 0.2 * init_d * gain;
        job.metrics = {{0, "same_run_test_nmse", 1, nmse, ""}, {0, "n_receptive_fields", std::nullopt, std::string(mode) == "batch" ? 10 / init_d : 20 / init_d * gain, ""}};
        jobs.push_back(job);
      }
    }
  }
  testing::write_test_sweep(db, "hidden", jobs);
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  PlotRequest request;
  request.kind = PlotKind::nmse_vs_kernel;
  const Figure figure = make_plot_figure(store, request);
  ASSERT_EQ(figure.panels.size(), 2u);
  std::string caption;
  for (const std::string& paragraph : figure.caption) caption += paragraph + "\n";
  EXPECT_NE(caption.find("hidden: gain_scale=0.2, mode=batch lies under gain_scale=1, mode=batch (equal values) in every panel"),
            std::string::npos)
      << caption;
  EXPECT_EQ(caption.find("mode=online lies under"), std::string::npos) << caption;  // the online curves differ
}

// The held-out reaching sweep records TRIAL (a row per reach) and no RF: its report had no
// figure, though rf-growth draws the fields per reach from TRIAL.
TEST_F(PlotTest, ReceptiveFieldGrowthIsAvailableFromTheTrialSeriesAlone) {
  const std::string db = directory_.file("trials.db");
  std::vector<testing::TestJob> jobs(2);
  for (int seed = 0; seed < 2; ++seed) {
    jobs[seed].params = {{"seed", seed}};
    jobs[seed].series.push_back(make_series("TRIAL", {"segment", "t", "n_receptive_fields"}, 5,
                                            [&](int r, int c) { return c == 0 ? r + 1.0 : c == 1 ? r : 3.0 * (r + 1) + seed; }));
  }
  testing::write_test_sweep(db, "trials", jobs);
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const auto kinds = find_available_plot_kinds(store, load_sweep_data(store, "trials"));
  EXPECT_NE(std::find(kinds.begin(), kinds.end(), PlotKind::rf_growth), kinds.end());
  // One TRIAL row per job (one trial) is not growth: rf-growth is not offered.
  const std::string flat = directory_.file("flat.db");
  for (auto& job : jobs) job.series = {make_series("TRIAL", {"segment", "t", "n_receptive_fields"}, 1, [](int, int c) { return c + 1.0; })};
  testing::write_test_sweep(flat, "flat", jobs);
  const ResultsStore flat_store = ResultsStore::open(flat, ResultsStore::Mode::read_only);
  const auto flat_kinds = find_available_plot_kinds(flat_store, load_sweep_data(flat_store, "flat"));
  EXPECT_EQ(std::find(flat_kinds.begin(), flat_kinds.end(), PlotKind::rf_growth), flat_kinds.end());
}

TEST_F(PlotTest, NoTextOverlapsOnAnyPlotKindOfASevenJointSweep) {
  const std::vector<std::string> plots = {
      "nmse-vs-kernel", "rf-growth", "signals", "tracking",
      "metric-vs-param --metric same_run_test_nmse --joint 7 --param learning.lwpr.init_D --group learning.mode"};
  for (const char* style : {"paper", "screen", "slide"}) {
    for (const std::string& plot : plots) {
      const std::string out = directory_.file(plot.substr(0, plot.find(' ')) + "_" + style + ".svg");
      const std::string svg = render(plot + " --sweep seven --style " + style, out);
      const auto boxes = testing::find_text_boxes(svg);
      EXPECT_GE(boxes.size(), 8u) << plot;  // the checker sees the labels
      const auto overlaps = testing::find_overlapping_text(svg);
      EXPECT_TRUE(overlaps.empty()) << plot << " (" << style << "): " << overlaps.size() << " overlaps, first "
                                    << (overlaps.empty() ? "" : overlaps.front());
    }
  }
}

// Found on the thesis's figure 6.1 database (60 jobs, init_D 0.01-3, issue 24): at paper style
// the kernel-width panels showed one x tick label ("set xtics 1e3" counts decades from 1), the
// receptive-field panel's y label wrapped onto its tick labels, tracking had a legend entry per
// job (a 4017 px tall PNG), and a single panel kept a blank title line under the figure's title.
TEST_F(PlotTest, KernelWidthSweepOfSixtyJobsReadsAtPaperStyle) {
  const std::string db = directory_.file("fig6_1.db");
  write_kernel_width_sweep(db);
  keep_for_inspection(db);
  const auto plot = [&](const std::string& arguments, const std::string& name) {
    const std::string out = directory_.file(name);
    const auto result = testing::run_armfarm("plot " + db + " " + arguments + " --out " + out);
    EXPECT_EQ(result.exit_code, 0) << arguments << ": " << result.output;
    keep_for_inspection(out);
    return test_support::read_text_file(out);
  };
  const std::string nmse = plot("nmse-vs-kernel --style paper", "fig6_1_nmse.svg");
  const auto boxes = testing::find_text_boxes(nmse);
  const auto frames = testing::find_plot_frames(nmse);
  ASSERT_EQ(frames.size(), 3u);  // joints 1 and 2, receptive fields
  for (const testing::Frame& frame : frames) {
    const auto ticks = testing::find_x_tick_labels(boxes, frame);
    EXPECT_GE(ticks.size(), 3u) << "x tick labels of a log axis over 0.01-3: " << ticks.size();
    EXPECT_NE(std::find(ticks.begin(), ticks.end(), "0.01"), ticks.end());
  }
  for (const char* label : {"receptive fields (count)", "same-run test nMSE"}) {
    EXPECT_TRUE(std::any_of(boxes.begin(), boxes.end(), [&](const testing::TextBox& b) { return b.rotated && b.text == label; }))
        << "y label '" << label << "' not on one line";
  }
  const auto crowded = testing::find_crowded_y_labels(boxes, 0.3);
  EXPECT_TRUE(crowded.empty()) << crowded.size() << " crowded, first " << (crowded.empty() ? "" : crowded.front());
  EXPECT_TRUE(testing::find_overlapping_text(nmse).empty());

  // Tracking: one entry per configuration (12), not per job (60), and a page of sane height.
  const std::string tracking = plot("tracking --style paper", "fig6_1_tracking.svg");
  std::size_t entries = 0;
  for (const testing::TextBox& box : testing::find_text_boxes(tracking)) entries += box.text.find("init_D=") != std::string::npos;
  EXPECT_EQ(entries, 12u);
  EXPECT_EQ(tracking.find("seed="), std::string::npos);
  EXPECT_NE(tracking.find("a curve per configuration: its first of 5 repeats"), std::string::npos);
  const std::string png = plot("tracking --style paper", "fig6_1_tracking.png");
  ASSERT_GT(png.size(), 24u);
  const auto be32 = [&png](std::size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(be32(16), 1050u);     // 3.5 in at 300 dpi
  EXPECT_LE(be32(20), 1800u);     // was 4017: 61 legend rows
  EXPECT_TRUE(testing::find_overlapping_text(tracking).empty());

  // One panel, no panel title: the figure's title sits right above the frame.
  const std::string metric = plot("metric-vs-param --metric n_receptive_fields --param learning.lwpr.init_D --style paper",
                                  "fig6_1_metric.svg");
  const auto rooms = testing::find_room_above_frames(testing::find_text_boxes(metric), testing::find_plot_frames(metric));
  ASSERT_EQ(rooms.size(), 1u);
  EXPECT_LT(rooms[0], 1.2) << "a blank line between the title and the panel";
}

// Figures: nMSE over decades gets a log axis whose error bars stay above zero, and an unplotted
// swept parameter splits the curves instead of being pooled into the error bars.
TEST(PlotAxes, LogAxesPositiveErrorBarsAndNoSilentPooling) {
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
TEST(PlotAxes, LogSpacedValuesGetALogAxisAndUnfinishedJobsAMark) {
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

TEST(SvgTextBoxes, FindsADeliberateOverlapAndNotItsSeparatedTwin) {
  const std::string label_a = "<g transform=\"translate(100.00,50.00)\" stroke=\"none\" font-size=\"12.00\" text-anchor=\"end\">\n"
                              "<text>torque (N·m)</text>\n</g>\n";
  const std::string label_b = "<g transform=\"translate(95.00,54.00)\" stroke=\"none\" font-size=\"12.00\">\n<text>0.24</text>\n</g>\n";
  const std::string rotated = "<g transform=\"translate(20.00,200.00) rotate(270)\" font-size=\"10.00\" text-anchor=\"middle\">\n"
                              "<text>time (s)</text>\n</g>\n";
  const std::string beside = "<g transform=\"translate(40.00,200.00)\" font-size=\"10.00\">\n<text>1e-02</text>\n</g>\n";
  const std::string on_it = "<g transform=\"translate(16.00,210.00)\" font-size=\"10.00\">\n<text>x</text>\n</g>\n";
  EXPECT_EQ(testing::find_overlapping_text("<svg>" + label_a + label_b + "</svg>").size(), 1u);
  EXPECT_TRUE(testing::find_overlapping_text("<svg>" + label_a + rotated + beside + "</svg>").empty());
  EXPECT_EQ(testing::find_overlapping_text("<svg>" + rotated + on_it + "</svg>").size(), 1u);  // rotated box is vertical
  const auto boxes = testing::find_text_boxes("<svg>" + rotated + "</svg>");
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_GT(boxes[0].bottom - boxes[0].top, boxes[0].right - boxes[0].left);
}

// The checks behind the paper-style test, each on a fixture made to fail it and its fixed twin.
TEST(SvgTextBoxes, FramesTicksCrowdedLabelsAndRoomAboveAFrame) {
  const std::string frame = "<path stroke='black'  d='M42.00,30.00 L42.00,200.00 L150.00,200.00 L150.00,30.00 L42.00,30.00 Z  '/>";
  const std::string open_path = "<path d='M42.00,30.00 L42.00,200.00 L150.00,200.00 L150.00,30.00 L42.00,30.00  '/>";
  const auto text = [](double x, double y, const std::string& content, const std::string& extra = "") {
    return "<g transform=\"translate(" + std::to_string(x) + "," + std::to_string(y) + ")" + extra +
           "\" font-size=\"8.00\" text-anchor=\"middle\">\n<text>" + content + "</text>\n</g>\n";
  };
  const auto frames = testing::find_plot_frames("<svg>" + frame + frame + open_path + "</svg>");
  ASSERT_EQ(frames.size(), 1u);  // the same border twice is one frame; an open path is none
  EXPECT_EQ(frames[0].left, 42.0);
  EXPECT_EQ(frames[0].bottom, 200.0);
  // One tick label under the frame (the fault) against three; a label elsewhere does not count.
  const std::string one_tick = "<svg>" + frame + text(78, 210, "0.1") + text(300, 210, "0.01") + "</svg>";
  EXPECT_EQ(testing::find_x_tick_labels(testing::find_text_boxes(one_tick), frames[0]).size(), 1u);
  const std::string ticks = "<svg>" + frame + text(42, 210, "0.01") + text(96, 210, "0.1") + text(150, 210, "1") + "</svg>";
  EXPECT_EQ(testing::find_x_tick_labels(testing::find_text_boxes(ticks), frames[0]).size(), 3u);
  // A y label's line 0.4 units from the tick labels (touching, not overlapping) against 4.4 units.
  const std::string tick = "<g transform=\"translate(36.00,100.00)\" font-size=\"8.00\" text-anchor=\"end\">\n<text>1e+03</text>\n</g>\n";
  const std::string touching = "<svg>" + tick + text(12, 100, "(count)", " rotate(270)") + "</svg>";
  ASSERT_TRUE(testing::find_overlapping_text(touching).empty());
  EXPECT_EQ(testing::find_crowded_y_labels(testing::find_text_boxes(touching), 0.3).size(), 1u);
  const std::string apart = "<svg>" + tick + text(8, 100, "(count)", " rotate(270)") + "</svg>";
  EXPECT_TRUE(testing::find_crowded_y_labels(testing::find_text_boxes(apart), 0.3).empty());
  // A title one blank line above the frame against one right above it.
  const auto room = [&](double title_baseline) {
    return testing::find_room_above_frames(testing::find_text_boxes("<svg>" + frame + text(96, title_baseline, "title") + "</svg>"),
                                           frames);
  };
  ASSERT_EQ(room(27).size(), 1u);
  EXPECT_LT(room(27)[0], 1.2);
  EXPECT_GT(room(17)[0], 1.2);
}

TEST_F(PlotTest, ReportIsSelfContainedHtmlPerSweep) {
  const std::string out = directory_.file("report");
  const auto result = testing::run_armfarm("report " + db_ + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string kernel = test_support::read_text_file(out + "/sweep_kernel.html");
  EXPECT_NE(kernel.find("<table>"), std::string::npos);
  EXPECT_NE(kernel.find("deadbeef"), std::string::npos);  // provenance
  EXPECT_NE(kernel.find("<svg"), std::string::npos);      // plot inline
  EXPECT_NE(kernel.find("same_run_test_nmse_j1"), std::string::npos);
  const std::string tracking = test_support::read_text_file(out + "/sweep_tracking.html");
  EXPECT_NE(tracking.find("tracking"), std::string::npos);
  EXPECT_NE(test_support::read_text_file(out + "/index.html").find("sweep_kernel.html"), std::string::npos);
  EXPECT_EQ(escape_html("<a href=\"x\">&'"), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;");
}

TEST_F(PlotTest, ReportPagesListTheirContentsFiguresFirstAndSortableTables) {
  const std::string out = directory_.file("report");
  const auto result = testing::run_armfarm("report " + db_ + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string kernel = test_support::read_text_file(out + "/sweep_kernel.html");
  // Figures come before the tables.
  const auto first_figure = kernel.find("<svg");
  const auto first_table = kernel.find("<table class=\"sortable\">");
  ASSERT_NE(first_figure, std::string::npos);
  ASSERT_NE(first_table, std::string::npos);
  EXPECT_LT(first_figure, first_table);
  // Every entry of the contents points at an anchor of the page.
  int links = 0;
  for (std::size_t at = kernel.find("<a href=\"#"); at != std::string::npos; at = kernel.find("<a href=\"#", at + 1)) {
    const std::size_t start = at + 10;
    const std::string anchor = kernel.substr(start, kernel.find('"', start) - start);
    EXPECT_NE(kernel.find("id=\"" + anchor + "\""), std::string::npos) << anchor;
    ++links;
  }
  EXPECT_GE(links, 4);
  // Tables scroll in their own box, sort by an inline script, and nothing is fetched.
  EXPECT_NE(kernel.find("<div class=\"scroll\"><table class=\"sortable\">"), std::string::npos);
  EXPECT_NE(kernel.find("<script>document.querySelectorAll('table.sortable')"), std::string::npos);
  for (const std::string& page : {kernel, test_support::read_text_file(out + "/index.html")}) {
    EXPECT_EQ(page.find("<script src"), std::string::npos);
    EXPECT_EQ(page.find("<link"), std::string::npos);
    EXPECT_EQ(page.find(" src="), std::string::npos);  // (the inline SVG's xmlns names, not fetches)
    EXPECT_EQ(page.find("href=\"http"), std::string::npos);
    EXPECT_EQ(page.find("url(http"), std::string::npos);
  }
  // The index has a row per sweep with its counts, date, spec hash and best result.
  const std::string index = test_support::read_text_file(out + "/index.html");
  EXPECT_NE(index.find("<th>jobs</th><th>done</th><th>failed</th><th>diverged</th><th>started</th><th>spec hash</th>"),
            std::string::npos)
      << index;
  EXPECT_NE(index.find("<a href=\"sweep_kernel.html\">kernel</a>"), std::string::npos) << index;
  EXPECT_NE(index.find(">0123456789ab</code>"), std::string::npos) << index;  // the test sweeps' spec hash
  EXPECT_NE(index.find("<td>–</td></tr>"), std::string::npos) << index;  // no job-level result metric

  // A sweep with a job-level result: the best job by it (lower tracking_nmse is better).
  const std::string db = directory_.file("best.db");
  std::vector<testing::TestJob> jobs(3);
  jobs[0].params = {{"control.gain_scale", 0.5}};
  jobs[0].metrics = {{0, "tracking_nmse", std::nullopt, 0.5, ""}};
  jobs[1].params = {{"control.gain_scale", 2.0}};
  jobs[1].metrics = {{0, "tracking_nmse", std::nullopt, 0.25, ""}};
  jobs[2].params = {{"control.gain_scale", 4.0}};
  jobs[2].status = "diverged";
  jobs[2].metrics = {{0, "tracking_nmse", std::nullopt, 0.01, ""}};  // not done: not a candidate
  testing::write_test_sweep(db, "best", jobs);
  ASSERT_EQ(testing::run_armfarm("report " + db + " --out " + directory_.file("best")).exit_code, 0);
  const std::string best = test_support::read_text_file(directory_.file("best") + "/index.html");
  EXPECT_NE(best.find("<td>tracking_nmse = 0.25 (lower is better, of 2 done): gain_scale=2<"), std::string::npos)
      << best;
  EXPECT_NE(best.find("data-sort=\"1\">1</td><td>"), std::string::npos) << best;  // one diverged
}

}  // namespace
}  // namespace armfarm
