// The thesis's tables as data (sweeps/thesis/thesis_results.json) and their comparison with a
// results database: published cells read back exactly, armfarm values are the aggregate of the
// matching done jobs, absent sweeps and metrics say "not run", bad files name the JSON path.
#include "analysis/analysis_error.hpp"
#include "analysis/thesis_comparison.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace armfarm {
namespace {

const std::string kThesisFile = std::string(ARMFARM_SOURCE_DIR) + "/sweeps/thesis/thesis_results.json";

const ThesisTable& find_table(const ThesisResults& results, const std::string& id) {
  for (const ThesisTable& table : results.tables) {
    if (table.id == id) return table;
  }
  throw std::runtime_error("no table " + id);
}

const ThesisCell& find_cell(const ThesisTable& table, const std::string& row, const std::string& column) {
  for (const ThesisCell& cell : table.cells) {
    if (cell.row == row && cell.column == column) return cell;
  }
  throw std::runtime_error("no cell " + row + " / " + column + " in " + table.id);
}

// What `armfarm table --against` does, without its confined read (tested in runner/).
ThesisResults load_thesis_results(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return parse_thesis_results_text(text.str(), path);
}

std::string error_of(const std::string& text) {
  testing::TemporaryDirectory dir;
  const std::string path = dir.file("thesis.json");
  std::ofstream(path) << text;
  try {
    load_thesis_results(path);
  } catch (const AnalysisError& e) {
    return std::string(e.what()).substr(path.size());  // the part after the file name
  }
  return "(no error)";
}

TEST(ThesisResults, ShippedFileHoldsEveryTableOfChapterSixAsPrinted) {
  const ThesisResults results = load_thesis_results(kThesisFile);
  // 6.1–6.7, the two unnumbered tables of figures 6.12, 6.13, then the figures' stated numbers
  // (6.7: fields after 1, 200 and 1000 reaches, the last also per output; 6.8–6.10: the model's
  // fields, summed and per output).
  ASSERT_EQ(results.tables.size(), 13u);
  std::size_t cells = 0;
  for (std::size_t t = 0; t < 9; ++t) cells += results.tables[t].cells.size();
  EXPECT_EQ(cells, 6u * 4 * 2 + 2u * 2 * 2 + 3u * 4 * 5);
  const ThesisTable& f67 = find_table(results, "fig6_7");
  ASSERT_EQ(f67.cells.size(), 4u);
  EXPECT_EQ(f67.cells[2].value, 271);  // read from figures[6].facts.receptive_fields_after_reaches
  EXPECT_EQ(*f67.cells[2].mapping.metric, "n_receptive_fields");
  EXPECT_EQ(f67.cells[3].value, 271);
  EXPECT_EQ(*f67.cells[3].mapping.metric, "n_receptive_fields_per_output");
  EXPECT_TRUE(f67.cells[0].mapping.metric_given && !f67.cells[0].mapping.metric);  // the RF series, no metric
  const ThesisCell& f69 = find_table(results, "fig6_9").cells.at(0);
  EXPECT_EQ(f69.value, 173);
  EXPECT_EQ(*f69.mapping.sweep, "table6_5_7_heldout_reaching");
  EXPECT_EQ(*f69.mapping.checkpoint, 200);

  // Literal values from the thesis (table, row, column as printed).
  const ThesisCell& t61 = find_cell(find_table(results, "table6_1"), "Joint 1", "avg(ff/fb)");
  EXPECT_EQ(t61.value, 0.433344);
  EXPECT_EQ(t61.printed, "0.433344");
  EXPECT_EQ(find_cell(find_table(results, "table6_1"), "Joint 1", "avg(ff)").printed, "0.013400");
  const ThesisCell& t62 = find_cell(find_table(results, "table6_2"), "Z-axis [0-750]", "Composite control nMSE");
  EXPECT_EQ(t62.value, 2.63e-4);
  EXPECT_EQ(t62.printed, "2.63E-04");
  EXPECT_EQ(find_cell(find_table(results, "table6_3"), "Y-axis [325-750]", "Feedback control nMSE").value, 8.96e-3);
  EXPECT_EQ(find_cell(find_table(results, "table6_4"), "Joint 6", "var(ff/fb)").value, 0.049541);
  EXPECT_EQ(find_cell(find_table(results, "table6_5"), "Joint 2", "avg(fb)").value, 0.194204);
  EXPECT_EQ(find_cell(find_table(results, "table6_6"), "Joint 3", "avg(ff/fb)").value, 0.656594);
  EXPECT_EQ(find_cell(find_table(results, "table6_7"), "Joint 2", "avg(ff)").value, 0.192755);
  EXPECT_EQ(find_cell(find_table(results, "fig6_12_numerical"), "Joint 2", "avg(ff)").value, 0.382137);
  EXPECT_EQ(find_cell(find_table(results, "fig6_13_numerical"), "Joint 3", "avg(fb)").value, 0.049179);

  const ThesisTable& t65 = find_table(results, "table6_5");
  EXPECT_EQ(*t65.number, "6.5");
  EXPECT_EQ(t65.heading, "Test set - model with 12 receptive fields");
  EXPECT_FALSE(t65.page);  // the text places figure 6.8 on page 57, not the table
  EXPECT_FALSE(find_table(results, "fig6_12_numerical").number);
  EXPECT_EQ(find_table(results, "fig6_12_numerical").caption, "Numerical results from Figure 6.12.");
  // The comparisons the thesis's text draws (table 6.1's major joints over 1, 5, 6; composite over
  // feedback in 6.2, 6.3; the sine over the eight; 6.7 over 6.5), each checked against its values.
  ASSERT_EQ(results.comparisons.size(), 27u);  // and the growth 12 → 173 → 271 of figures 6.8–6.10
  EXPECT_EQ(results.comparisons[9].greater.column, "Feedback control nMSE");
  EXPECT_EQ(results.comparisons[24].less.table, "table6_7");

  // The mapping: held-out reaching at checkpoint 200, the second active joint.
  const ThesisMapping& m = find_cell(find_table(results, "table6_6"), "Joint 2", "var(ff/fb)").mapping;
  EXPECT_EQ(*m.sweep, "table6_5_7_heldout_reaching");
  EXPECT_EQ(*m.metric, "heldout_ff_fb_ratio_var");
  EXPECT_EQ(*m.active_joint, 2);
  EXPECT_EQ(*m.checkpoint, 200.0);
  const ThesisMapping& fb = find_cell(find_table(results, "table6_2"), "Y-axis [0-750]", "Feedback control nMSE").mapping;
  EXPECT_EQ(*fb.metric, "tracking_nmse_y");
  ASSERT_EQ(fb.where.size(), 2u);  // the table's gain scale and the column's control mode
  EXPECT_EQ(fb.where[1].second, "feedback");
}

TEST(ThesisResults, ShippedFileStatesTheFiguresFacts) {
  std::ifstream in(kThesisFile);
  const nlohmann::json document = nlohmann::json::parse(in);
  std::map<std::string, nlohmann::json> figures;
  for (const auto& figure : document.at("figures")) figures[figure.at("number").get<std::string>()] = figure;
  EXPECT_EQ(figures.at("6.8").at("page"), 57);
  EXPECT_EQ(figures.at("6.9").at("page"), 58);
  EXPECT_EQ(figures.at("6.10").at("page"), 59);
  EXPECT_EQ(figures.at("6.8").at("facts").at("receptive_fields"), 12);
  EXPECT_EQ(figures.at("6.9").at("facts").at("receptive_fields"), 173);
  EXPECT_EQ(figures.at("6.10").at("facts").at("receptive_fields"), 271);
  EXPECT_TRUE(figures.at("6.1").at("page").is_null());
  EXPECT_EQ(figures.at("6.1").at("facts").at("samples"), 40000);
  EXPECT_EQ(figures.at("6.3").at("facts").at("samples"), 200000);
  EXPECT_EQ(figures.at("6.7").at("facts").at("reaches"), 1000);
}

JobResult make_job(int index, const std::string& mode, int seed, const std::string& status, std::map<MetricId, double> metrics) {
  JobResult job;
  job.key = "job" + std::to_string(index);
  job.status = status;
  job.seed = seed;
  job.params = {{"control.mode", mode}, {"seed", seed}};
  // Joint numbers as the store's normalized configuration reads them back (2.0).
  job.config = {{"active_joints", {2.0, 3.0, 5.0}}, {"control", {{"mode", mode}, {"gain_scale", 0.2}}}};
  job.metrics = std::move(metrics);
  return job;
}

// A two-table file: a tracking table with filters per column and metrics per row, and a
// per-joint table on an absent sweep.
const char* kSmallThesis = R"json({"tables": [
  {"id": "t_track", "number": "6.2", "caption": "tracking", "page": null,
   "armfarm": {"sweep": "track", "where": {"control.gain_scale": 0.2}},
   "columns": [{"label": "FB", "armfarm": {"where": {"control.mode": "feedback"}}},
               {"label": "CO", "armfarm": {"where": {"control.mode": "composite"}}}],
   "rows": [{"label": "Y", "armfarm": {"metric": "tracking_nmse_y"}},
            {"label": "J2", "armfarm": {"metric": "ff_fb_ratio_avg", "active_joint": 2}},
            {"label": "J3", "armfarm": {"metric": "ff_fb_ratio_avg", "active_joint": 3}},
            {"label": "W", "armfarm": {"metric": null}},
            {"label": "H", "armfarm": {"metric": "heldout_ff_fb_ratio_avg", "checkpoint": 200}},
            {"label": "J4", "armfarm": {"metric": "ff_fb_ratio_avg", "active_joint": 4}}],
   "cells": [{"row": "Y", "column": "FB", "value": 2.0E-03, "printed": "2.0E-03"},
             {"row": "Y", "column": "CO", "value": 1.0E-03, "printed": "1.0E-03"},
             {"row": "J2", "column": "CO", "value": 0.5, "printed": "0.5"},
             {"row": "J3", "column": "CO", "value": 0.8, "printed": "0.8"},
             {"row": "W", "column": "CO", "value": 1, "printed": "1"},
             {"row": "H", "column": "CO", "value": 0.4, "printed": "0.4"},
             {"row": "J4", "column": "CO", "value": 0.4, "printed": "0.4"}]},
  {"id": "t_absent", "number": null, "caption": "absent", "page": 57, "armfarm": {"sweep": "never_run"},
   "columns": [{"label": "avg(ff/fb)", "armfarm": {"metric": "ff_fb_ratio_avg"}}],
   "rows": [{"label": "Joint 1", "armfarm": {"active_joint": 1}}],
   "cells": [{"row": "Joint 1", "column": "avg(ff/fb)", "value": 0.25, "printed": "0.25"}]}]})json";

