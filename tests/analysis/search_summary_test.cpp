// The search summary behind `table`, `status`, `plot search` and `report`: a hand-worked ASHA
// search (two rungs, a diverged trial, a step not yet committed) gives the ranking, rung
// counts, survivors, budget spent and best-so-far curve worked out below; `plot search --sweep`
// draws the method beside the random search of the same objective and leaves out one of
// another objective.
#include "analysis/analysis_error.hpp"
#include "analysis/plots.hpp"
#include "analysis/search_summary.hpp"

#include <gtest/gtest.h>

#include "support/test_database.hpp"
#include "support/text_file.hpp"
#include "svg_text_boxes.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <tuple>
#include <string>
#include <vector>

namespace armfarm {
namespace {

SweepRegistration make_sweep(const std::string& name) {
  SweepRegistration sweep;
  sweep.name = name;
  sweep.spec_text = "{}";
  sweep.spec_hash = "h-" + name;
  sweep.started_at = make_utc_timestamp();
  sweep.metric_info = testing::make_test_metric_info();
  return sweep;
}

SearchRecord make_search(const std::string& sweep, const std::string& method, const std::string& metric,
                         std::vector<SearchRungRecord> rungs) {
  SearchRecord search;
  search.sweep = sweep;
  search.method = method;
  search.sampler = "random";
  search.seed = 3;
  search.budget_unit = "jobs";
  search.budget = 9;
  search.objective_metric = metric;
  search.objective_direction = "lower";
  search.objective_joint = 2;
  search.rungs = std::move(rungs);
  return search;
}

void add_steps(ResultsStore& store, const std::string& sweep, const std::vector<SearchStepRecord>& steps,
               const std::vector<std::optional<double>>& objectives, std::size_t committed) {
  std::vector<JobRegistration> jobs;
  for (const SearchStepRecord& step : steps) jobs.push_back({step.job_key, {{"x", step.step}}, {{"x", step.step}}, 0});
  store.insert_sweep_run(make_sweep(sweep), jobs);
  std::int64_t trials = 0;
  for (const SearchStepRecord& step : steps) {
    std::optional<SearchTrialRecord> trial;
    if (step.trial == trials) trial = SearchTrialRecord{trials++, 0, "{\"x\":" + std::to_string(step.trial) + "}"};
    store.insert_search_step(sweep, step, trial);
  }
  for (std::size_t s = 0; s < committed; ++s) {
    store.update_search_objective(sweep, static_cast<std::int64_t>(s), objectives[s], objectives[s] ? "" : "diverged");
  }
}

class SearchSummaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ResultsStore store = ResultsStore::open(db(), ResultsStore::Mode::read_write);
    store.insert_sweep_run(make_sweep("asha_s"), {});
    store.insert_search(make_search("asha_s", "asha", "heldout_test_nmse", {{0, 10, 1.0}, {1, 50, 3.0}}));
    // trial 0, 1, 2 at rung 0; trial 1 promoted (cost 3 - 1 = 2); trial 3 started, not committed.
    add_steps(store, "asha_s",
              {{0, 0, 0, 0, "new", 1.0, "a0", std::nullopt, "", false}, {1, 1, 0, 0, "new", 1.0, "a1", std::nullopt, "", false}, {2, 2, 0, 0, "new", 1.0, "a2", std::nullopt, "", false},
               {3, 1, 1, 3, "promotion", 2.0, "a3", std::nullopt, "", false}, {4, 3, 0, 3, "new", 1.0, "a4", std::nullopt, "", false}},
              {0.5, 0.2, std::nullopt, 0.3}, 4);
    store.insert_sweep_run(make_sweep("random_s"), {});
    store.insert_search(make_search("random_s", "random", "heldout_test_nmse", {{0, std::nullopt, 1.0}}));
    add_steps(store, "random_s", {{0, 0, 0, 0, "new", 1.0, "r0", std::nullopt, "", false}, {1, 1, 0, 0, "new", 1.0, "r1", std::nullopt, "", false}, {2, 2, 0, 0, "new", 1.0, "r2", std::nullopt, "", false}},
              {0.4, 0.35, 0.6}, 3);
    store.insert_sweep_run(make_sweep("other_objective"), {});
    store.insert_search(make_search("other_objective", "random", "tracking_nmse", {{0, std::nullopt, 1.0}}));
    add_steps(store, "other_objective", {{0, 0, 0, 0, "new", 1.0, "o0", std::nullopt, "", false}}, {0.1}, 1);
    store.insert_sweep_run(make_sweep("plain"), {{"p0", {{"x", 1}}, {{"x", 1}}, 0}});
  }
  std::string db() const { return directory_.file("search.db"); }
  testing::TemporaryDirectory directory_;
};

