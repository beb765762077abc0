// The thesis's tables as data (sweeps/thesis/thesis_results.json) and their comparison with a
// results database: published cells read back exactly, armfarm values are the aggregate of the
// matching done jobs, absent sweeps and metrics say "not run", bad files name the JSON path.
#include "analysis/analysis_error.hpp"
#include "analysis/thesis_comparison.hpp"
#include "test_database.hpp"

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
  ASSERT_EQ(results.tables.size(), 9u);  // 6.1–6.7 and the two unnumbered tables of figures 6.12, 6.13
  std::size_t cells = 0;
  for (const ThesisTable& table : results.tables) cells += table.cells.size();
  EXPECT_EQ(cells, 6u * 4 * 2 + 2u * 2 * 2 + 3u * 4 * 5);

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
  EXPECT_NE(text.find("| Y | FB | 2.0E-03 | 4.000e-03 ± 1.414e-03 | 2 | 2 |"), std::string::npos) << text;
  EXPECT_NE(text.find("| W | CO | 1 | no metric | — | 0 |"), std::string::npos) << text;
  EXPECT_NE(text.find("### absent (page 57)"), std::string::npos) << text;
  EXPECT_NE(text.find("not run (sweep never_run absent)"), std::string::npos) << text;
  const std::string csv =
      format_thesis_comparison(make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::mean), TableFormat::csv,
                               Aggregate::mean);
  EXPECT_NE(csv.find("t_track,J2,CO,0.5,0.6,1.2,1,compared,\n"), std::string::npos) << csv;
  const nlohmann::json json = nlohmann::json::parse(format_thesis_comparison(
      make_thesis_comparison(thesis, {{"track", small_sweep()}}, Aggregate::mean), TableFormat::json, Aggregate::mean));
  EXPECT_DOUBLE_EQ(json[0]["cells"][0]["ratio"].get<double>(), 2.0);
  EXPECT_TRUE(json[1]["cells"][0]["armfarm"].is_null());
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
  EXPECT_NE(result.output.find("| Joint 1 | avg(ff/fb) | 0.912390 | 0.4562 | 0.5 | 1 |"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("| Joint 6 | avg(fb) | 0.001557 | 1.557e-03 | 1 | 1 |"), std::string::npos);
  EXPECT_NE(result.output.find("not run (sweep table6_1_figure_eight absent)"), std::string::npos);
  EXPECT_NE(result.output.find("| Joint 2 | avg(ff) | 0.329532 | not run (metric ff_abs_avg_j2 absent) | — | 0 |"),
            std::string::npos);

  const auto only = testing::run_armfarm("table " + db + " --sweep table6_4_sine --against " + kThesisFile + " --format csv");
  EXPECT_EQ(only.exit_code, 0) << only.output;
  EXPECT_EQ(only.output.find("table6_1"), std::string::npos) << only.output;
  EXPECT_NE(only.output.find("table6_4,Joint 1,avg(ff/fb),0.912390,0.456195,0.5,1,compared,"), std::string::npos) << only.output;

  const std::string bad = dir.file("bad.json");
  std::ofstream(bad) << R"({"tables": [{"id": "t", "caption": "c", "page": "57"}]})";
  const auto failure = testing::run_armfarm("table " + db + " --against " + bad);
  EXPECT_EQ(failure.exit_code, 2);
  EXPECT_EQ(failure.output, "armfarm: " + bad + ": tables[0].page: expected a positive integer or null\n");
}

}  // namespace
}  // namespace armfarm