ThesisResults small_thesis() { return parse_thesis_results(nlohmann::json::parse(kSmallThesis), "small.json"); }

SweepData small_sweep() {
  SweepData data;
  data.name = "track";
  // Feedback: two seeds, y nMSE 3e-3 and 5e-3 → mean 4e-3, ratio 2 against 2e-3.
  data.jobs.push_back(make_job(0, "feedback", 0, "done", {{{"tracking_nmse_y", {}}, 3e-3}}));
  data.jobs.push_back(make_job(1, "feedback", 1, "done", {{{"tracking_nmse_y", {}}, 5e-3}}));
  // Composite: one done (joint 3 is the second active joint, joint 5 the third), one diverged
  // whose values must not be averaged in.
  data.jobs.push_back(make_job(2, "composite", 0, "done",
                               {{{"tracking_nmse_y", {}}, 5e-4}, {{"ff_fb_ratio_avg", 3}, 0.6}, {{"ff_fb_ratio_avg", 2}, 0.1}}));
  data.jobs.push_back(make_job(3, "composite", 1, "diverged", {{{"tracking_nmse_y", {}}, 1e9}, {{"ff_fb_ratio_avg", 3}, 1e9}}));
  data.varying_params = calc_varying_params(data.jobs);
  return data;
}

// A checkpointed cell reads the metric at that checkpoint only; an undefined (NULL) value is
// reported with its stored reason, never averaged as a number.
TEST(ThesisComparison, CheckpointCellsReadTheirCheckpointAndUndefinedValuesAreNotAveraged) {
  const ThesisResults thesis = small_thesis();
  SweepData data = small_sweep();
  MetricId at200{"heldout_ff_fb_ratio_avg", std::nullopt, 200}, at1{"heldout_ff_fb_ratio_avg", std::nullopt, 1};
  data.jobs[2].metrics[at200] = 0.3;
  data.jobs[2].metrics[at1] = 0.9;
  ThesisComparison comparison = make_thesis_comparison(thesis, {{"track", data}}, Aggregate::mean);
  const ComparedCell& held_out = comparison.tables[0].cells[5];
  ASSERT_EQ(held_out.state, CellState::compared) << held_out.reason;
  EXPECT_NEAR(held_out.armfarm_value, 0.3, 1e-15);
  EXPECT_NEAR(*held_out.ratio, 0.75, 1e-12);  // against the thesis 0.4

  data.jobs[2].metrics[at200] = std::nan("");
  data.jobs[2].reasons[at200] = "target std below the floor";
  comparison = make_thesis_comparison(thesis, {{"track", data}}, Aggregate::mean);
  const ComparedCell& undefined = comparison.tables[0].cells[5];
  EXPECT_EQ(undefined.state, CellState::not_run);
  EXPECT_NE(undefined.reason.find("target std below the floor"), std::string::npos) << undefined.reason;
}