TEST_F(SearchSummaryTest, RanksTrialsByRungThenObjectiveAndCountsRungsAndBudget) {
  const ResultsStore store = ResultsStore::open(db(), ResultsStore::Mode::read_only);
  EXPECT_FALSE(load_search_summary(store, "plain").has_value());
  const std::optional<SearchSummary> summary = load_search_summary(store, "asha_s");
  ASSERT_TRUE(summary.has_value());
  EXPECT_DOUBLE_EQ(summary->spent, 6.0);           // 1 + 1 + 1 + 2 + 1
  EXPECT_DOUBLE_EQ(summary->committed_cost, 5.0);  // without step 4
  ASSERT_EQ(summary->trials.size(), 4u);
  // trial 1 reached rung 1 (0.3 there beats nothing: its 0.2 at rung 0 no longer counts);
  // trial 0 stayed at rung 0 with 0.5; trials 2 (diverged) and 3 (running) have none.
  EXPECT_EQ(summary->trials[0].trial, 1);
  EXPECT_EQ(summary->trials[0].rung, 1);
  EXPECT_EQ(summary->trials[0].objective, 0.3);
  EXPECT_EQ(summary->trials[0].job_key, "a3");
  EXPECT_DOUBLE_EQ(summary->trials[0].cost, 3.0);
  EXPECT_EQ(summary->trials[1].trial, 0);
  EXPECT_EQ(summary->trials[1].objective, 0.5);
  EXPECT_EQ(summary->trials[2].trial, 2);
  EXPECT_FALSE(summary->trials[2].objective.has_value());
  EXPECT_EQ(summary->trials[3].trial, 3);
  ASSERT_EQ(summary->rungs.size(), 2u);
  EXPECT_EQ(summary->rungs[0].checkpoint, 10);
  EXPECT_EQ(summary->rungs[0].started, 4);
  EXPECT_EQ(summary->rungs[0].committed, 3);
  EXPECT_EQ(summary->rungs[0].undefined, 1);
  EXPECT_EQ(summary->rungs[1].started, 1);
  EXPECT_EQ(summary->rungs[1].committed, 1);
  // Only the last rung's objectives move the curve: 0.3 after 5 jobs' worth of cost.
  ASSERT_EQ(summary->curve.size(), 1u);
  EXPECT_DOUBLE_EQ(summary->curve[0].cumulative_cost, 5.0);
  EXPECT_DOUBLE_EQ(summary->curve[0].best, 0.3);

  const std::string text = format_search_summary(*summary, 2);
  EXPECT_NE(text.find("budget spent: 6 of 9 jobs"), std::string::npos) << text;
  EXPECT_NE(text.find("| 0 | 10 | 4 | 3 | 1 | 1 | 4 |"), std::string::npos) << text;  // 1 survivor of rung 0
  EXPECT_NE(text.find("| 1 | 1 | 1 | 0.3 | 3 | a3 |"), std::string::npos) << text;
  EXPECT_NE(text.find("(2 more trials not shown)"), std::string::npos) << text;
  const std::string progress = format_search_progress(*summary);
  EXPECT_NE(progress.find("rung 0 (checkpoint 10): 4 started, 3 committed (1 without objective)"), std::string::npos) << progress;
  EXPECT_NE(progress.find("rung 1 (checkpoint 50): 1 started, 1 committed"), std::string::npos) << progress;
}

