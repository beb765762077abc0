// `armfarm plot DB KIND [--sweep NAME] [--job KEY] [--out FILE.svg|.png] [--metric M --param P
// [--group P] [--joint J]]`: the thesis's figures from a results database, via gnuplot.
#include "analysis/plots.hpp"
#include "results/results_store.hpp"
#include "runner/cli/subcommand.hpp"

#include <iostream>
#include <memory>

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
  bool log_x = false, log_y = false, linear_x = false, linear_y = false;
  std::string kernel_param = "learning.lwpr.init_D";
  std::string adaptation_param = "learning.lwpr.update_D";
};

}  // namespace

RunFunction setup_plot(CLI::App& parent) {
  auto options = std::make_shared<PlotOptions>();
  CLI::App* sub = parent.add_subcommand("plot", "Plot a sweep: nmse-vs-kernel, rf-growth, signals, tracking, metric-vs-param");
  sub->add_option("database", options->database, "Results database (SQLite)")->required();
  sub->add_option("kind", options->kind, "nmse-vs-kernel | rf-growth | signals | tracking | metric-vs-param")
      ->required()
      ->check(CLI::IsMember({"nmse-vs-kernel", "rf-growth", "signals", "tracking", "metric-vs-param"}));
  sub->add_option("--sweep", options->sweep, "Sweep name (needed when the database holds several)");
  sub->add_option("--job", options->jobs, "Job key or unique prefix (repeatable; default: chosen from the sweep)");
  sub->add_option("--out", options->out, "Output file, .svg or .png (default: KIND.svg)");
  sub->add_option("--metric", options->metric, "metric-vs-param: the metric on the y axis");
  sub->add_option("--param", options->param, "metric-vs-param: the swept parameter on the x axis");
  sub->add_option("--group", options->group, "metric-vs-param: one curve per value of this parameter");
  sub->add_option("--joint", options->joint, "metric-vs-param: joint of a per-joint metric (1-based)")->check(CLI::PositiveNumber);
  sub->add_flag("--logx", options->log_x, "Logarithmic x axis (default: automatic, where values span decades)");
  sub->add_flag("--logy", options->log_y, "Logarithmic y axis (default: automatic)");
  sub->add_flag("--linx", options->linear_x, "Linear x axis");
  sub->add_flag("--liny", options->linear_y, "Linear y axis");
  sub->add_option("--kernel-param", options->kernel_param, "nmse-vs-kernel: kernel-width parameter");
  sub->add_option("--adaptation-param", options->adaptation_param, "nmse-vs-kernel: distance-metric adaptation parameter");
  return [options] {
    PlotRequest request;
    request.kind = parse_plot_kind(options->kind);
    if (!options->sweep.empty()) request.sweep = options->sweep;
    request.job_keys = options->jobs;
    request.metric = options->metric;
    request.param = options->param;
    request.group = options->group;
    if (options->joint > 0) request.joint = options->joint;
    request.kernel_param = options->kernel_param;
    request.adaptation_param = options->adaptation_param;
    if (options->log_x || options->linear_x) request.log_x = options->log_x;
    if (options->log_y || options->linear_y) request.log_y = options->log_y;
    const std::string out = options->out.empty() ? options->kind + ".svg" : options->out;
    const ResultsStore store = ResultsStore::open(options->database, ResultsStore::Mode::read_only);
    write_figure(make_plot_figure(store, request), out);
    std::cout << "wrote " << out << "\n";
    return 0;
  };
}

}  // namespace armfarm::cli