TEST(ThesisComparison, CellsAreTheAggregateOfMatchingDoneJobsAndTheirRatio) {
  const ThesisResults thesis = small_thesis();
  const ThesisComparison comparison = make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::mean);
  ASSERT_EQ(comparison.tables.size(), 2u);
  const std::vector<ComparedCell>& cells = comparison.tables[0].cells;
  ASSERT_EQ(cells.size(), 7u);
  EXPECT_EQ(cells[0].state, CellState::compared);
  EXPECT_EQ(cells[0].armfarm.count, 2);
  EXPECT_NEAR(cells[0].armfarm_value, 4e-3, 1e-18);
  EXPECT_NEAR(*cells[0].ratio, 2.0, 1e-12);
  EXPECT_EQ(cells[1].armfarm.count, 1);  // the diverged job's 1e9 is not averaged in
  EXPECT_NEAR(*cells[1].ratio, 0.5, 1e-12);
  // "Joint 2" of the thesis = the second active joint = physical joint 3.
  EXPECT_NEAR(cells[2].armfarm_value, 0.6, 1e-15);
  EXPECT_NEAR(*cells[2].ratio, 1.2, 1e-12);  // against the thesis 0.5
  // The third active joint (5) has no ff_fb_ratio_avg.
  EXPECT_EQ(cells[3].state, CellState::not_run);
  EXPECT_EQ(cells[3].reason, "metric ff_fb_ratio_avg_j3 absent");
  EXPECT_EQ(cells[4].state, CellState::no_metric);
  EXPECT_EQ(cells[5].state, CellState::not_run);
  EXPECT_NE(cells[5].reason.find("checkpoint 200"), std::string::npos) << cells[5].reason;
  EXPECT_EQ(cells[6].reason, "the jobs move fewer than 4 joints");  // the jobs move 3
  // A sweep the database does not hold.
  EXPECT_EQ(comparison.tables[1].cells[0].state, CellState::not_run);
  EXPECT_EQ(comparison.tables[1].cells[0].reason, "sweep never_run absent");

  const ThesisComparison only = make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::max, std::string("never_run"));
  ASSERT_EQ(only.tables.size(), 1u);
  EXPECT_EQ(only.tables[0].thesis->id, "t_absent");
  EXPECT_THROW(make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::mean, std::string("other")), AnalysisError);
  const ThesisComparison maximum = make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::max);
  EXPECT_DOUBLE_EQ(maximum.tables[0].cells[0].armfarm_value, 5e-3);
}