TEST_F(SearchSummaryTest, PlotSearchDrawsTheMethodBesideRandomOfTheSameObjective) {
  const ResultsStore store = ResultsStore::open(db(), ResultsStore::Mode::read_only);
  PlotRequest request;
  request.kind = parse_plot_kind("search");
  request.sweep = "asha_s";
  const Figure figure = make_plot_figure(store, request);
  ASSERT_EQ(figure.panels.size(), 1u);
  const std::vector<Curve>& curves = figure.panels[0].curves;
  ASSERT_EQ(curves.size(), 2u);  // other_objective is left out
  EXPECT_EQ(curves[0].title, "asha + random");  // the sweeps are named in the caption
  EXPECT_EQ(curves[0].x, (std::vector<double>{5.0, 6.0}));  // held to the budget spent
  EXPECT_EQ(curves[0].y, (std::vector<double>{0.3, 0.3}));
  EXPECT_EQ(curves[1].title, "random");
  EXPECT_EQ(figure.caption.at(0), "searches: asha + random: sweep asha_s; random: sweep random_s (the baseline)");
  EXPECT_EQ(curves[1].x, (std::vector<double>{1.0, 2.0, 2.0, 3.0}));  // a staircase: 0.4, then 0.35; 0.6 no better
  EXPECT_EQ(curves[1].y, (std::vector<double>{0.4, 0.4, 0.35, 0.35}));

  request.sweep.reset();
  EXPECT_EQ(make_plot_figure(store, request).panels[0].curves.size(), 3u);  // every search
  request.sweep = "plain";
  EXPECT_THROW(make_plot_figure(store, request), AnalysisError);
}

// Issue 24: at paper style the search plot of a lone search (sweeps/search/fig6_1_kernel_width_tpe.json)
// wrapped its y label ("best heldout_test_nmse (joint" over "2)"), the panel having room for it.
TEST_F(SearchSummaryTest, PlotSearchAtPaperStyleKeepsItsYLabelOnOneLine) {
  const std::string lone = directory_.file("lone.db");
  {
    ResultsStore store = ResultsStore::open(lone, ResultsStore::Mode::read_write);
    store.insert_sweep_run(make_sweep("tpe_s"), {});
    store.insert_search(make_search("tpe_s", "tpe", "heldout_test_nmse", {{0, std::nullopt, 1.0}}));
    add_steps(store, "tpe_s", {{0, 0, 0, 0, "new", 1.0, "t0", std::nullopt, "", false}, {1, 1, 0, 0, "new", 1.0, "t1", std::nullopt, "", false}},
              {0.4, 0.3}, 2);
  }
  const std::string out = directory_.file("search.svg");
  const auto result = testing::run_armfarm("plot " + lone + " search --style paper --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string svg = test_support::read_text_file(out);
  EXPECT_NE(svg.find(">best held-out test nMSE, joint 2</text>"), std::string::npos) << svg;
  EXPECT_TRUE(testing::find_overlapping_text(svg).empty());
  EXPECT_TRUE(testing::find_crowded_y_labels(testing::find_text_boxes(svg), 0.3).empty());
}

// A TPE search and the random search of the same objective and seed, five jobs each (the lead's
// search_fig6_1_reduced against random_fig6_1_reduced, issue 24): TPE's start-up trials are
// random's own, so both best-so-far staircases are 0.5 after job 1 and 0.3 after job 2; at job 4
// TPE finds 0.1, random 0.2. The objective is tracking RMSE of joint 2, in rad in the catalog.
class SearchFigureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ResultsStore store = ResultsStore::open(db(), ResultsStore::Mode::read_write);
    for (const auto& [sweep, method, fourth] : {std::tuple<const char*, const char*, double>{"tpe_s", "tpe", 0.1},
                                                std::tuple<const char*, const char*, double>{"random_s", "random", 0.2}}) {
      store.insert_sweep_run(make_sweep(sweep), {});
      store.insert_search(make_search(sweep, method, "tracking_rmse", {{0, std::nullopt, 1.0}}));
      std::vector<SearchStepRecord> steps;
      for (std::int64_t s = 0; s < 5; ++s) steps.push_back({s, s, 0, s, "new", 1.0, std::string(sweep) + std::to_string(s), std::nullopt, "", false});
      add_steps(store, sweep, steps, {0.5, 0.3, 0.4, fourth, 0.35}, 5);
    }
  }
  Figure make_figure(std::optional<bool> log_y = std::nullopt) const {
    const ResultsStore store = ResultsStore::open(db(), ResultsStore::Mode::read_only);
    PlotRequest request;
    request.kind = PlotKind::search;
    request.sweep = "tpe_s";
    request.log_y = log_y;
    return make_plot_figure(store, request);
  }
  std::string db() const { return directory_.file("search.db"); }
  testing::TemporaryDirectory directory_;
};

