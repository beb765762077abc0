#pragma once
// The thesis's figures of chapter 6, drawn from the shipped specs' databases beside the numbers
// the thesis publishes for them (sweeps/thesis/thesis_results.json, read by
// thesis_comparison.hpp). Which sweep, filter and checkpoint draw a figure is the file's
// `armfarm` mapping (the figure's own, else that of the table the figure's facts name); the
// overlays are the figure's stated facts and its table's cells, so each number has one home.
//
//   6.1   heldout_test_nmse of the thesis's joints 1 and 2 (the first two active joints) against
//         init_D, with and without distance-metric adaptation, at the last checkpoint; 95 %
//         Student-t bars over the seeds (the thesis prints no numbers: its finding is the title)
//   6.2   receptive fields per output against init_D, with and without adaptation, bars as 6.1
//   6.7   receptive fields per output against reaches (the TRIAL series' per-reach count ÷ the
//         outputs), the mean over seeds with its 95 % band per swept group; the thesis's 12 / 173
//         / 271 after 1 / 200 / 1000 reaches as black marks
//   6.8–6.10  feedback, feed-forward and composite torque per joint over the held-out pass at
//         the figure's checkpoint (series heldout_F_c<N>, heldout_FF_c<N>, heldout_TOR_c<N>) of
//         one job; each panel's title puts the thesis's avg(ff/fb) beside armfarm's mean [CI] (n)
//         over the seeds and the verdict (thesis_comparison.hpp)
//   6.11  the two recordings (POS_D of the test jobs of figures 6.12 and 6.13), top (x–y) and
//         side (y–z) views
//   6.12, 6.13  feedback and feed-forward per joint over the recording (series F, FF), titles as
//         6.8–6.10
#include "analysis/figure.hpp"
#include "analysis/thesis_comparison.hpp"
#include "results/results_store.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// The figure numbers make_thesis_figure draws: 6.1, 6.2, 6.7, 6.8, 6.9, 6.10, 6.11, 6.12, 6.13.
const std::vector<std::string>& drawable_thesis_figures();

struct ThesisFigureRequest {
  std::string number;                 ///< "6.7"
  std::optional<std::string> sweep;   ///< replaces the file's sweep (e.g. a renamed copy)
  std::vector<std::string> job_keys;  ///< signal figures: the job (key or unique prefix); default: the lowest seed with the series
  /// The SI unit of a configuration key (runner/cli/param_unit.hpp), for parameter axes.
  std::function<std::string(const std::string& path)> param_unit;
};

/// Builds figure `request.number` from `store`. Throws AnalysisError naming what is missing: a
/// number not drawn (listing those that are), a figure the file lacks, a sweep absent from the
/// database, series not recorded (with the recording.series to set).
Figure make_thesis_figure(const ResultsStore& store, const ThesisResults& thesis, const ThesisFigureRequest& request);

}  // namespace armfarm