TEST(ThesisComparison, NoJobMatchingTheFilterIsNotRun) {
  const ThesisResults thesis = small_thesis();
  SweepData data = small_sweep();
  for (JobResult& job : data.jobs) job.config["control"]["gain_scale"] = 1.0;
  const ThesisComparison comparison = make_thesis_comparison(thesis, {{"track", data}}, Aggregate::mean);
  EXPECT_EQ(comparison.tables[0].cells[0].state, CellState::not_run);
  EXPECT_EQ(comparison.tables[0].cells[0].reason, "no job of track with control.gain_scale=0.2, control.mode=feedback");
}

TEST(ThesisComparison, MarkdownShowsThesisArmfarmAndRatio) {
  const ThesisResults thesis = small_thesis();
  const std::string text =
      format_thesis_comparison(make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::mean), TableFormat::markdown,
                               Aggregate::mean);
  EXPECT_NE(text.find("### Table 6.2: tracking"), std::string::npos) << text;
  EXPECT_NE(text.find("| Y | FB | 2.0E-03 | 4.000e-03 [-8.706e-03, 0.01671] (2) | 2 | matches |"), std::string::npos) << text;
  EXPECT_NE(text.find("| W | CO | 1 | no metric | — | — |"), std::string::npos) << text;
  EXPECT_NE(text.find("### absent (page 57)"), std::string::npos) << text;
  EXPECT_NE(text.find("not run (sweep never_run absent)"), std::string::npos) << text;
  const std::string csv =
      format_thesis_comparison(make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::mean), TableFormat::csv,
                               Aggregate::mean);
  EXPECT_NE(csv.find("t_track,J2,CO,0.5,0.6,,,1.2,1,one seed,compared,\n"), std::string::npos) << csv;
  const nlohmann::json json = nlohmann::json::parse(format_thesis_comparison(
      make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::mean), TableFormat::json, Aggregate::mean));
  EXPECT_DOUBLE_EQ(json[0]["cells"][0]["ratio"].get<double>(), 2.0);
  EXPECT_TRUE(json[1]["cells"][0]["armfarm"].is_null());
}