std::string join_caption(const Figure& figure) {
  std::string text;
  for (const std::string& paragraph : figure.caption) text += paragraph + "\n";
  return text;
}

// `plot search --logy/--liny` were ignored (the search figure did not see the request), and its
// automatic rule wanted a factor 100 where every other kind takes 20 (spans_decades): a user's
// reaching search whose random baseline started at 4.6 and ended at 0.07 (a factor 66) drew a
// linear axis on which both best-so-far curves lay flat on zero.
TEST_F(SearchFigureTest, TakesTheRequestedYScaleAndOtherwiseTheOneAutomaticRule) {
  EXPECT_FALSE(make_figure().panels[0].log_y);  // 0.5 down to 0.1: a factor 5
  EXPECT_TRUE(make_figure(true).panels[0].log_y);
  EXPECT_FALSE(make_figure(false).panels[0].log_y);
  {
    ResultsStore store = ResultsStore::open(db(), ResultsStore::Mode::read_write);
    store.insert_sweep_run(make_sweep("random_wide"), {});
    store.insert_search(make_search("random_wide", "random", "tracking_rmse", {{0, std::nullopt, 1.0}}));
    std::vector<SearchStepRecord> steps;
    for (std::int64_t s = 0; s < 3; ++s) steps.push_back({s, s, 0, s, "new", 1.0, "random_wide" + std::to_string(s), std::nullopt, "", false});
    add_steps(store, "random_wide", steps, {4.6, 0.2, 0.07}, 3);
  }
  EXPECT_TRUE(make_figure().panels[0].log_y);  // 4.6 down to 0.07 across the drawn curves: a factor 66
  EXPECT_FALSE(make_figure(false).panels[0].log_y);
}

// The y label and title were the raw column name ("best heldout_test_nmse (joint 2)"); every
// other kind takes the readable name and unit from the catalog (make_metric_axis_label).
TEST_F(SearchFigureTest, LabelsTheObjectiveWithTheCatalogsNameAndUnit) {
  const Figure figure = make_figure();
  ASSERT_EQ(figure.panels.size(), 1u);
  EXPECT_EQ(figure.panels[0].y_label, "best tracking RMSE, joint 2 (rad)");
  EXPECT_EQ(figure.title, "Search: tracking RMSE, joint 2, lower is better");
  EXPECT_EQ(figure.panels[0].x_label, "jobs run (cumulative)");
  // The column spelling stays findable, in the caption.
  EXPECT_NE(join_caption(figure).find("column: tracking_rmse_j2 (the tables' spelling)"), std::string::npos) << join_caption(figure);
}

