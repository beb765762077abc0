// `armfarm plot DB KIND [--sweep NAME] [--job KEY] [--out FILE.pdf|.svg|.png] [--metric M --param P
// [--group P] [--joint J] [--checkpoint N]] [--style paper|slide|screen] [--size W,H] [--font-size PT]
// [--title T] [--xlabel X] [--ylabel Y] [--caption|--no-caption]`: the thesis's figures from a results database, via gnuplot.
// `armfarm plot DB thesis-figure --figure 6.7 --against sweeps/thesis/thesis_results.json`: a
// figure of chapter 6 beside the thesis's numbers (analysis/thesis_figures.hpp).
#include "analysis/analysis_error.hpp"
#include "analysis/plots.hpp"
#include "analysis/thesis_figures.hpp"
#include "engine/io/input_file.hpp"
#include "results/readable_check.hpp"
#include "results/results_store.hpp"
#include "runner/cli/param_unit.hpp"
#include "runner/cli/number_checks.hpp"
#include "runner/cli/subcommand.hpp"

#include <iostream>
#include <memory>
#include <optional>

namespace armfarm::cli {
namespace {

struct PlotOptions {
  std::string database;
  std::string kind;
  std::string sweep;
  std::vector<std::string> jobs;
  std::string out;
  std::string metric;
  std::string param;
  std::string group;
  int joint = 0;
  int checkpoint = 0;
  bool log_x = false, log_y = false, linear_x = false, linear_y = false;
  std::string style;
  std::vector<double> size;
  double font_size = 0;
  std::optional<std::string> title, x_label, y_label;
  bool caption = true;  ///< --no-caption: nothing under the legend; the caption goes to standard output
  std::string kernel_param = "learning.lwpr.init_D";
  std::string adaptation_param = "learning.lwpr.update_D";
  std::string figure;   ///< thesis-figure: "6.7"
  std::string against;  ///< thesis-figure: thesis_results.json
};

// The thesis figure `options` ask for (kind thesis-figure), from the numbers of `options.against`.
Figure make_requested_thesis_figure(const ResultsStore& store, const PlotOptions& options) {
  if (options.figure.empty() || options.against.empty()) {
    throw AnalysisError("thesis-figure needs --figure N (one of 6.1, 6.2, 6.7, 6.8, 6.9, 6.10, 6.11, 6.12, 6.13) and --against "
                        "sweeps/thesis/thesis_results.json");
  }
  const ThesisResults thesis =
      parse_thesis_results_text(read_input_file_as<AnalysisError>(options.against, InputFileKind::json), options.against);
  ThesisFigureRequest request;
  request.number = options.figure;
  if (!options.sweep.empty()) request.sweep = options.sweep;
  request.job_keys = options.jobs;
  request.param_unit = find_param_unit;
  return make_thesis_figure(store, thesis, request);
}

// The plot subcommand's arguments and options, into `options`.
void add_plot_options(CLI::App& parent, PlotOptions& options) {
  CLI::App* sub = parent.add_subcommand("plot", "Plot a sweep: nmse-vs-kernel, rf-growth, signals, tracking, metric-vs-param, search, thesis-figure");
  sub->add_option("database", options.database, "Results database (SQLite)")->required();
  sub->add_option("kind", options.kind,
                  "nmse-vs-kernel | rf-growth | signals | tracking | metric-vs-param | search (objective against cost, random beside the "
                  "method) | thesis-figure (--figure N --against thesis_results.json: a chapter-6 figure with the thesis's numbers)")
      ->required()
      ->check(CLI::IsMember({"nmse-vs-kernel", "rf-growth", "signals", "tracking", "metric-vs-param", "search", "thesis-figure"}));
  sub->add_option("--sweep", options.sweep, "Sweep name (needed when the database holds several)");
  sub->add_option("--job", options.jobs, "Job key or unique prefix (repeatable; default: chosen from the sweep)");
  sub->add_option("--out", options.out, "Output file, .pdf, .svg or .png by extension (default: KIND.svg)");
  sub->add_option("--metric", options.metric, "metric-vs-param: the metric on the y axis");
  sub->add_option("--param", options.param, "metric-vs-param: the swept parameter on the x axis");
  sub->add_option("--group", options.group, "metric-vs-param: one curve per value of this parameter");
  sub->add_option("--joint", options.joint, "metric-vs-param: joint of a per-joint metric (1-based)")->check(make_positive_check());
  sub->add_option("--checkpoint", options.checkpoint, "metric-vs-param: checkpoint of a held-out metric (heldout_*)")
      ->check(make_positive_check());
  sub->add_option("--style", options.style,
                  "paper (3.5 in wide, 8 pt; default for .pdf and .png), slide (10 x 5.6 in, 16 pt) or screen (default for .svg)")
      ->check(CLI::IsMember({"paper", "slide", "screen"}));
  sub->add_option("--size", options.size, "Width,height in inches (overrides the style)")->delimiter(',')->expected(2)
      ->check(make_range_check(0.5, 100.0));
  sub->add_option("--font-size", options.font_size, "Font size in points (overrides the style)")->check(make_range_check(1.0, 200.0));
  sub->add_option("--title", options.title, "Figure title (\"\" for none)");
  sub->add_option("--xlabel", options.x_label, "x-axis label of every panel");
  sub->add_option("--ylabel", options.y_label, "y-axis label of every panel");
  sub->add_flag("--caption,!--no-caption", options.caption,
                "Draw the caption and table under the legend (default); --no-caption leaves them out, for a document that sets "
                "its own caption, and prints them after the file's name");
  sub->add_flag("--logx", options.log_x, "Logarithmic x axis (default: automatic, where values span decades)");
  sub->add_flag("--logy", options.log_y, "Logarithmic y axis (default: automatic)");
  sub->add_flag("--linx", options.linear_x, "Linear x axis");
  sub->add_flag("--liny", options.linear_y, "Linear y axis");
  sub->add_option("--kernel-param", options.kernel_param, "nmse-vs-kernel: kernel-width parameter");
  sub->add_option("--adaptation-param", options.adaptation_param, "nmse-vs-kernel: distance-metric adaptation parameter");
  sub->add_option("--figure", options.figure,
                  "thesis-figure: 6.1, 6.2 (kernel width), 6.7 (fields per reach), 6.8-6.10 (held-out torques), 6.11 (recordings), "
                  "6.12, 6.13 (torques on the recordings)");
  sub->add_option("--against", options.against,
                  "thesis-figure: thesis results JSON (sweeps/thesis/thesis_results.json): the sweep, filter and the numbers overlaid");
}

// The request of a plot kind (not thesis-figure) from the command's options.
PlotRequest make_plot_request(const PlotOptions& options) {
  PlotRequest request;
  request.kind = parse_plot_kind(options.kind);
  if (!options.sweep.empty()) request.sweep = options.sweep;
  request.job_keys = options.jobs;
  request.metric = options.metric;
  request.param = options.param;
  request.group = options.group;
  if (options.joint > 0) request.joint = options.joint;
  if (options.checkpoint > 0) request.checkpoint = options.checkpoint;
  request.kernel_param = options.kernel_param;
  request.adaptation_param = options.adaptation_param;
  request.param_unit = find_param_unit;
  if (options.log_x || options.linear_x) request.log_x = options.log_x;
  if (options.log_y || options.linear_y) request.log_y = options.log_y;
  return request;
}

FigureOptions make_figure_options(const PlotOptions& options) {
  FigureOptions figure_options;
  if (!options.style.empty()) figure_options.style = parse_figure_style(options.style);
  if (options.size.size() == 2) {
    figure_options.width_in = options.size[0];
    figure_options.height_in = options.size[1];
  }
  if (options.font_size > 0) figure_options.font_pt = options.font_size;
  figure_options.caption = options.caption;
  return figure_options;
}

int run_plot(const PlotOptions& options) {
  const ResultsStore store = ResultsStore::open(options.database, ResultsStore::Mode::read_only);
  verify_readable(store);  // damaged rows and series are an error, not a quiet plot
  // thesis-figure: analysis/thesis_figures.hpp
  Figure figure = options.kind == "thesis-figure" ? make_requested_thesis_figure(store, options)
                                                  : make_plot_figure(store, make_plot_request(options));
  if (options.title) figure.title = *options.title;
  for (Panel& panel : figure.panels) {
    if (options.x_label) panel.x_label = *options.x_label;
    if (options.y_label) panel.y_label = *options.y_label;
  }
  const std::string out = options.out.empty() ? options.kind + ".svg" : options.out;
  write_figure(figure, out, make_figure_options(options));
  std::cout << "wrote " << out << "\n";
  const std::string caption = format_caption_text(figure);
  if (!options.caption && !caption.empty()) std::cout << "caption (not drawn, --no-caption):\n" << caption;
  return 0;
}

}  // namespace

RunFunction setup_plot(CLI::App& parent) {
  auto options = std::make_shared<PlotOptions>();
  add_plot_options(parent, *options);
  return [options] { return run_plot(*options); };
}

}  // namespace armfarm::cli