// Verdicts on constructed cases: table "t" with cells A (thesis 1.0) and B (thesis 0.5), the
// thesis drawing A > B, and C (thesis 2.0) that no comparison names.
const char* kVerdictThesis = R"json({"tables": [
  {"id": "t", "number": "9.9", "caption": "verdicts", "page": null, "armfarm": {"sweep": "v"},
   "columns": [{"label": "value"}],
   "rows": [{"label": "A", "armfarm": {"metric": "m_a"}}, {"label": "B", "armfarm": {"metric": "m_b"}},
            {"label": "C", "armfarm": {"metric": "m_c"}}],
   "cells": [{"row": "A", "column": "value", "value": 1.0, "printed": "1.0"},
             {"row": "B", "column": "value", "value": 0.5, "printed": "0.5"},
             {"row": "C", "column": "value", "value": 2.0, "printed": "2.0"}]}],
 "comparisons": [{"claim": "A above B", "greater": {"table": "t", "row": "A", "column": "value"},
                  "less": {"table": "t", "row": "B", "column": "value"}}]})json";

// One job per seed with m_a, m_b, m_c as given.
SweepData make_verdict_sweep(const std::vector<double>& a, const std::vector<double>& b, const std::vector<double>& c) {
  SweepData data;
  data.name = "v";
  for (std::size_t i = 0; i < a.size(); ++i) {
    JobResult job;
    job.key = "v" + std::to_string(i);
    job.status = "done";
    job.seed = static_cast<std::int64_t>(i);
    job.params = {{"seed", job.seed}};
    job.metrics = {{{"m_a", {}}, a[i]}, {{"m_b", {}}, b[i]}, {{"m_c", {}}, c[i]}};
    data.jobs.push_back(job);
  }
  data.varying_params = calc_varying_params(data.jobs);
  return data;
}

std::vector<Verdict> verdicts_of(const SweepData& data) {
  const ThesisResults thesis = parse_thesis_results(nlohmann::json::parse(kVerdictThesis), "verdicts.json");
  const ThesisComparison comparison = make_thesis_comparison(thesis, {{"v", data}}, Aggregate::mean);
  std::vector<Verdict> verdicts;
  for (const ComparedCell& cell : comparison.tables.at(0).cells) verdicts.push_back(cell.verdict);
  return verdicts;
}