// The TPE curve was invisible for its first jobs: it equals random's there and random, declared
// after it, was drawn on top. The baseline is drawn first and wider; the legend and colours keep
// the method first (the palette's first colour), and the caption says where the two are equal.
TEST_F(SearchFigureTest, DrawsTheMethodOverItsBaselineAndSaysWhereTheyAreEqual) {
  const Figure figure = make_figure();
  const std::vector<Curve>& curves = figure.panels[0].curves;
  ASSERT_EQ(curves.size(), 2u);
  EXPECT_EQ(curves[0].title, "tpe");  // the sweeps are in the caption, not in a legend wider than the panel
  EXPECT_EQ(curves[1].title, "random");
  FigureOptions paper;
  paper.style = FigureStyle::paper;
  const std::string script = make_gnuplot_script(figure, make_terminal_settings("f.pdf", paper, figure), "f.pdf", "/tmp");
  const std::size_t plot = script.find("\nplot ");
  ASSERT_NE(plot, std::string::npos) << script;
  const std::size_t tpe = script.find("data_0_0.dat", plot), random = script.find("data_0_1.dat", plot);
  ASSERT_NE(tpe, std::string::npos) << script;
  ASSERT_NE(random, std::string::npos) << script;
  EXPECT_LT(random, tpe) << script;  // drawn first: under tpe
  EXPECT_NE(script.find("with linespoints lw 2.5 pt 7 ps 0.7 lc rgb '" + figure_colours()[1] + "'", plot), std::string::npos) << script;
  EXPECT_NE(script.find("with linespoints lw 1 pt 7 ps 0.7 lc rgb '" + figure_colours()[0] + "'", plot), std::string::npos) << script;
  EXPECT_LT(script.find("title 'tpe'"), script.find("title 'random'")) << script;
  // Equal from job 1 until job 4, where TPE improves on random.
  const std::string caption = join_caption(figure);
  EXPECT_NE(caption.find("overlap: tpe lies on random (equal values) from 1 until 4 jobs run, random the wider line beneath"),
            std::string::npos)
      << caption;
  EXPECT_NE(caption.find("searches: tpe: sweep tpe_s; random: sweep random_s (the baseline)"), std::string::npos) << caption;
}

// Two random searches with equal staircases to the end: the later one hides the earlier, and
// the caption says so for the whole stretch ("to", not "until").
TEST_F(SearchFigureTest, ACurveHiddenToTheEndIsNamedWithTheSweepsThatTellThemApart) {
  {
    ResultsStore store = ResultsStore::open(db(), ResultsStore::Mode::read_write);
    store.insert_sweep_run(make_sweep("random_t"), {});
    store.insert_search(make_search("random_t", "random", "tracking_rmse", {{0, std::nullopt, 1.0}}));
    std::vector<SearchStepRecord> steps;
    for (std::int64_t s = 0; s < 5; ++s) steps.push_back({s, s, 0, s, "new", 1.0, "random_t" + std::to_string(s), std::nullopt, "", false});
    add_steps(store, "random_t", steps, {0.5, 0.3, 0.4, 0.2, 0.35}, 5);
  }
  const Figure figure = make_figure();
  ASSERT_EQ(figure.panels[0].curves.size(), 3u);
  EXPECT_EQ(figure.panels[0].curves[1].title, "random (random_s)");  // two random searches: named by sweep
  EXPECT_EQ(figure.panels[0].curves[2].title, "random (random_t)");
  const std::string caption = join_caption(figure);
  EXPECT_NE(caption.find("random (random_t) lies on random (random_s) (equal values) from 1 to 5 jobs run"), std::string::npos) << caption;
  EXPECT_NE(caption.find("tpe lies on random (random_s) (equal values) from 1 until 4 jobs run"), std::string::npos) << caption;
}

// The panel had about half of the page: a panel title ("Best objective against cost", what the
// figure's title says) took 3.6 lines under the figure's title. At paper style without the
// caption, the plot area now has at least 60 % of the page's height (51.6 % before).
TEST_F(SearchFigureTest, ThePanelSitsUnderTheTitleAndFillsMostOfThePage) {
  const Figure figure = remove_caption(make_figure());
  EXPECT_TRUE(figure.panels[0].title.empty());
  FigureOptions paper;
  paper.style = FigureStyle::paper;
  const std::string script = make_gnuplot_script(figure, make_terminal_settings("f.pdf", paper, figure), "f.pdf", "/tmp");
  const std::size_t at = script.find(" margins ");
  ASSERT_NE(at, std::string::npos) << script;
  double left = 0, right = 0, bottom = 0, top = 0;
  ASSERT_EQ(std::sscanf(script.c_str() + at, " margins %lf,%lf,%lf,%lf", &left, &right, &bottom, &top), 4) << script;
  EXPECT_GE(top - bottom, 0.6) << script;
}

