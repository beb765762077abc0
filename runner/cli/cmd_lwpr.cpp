// `armfarm lwpr`: the group of LWPR commands (fit; inspect, predict with and export a saved or
// stored model).
#include "runner/cli/subcommand.hpp"

namespace armfarm::cli {

RunFunction setup_lwpr_fit(CLI::App& group);
RunFunction setup_lwpr_inspect(CLI::App& group);
RunFunction setup_lwpr_predict(CLI::App& group);
RunFunction setup_lwpr_export(CLI::App& group);

RunFunction setup_lwpr(CLI::App& parent) {
  CLI::App* group = parent.add_subcommand("lwpr", "LWPR learning on recorded data (fit) and learned models (inspect, predict, export)");
  group->require_subcommand(1);
  std::vector<std::pair<CLI::App*, RunFunction>> commands;
  const std::size_t before = group->get_subcommands({}).size();
  std::size_t count = before;
  for (const auto setup : {setup_lwpr_fit, setup_lwpr_inspect, setup_lwpr_predict, setup_lwpr_export}) {
    RunFunction run = setup(*group);
    if (group->get_subcommands({}).size() > count) commands.emplace_back(group->get_subcommands({}).back(), run);
    count = group->get_subcommands({}).size();
  }
  return [commands] {
    for (const auto& [sub, run] : commands) {
      if (sub->parsed()) return run();
    }
    return 2;
  };
}

}  // namespace armfarm::cli