TEST(ThesisComparison, VerdictsFollowTheRuleOnConstructedCases) {
  // A's five seeds have mean 1.0 and interval 1.0 ∓ 2.776·0.0791 ⊃ 1.0: matches. B's interval
  // [2.08, 2.32] misses 0.5 but A > B fails in every seed: differs. C: no comparison, outside: differs.
  EXPECT_EQ(verdicts_of(make_verdict_sweep({0.9, 1.0, 1.1, 0.95, 1.05}, {2.0, 2.1, 2.2, 2.3, 2.4}, {5, 5.1, 5.2, 5.3, 5.4})),
            (std::vector<Verdict>{Verdict::matches, Verdict::differs, Verdict::differs}));
  // A far above 1.0 and B far above 0.5, but A > B in all five seeds (sign test p = 1/32):
  // both "same direction"; C inside its interval matches.
  EXPECT_EQ(verdicts_of(make_verdict_sweep({3.0, 3.1, 3.2, 3.3, 3.4}, {2.0, 2.1, 2.2, 2.3, 2.4}, {1.9, 2.0, 2.1, 2.0, 2.0})),
            (std::vector<Verdict>{Verdict::same_direction, Verdict::same_direction, Verdict::matches}));
  // A > B in 4 of 5 seeds: p = 6/32 > 5 %, so differs.
  EXPECT_EQ(verdicts_of(make_verdict_sweep({3.0, 3.1, 3.2, 3.3, 2.0}, {2.0, 2.1, 2.2, 2.3, 2.4}, {5, 5.1, 5.2, 5.3, 5.4}))[0],
            Verdict::differs);
  // 9 of 10 seeds: p = 11/1024 < 5 %, so the comparison holds without holding in every seed.
  std::vector<double> a, b, c;
  for (int i = 0; i < 10; ++i) {
    a.push_back(3.0 + 0.1 * i);
    b.push_back(i == 9 ? 9.0 : 2.0 + 0.1 * i);
    c.push_back(2.0);
  }
  EXPECT_EQ(verdicts_of(make_verdict_sweep(a, b, c))[0], Verdict::same_direction);
  // One seed: no interval, no verdict.
  EXPECT_EQ(verdicts_of(make_verdict_sweep({3.0}, {2.0}, {2.0}))[0], Verdict::one_seed);
  EXPECT_TRUE(holds_across_seeds(2, 2));
  EXPECT_FALSE(holds_across_seeds(1, 1));
  EXPECT_FALSE(holds_across_seeds(4, 5));

  // The printed cell: thesis | mean [interval] (n) | ratio | verdict with the seed count.
  const ThesisResults thesis = parse_thesis_results(nlohmann::json::parse(kVerdictThesis), "verdicts.json");
  const std::string text = format_thesis_comparison(
      make_thesis_comparison(thesis, {{"v", make_verdict_sweep({3.0, 3.1, 3.2, 3.3, 3.4}, {2.0, 2.1, 2.2, 2.3, 2.4}, {2, 2, 2, 2, 2})}},
                             Aggregate::mean),
      TableFormat::markdown, Aggregate::mean);
  EXPECT_NE(text.find("| A | value | 1.0 | 3.2 [3.004, 3.396] (5) | 3.2 | same direction (above t B / value: 5 of 5 seeds) |"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("Verdicts over 3 cells: 1 matches, 2 same direction, 0 differs, 0 one seed, 0 not compared"), std::string::npos)
      << text;
}

// A cell whose matching jobs differ in more than their seed is not pooled.
TEST(ThesisComparison, CellsPoolOnlyJobsThatDifferInTheirSeed) {
  SweepData data = make_verdict_sweep({1.0, 1.1}, {0.5, 0.6}, {2.0, 2.1});
  data.jobs[1].params["learning.lwpr.init_D"] = 0.5;
  data.jobs[0].params["learning.lwpr.init_D"] = 0.1;
  data.varying_params = calc_varying_params(data.jobs);
  const ThesisResults thesis = parse_thesis_results(nlohmann::json::parse(kVerdictThesis), "verdicts.json");
  const ThesisComparison comparison = make_thesis_comparison(thesis, {{"v", data}}, Aggregate::mean);
  EXPECT_EQ(comparison.tables[0].cells[0].state, CellState::not_run);
  EXPECT_NE(comparison.tables[0].cells[0].reason.find("differ in learning.lwpr.init_D"), std::string::npos)
      << comparison.tables[0].cells[0].reason;
}

// A later stage repeated by seed names the earlier stage's job of its own seed: those jobs pool;
// a reference to another seed's model is a difference.
TEST(ThesisComparison, StageJobsWhoseModelComesFromTheirOwnSeedPool) {
  SweepData data = make_verdict_sweep({1.0, 1.1}, {0.5, 0.6}, {2.0, 2.1});
  for (JobResult& job : data.jobs) {
    job.params["learning.initial_model"] = {{"stage", "train"}, {"params", {{"seed", job.seed}}}};
  }
  data.varying_params = calc_varying_params(data.jobs);
  const ThesisResults thesis = parse_thesis_results(nlohmann::json::parse(kVerdictThesis), "verdicts.json");
  ThesisComparison comparison = make_thesis_comparison(thesis, {{"v", data}}, Aggregate::mean);
  ASSERT_EQ(comparison.tables[0].cells[0].state, CellState::compared) << comparison.tables[0].cells[0].reason;
  EXPECT_EQ(comparison.tables[0].cells[0].armfarm.count, 2);

  data.jobs[1].params["learning.initial_model"]["params"]["seed"] = 0;  // seed 1's job on seed 0's model
  data.varying_params = calc_varying_params(data.jobs);
  comparison = make_thesis_comparison(thesis, {{"v", data}}, Aggregate::mean);
  EXPECT_EQ(comparison.tables[0].cells[0].state, CellState::not_run);
  EXPECT_NE(comparison.tables[0].cells[0].reason.find("differ in learning.initial_model"), std::string::npos)
      << comparison.tables[0].cells[0].reason;
}

TEST(ThesisResults, ComparisonsMustAgreeWithTheThesissOwnValues) {
  auto with_claim = [](const std::string& greater, const std::string& less) {
    nlohmann::json document = nlohmann::json::parse(kVerdictThesis);
    document["comparisons"][0]["greater"]["row"] = greater;
    document["comparisons"][0]["less"]["row"] = less;
    return document;
  };
  EXPECT_NO_THROW(parse_thesis_results(with_claim("C", "A"), "x.json"));  // 2.0 above 1.0
  try {
    parse_thesis_results(with_claim("B", "A"), "x.json");  // 0.5 above 1.0 is not what the thesis printed
    FAIL() << "accepted";
  } catch (const AnalysisError& e) {
    EXPECT_EQ(std::string(e.what()), "x.json: comparisons[0]: the thesis's own values (0.5 and 1) do not have greater above less");
  }
  try {
    parse_thesis_results(with_claim("Z", "A"), "x.json");
    FAIL() << "accepted";
  } catch (const AnalysisError& e) {
    EXPECT_EQ(std::string(e.what()), "x.json: comparisons[0].greater: table 't' has no cell 'Z' / 'value'");
  }
}

TEST(ThesisResults, MalformedFilesNameTheJsonPath) {
  EXPECT_EQ(error_of("{\"tables\": [}").substr(0, 26), ": line 1, column 13: not v");
  EXPECT_EQ(error_of("{\"tables\": 3}"), ": tables: expected an array");
  const std::string table = R"({"id": "t", "number": "6.1", "caption": "c", "page": null,
    "columns": [{"label": "a"}], "rows": [{"label": "r"}], "cells": [CELL]})";
  auto with_cell = [&](const std::string& cell) {
    std::string text = table;
    text.replace(text.find("CELL"), 4, cell);
    return error_of("{\"tables\": [" + text + "]}");
  };
  EXPECT_EQ(with_cell(R"({"row": "r", "column": "a", "value": "0.5", "printed": "0.5"})"), ": tables[0].cells[0].value: expected a number");
  EXPECT_EQ(with_cell(R"({"row": "r", "column": "a", "value": 0.5, "printed": "0.50001"})"),
            ": tables[0].cells[0].printed: '0.50001' is not the value 0.5");
  EXPECT_EQ(with_cell(R"({"row": "x", "column": "a", "value": 0.5, "printed": "0.5"})"),
            ": tables[0].cells[0].row: 'x' is not a label of tables[0].rows");
  EXPECT_EQ(with_cell(R"({"row": "r", "column": "a", "value": 0.5, "printed": "0.5", "armfarm": {"metirc": "x"}})"),
            ": tables[0].cells[0].armfarm.metirc: unknown key (expected sweep, where, metric, active_joint, checkpoint, note)");
  EXPECT_EQ(with_cell(R"({"row": "r", "column": "a", "value": 0.5, "printed": "0.5", "armfarm": {"active_joint": 0}})"),
            ": tables[0].cells[0].armfarm.active_joint: expected a positive integer or null");
  EXPECT_EQ(error_of(R"({"tables": [{"id": "t", "caption": "c", "columns": [], "rows": [], "cells": []}]})"),
            ": tables[0]: missing key 'page'");
}