// The overlap check of every other kind, on this one: each style, with and without the caption.
TEST_F(SearchFigureTest, NoTextOverlapsOrLeavesThePageInAnyStyle) {
  for (const char* style : {"paper", "screen", "slide"}) {
    for (const char* caption : {"", " --no-caption"}) {
      const std::string out = directory_.file(std::string("search_") + style + ".svg");
      const auto result = testing::run_armfarm("plot " + db() + " search --sweep tpe_s --style " + style + caption + " --out " + out);
      ASSERT_EQ(result.exit_code, 0) << result.output;
      const std::string svg = test_support::read_text_file(out);
      const auto boxes = testing::find_text_boxes(svg);
      EXPECT_GE(boxes.size(), 10u) << style << caption;  // the checker sees the labels
      const auto overlaps = testing::find_overlapping_text(svg);
      EXPECT_TRUE(overlaps.empty()) << style << caption << ": " << overlaps.size() << " overlaps, first "
                                    << (overlaps.empty() ? "" : overlaps.front());
      double width = 0, height = 0;
      ASSERT_EQ(std::sscanf(svg.c_str() + svg.find("viewBox=\"0 0 "), "viewBox=\"0 0 %lf %lf", &width, &height), 2);
      for (const testing::TextBox& box : boxes) {
        EXPECT_TRUE(box.left >= 0 && box.top >= 0 && box.right <= width && box.bottom <= height)
            << style << caption << ": '" << box.text << "' leaves the " << width << " x " << height << " page";
      }
      // --no-caption leaves the caption out (plot prints it instead).
      EXPECT_EQ(svg.find(">overlap: ") == std::string::npos, std::string(caption) != "") << style << caption;
      if (*caption) {
        EXPECT_NE(result.output.find("overlap: tpe lies on random"), std::string::npos) << result.output;
      }
    }
  }
}

// Spearman's ρ, worked by hand. Without ties, from 1 − 6 Σd²/(n(n²−1)), a different formula
// from the code's Pearson-of-ranks: x ranks 1…5, y = (0.3, 0.1, 0.2, 0.5, 0.4) ranks (3, 1, 2, 5, 4),
// d = (−2, 1, 1, −1, 1), Σd² = 8, ρ = 1 − 48/120 = 0.6. With a tie: x = (1, 2, 2, 3) has mid-ranks
// (1, 2.5, 2.5, 4), y ranks (1, 2, 3, 4); about the mean 2.5, Σrs = 4.5, Σr² = 4.5, Σs² = 5, so
// ρ = 4.5/√22.5 = √0.9.
TEST(RankCorrelation, MatchesHandWorkedValuesWithAndWithoutTies) {
  EXPECT_NEAR(*calc_rank_correlation({10, 20, 30, 40, 50}, {0.3, 0.1, 0.2, 0.5, 0.4}), 0.6, 1e-12);
  EXPECT_NEAR(*calc_rank_correlation({1, 2, 2, 3}, {1, 2, 3, 4}), std::sqrt(0.9), 1e-12);
  EXPECT_NEAR(*calc_rank_correlation({1, 2, 3}, {30, 20, 10}), -1.0, 1e-12);
  EXPECT_NEAR(*calc_rank_correlation({1, 5, 100}, {0.01, 0.02, 7}), 1.0, 1e-12);  // ranks only, not values
}

TEST(RankCorrelation, IsUndefinedForAConstantSideTooFewPairsOrUnequalSizes) {
  EXPECT_FALSE(calc_rank_correlation({1, 1, 1}, {1, 2, 3}).has_value());
  EXPECT_FALSE(calc_rank_correlation({4}, {2}).has_value());
  EXPECT_FALSE(calc_rank_correlation({1, 2, 3}, {1, 2}).has_value());
}

}  // namespace
}  // namespace armfarm