// A figure's "fact" is a path into its `facts` read by the one path parser (base/config_path.hpp,
// through find_config_value): keys by '.', array elements by 0-based "[i]"; a path that names
// nothing, or does not parse, is "no fact".
TEST(ThesisResults, AFactIsAPathIntoTheFiguresFacts) {
  auto figure_with_fact = [](const std::string& fact) {
    return R"({"tables": [], "figures": [{"number": "6.7", "caption": "c", "page": null,
      "facts": {"fields": {"200": 173}, "box": {"x": [20, 70]}, "source": "text"},
      "fact_cells": [{"fact": ")" + fact + R"(", "label": "L"}]}]})";
  };
  testing::TemporaryDirectory dir;
  const std::string path = dir.file("thesis.json");
  std::ofstream(path) << figure_with_fact("fields.200");
  EXPECT_EQ(load_thesis_results(path).tables.at(0).cells.at(0).value, 173);
  std::ofstream(path) << figure_with_fact("box.x[1]");
  const ThesisResults element = load_thesis_results(path);
  EXPECT_EQ(element.tables.at(0).id, "fig6_7");
  EXPECT_EQ(element.tables.at(0).cells.at(0).value, 70);
  EXPECT_EQ(element.tables.at(0).cells.at(0).printed, "70");
  for (const std::string fact : {"fields.201", "box.x[2]", "fields..200", "", "box[0]"}) {
    EXPECT_EQ(error_of(figure_with_fact(fact)), ": figures[0].fact_cells[0].fact: no fact '" + fact + "' in figures[0].facts") << fact;
  }
  EXPECT_EQ(error_of(figure_with_fact("source")), ": figures[0].fact_cells[0].fact: 'source' is not a number");
}
TEST(ThesisComparison, ArmfarmTableAgainstPrintsEveryThesisCell) {
  testing::TemporaryDirectory dir;
  const std::string db = dir.file("results.db");
  // A database holding a sweep named like the shipped table 6.4 sweep, with joints 1-6 active.
  std::vector<testing::TestJob> jobs(1);
  jobs[0].params = {{"control.mode", "composite"}, {"control.feed_forward", "learner"}, {"active_joints", {1, 2, 3, 4, 5, 6}}};
  jobs[0].metrics = {{0, "ff_fb_ratio_avg", 1, 0.456195}, {0, "fb_abs_avg", 6, 0.001557}};
  testing::write_test_sweep(db, "table6_4_sine", jobs);

  const auto result = testing::run_armfarm("table " + db + " --against " + kThesisFile);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("| Joint 1 | avg(ff/fb) | 0.912390 | 0.4562 (1) | 0.5 | one seed |"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("| Joint 6 | avg(fb) | 0.001557 | 1.557e-03 (1) | 1 | one seed |"), std::string::npos);
  EXPECT_NE(result.output.find("not run (sweep table6_1_figure_eight absent)"), std::string::npos);
  EXPECT_NE(result.output.find("| Joint 2 | avg(ff) | 0.329532 | not run (metric ff_abs_avg_j2 absent) | — | — |"),
            std::string::npos);

  const auto only = testing::run_armfarm("table " + db + " --sweep table6_4_sine --against " + kThesisFile + " --format csv");
  EXPECT_EQ(only.exit_code, 0) << only.output;
  EXPECT_EQ(only.output.find("table6_1"), std::string::npos) << only.output;
  EXPECT_NE(only.output.find("table6_4,Joint 1,avg(ff/fb),0.912390,0.456195,,,0.5,1,one seed,compared,"), std::string::npos) << only.output;

  const std::string bad = dir.file("bad.json");
  std::ofstream(bad) << R"({"tables": [{"id": "t", "caption": "c", "page": "57"}]})";
  const auto failure = testing::run_armfarm("table " + db + " --against " + bad);
  EXPECT_EQ(failure.exit_code, 2);
  EXPECT_EQ(failure.output, "armfarm: " + bad + ": tables[0].page: expected a positive integer or null\n");
}

// --sweep takes every shipped spec: one mapped through a figure's facts prints that figure's
// table; one that draws figures without numbers, or no thesis content, prints why and exits 0;
// a name neither the file nor the database knows exits 2.
TEST(ThesisComparison, ArmfarmTableAgainstAcceptsEveryShippedSweep) {
  testing::TemporaryDirectory dir;
  const std::string db = dir.file("results.db");
  std::vector<testing::TestJob> jobs(2);
  jobs[0].params = {{"seed", 0}};
  jobs[0].metrics = {{0, "n_receptive_fields", std::nullopt, 300}};
  jobs[1].params = {{"seed", 1}};
  jobs[1].metrics = {{0, "n_receptive_fields", std::nullopt, 310}};
  testing::write_test_sweep(db, "fig6_1_kernel_width", jobs);
  testing::write_test_sweep(db, "controllers_sine", jobs);
  // Figure 6.7 reads the init_D of its rule (0.3, sweeps/thesis/README.md); the jobs at another
  // width are left out, or the cell would pool jobs that differ in more than their seed.
  std::vector<testing::TestJob> widths = jobs;
  for (testing::TestJob& job : widths) job.params["learning.lwpr.init_D"] = 0.3;
  for (const testing::TestJob& job : jobs) {
    testing::TestJob wide = job;
    wide.params["learning.lwpr.init_D"] = 0.5;
    wide.metrics = {{0, "n_receptive_fields", std::nullopt, 900}};
    widths.push_back(wide);
  }
  testing::write_test_sweep(db, "fig6_7_reaching_fields", widths);

  const auto fields = testing::run_armfarm("table " + db + " --sweep fig6_7_reaching_fields --against " + kThesisFile);
  EXPECT_EQ(fields.exit_code, 0) << fields.output;
  EXPECT_NE(fields.output.find("### Figure 6.7: Number of receptive fields"), std::string::npos) << fields.output;
  // 305 ∓ 12.706·5: [241.5, 368.5] holds 271.
  EXPECT_NE(fields.output.find("| receptive fields after 1000 reaches (summed over the outputs) | fact | 271 | 305 [241.5, 368.5] (2) | 1.125 | matches |"),
            std::string::npos)
      << fields.output;
  EXPECT_NE(fields.output.find("| receptive fields after 1 reach | fact | 12 | no metric | — | — |"), std::string::npos) << fields.output;

  const auto kernel = testing::run_armfarm("table " + db + " --sweep fig6_1_kernel_width --against " + kThesisFile);
  EXPECT_EQ(kernel.exit_code, 0) << kernel.output;
  EXPECT_NE(kernel.output.find("sweep fig6_1_kernel_width draws figure(s) 6.1, 6.2"), std::string::npos) << kernel.output;
  const auto other = testing::run_armfarm("table " + db + " --sweep controllers_sine --against " + kThesisFile);
  EXPECT_EQ(other.exit_code, 0) << other.output;
  EXPECT_NE(other.output.find("sweep controllers_sine reproduces no table or figure of the thesis"), std::string::npos) << other.output;
  const auto typo = testing::run_armfarm("table " + db + " --sweep fig6_7_reaching_feilds --against " + kThesisFile);
  EXPECT_EQ(typo.exit_code, 2) << typo.output;
}

}  // namespace
}  // namespace armfarm
