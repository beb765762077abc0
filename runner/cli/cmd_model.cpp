// `armfarm model <subcommand>`: commands that read one arm model file. The group is a small
// table like the top-level one: add a model subcommand with one declaration and one entry.
#include "runner/cli/subcommand.hpp"

namespace armfarm::cli {

RunFunction setup_model_info(CLI::App& model);
RunFunction setup_model_dynamics(CLI::App& model);

namespace {
const std::vector<SubcommandEntry>& model_subcommands() {
  static const std::vector<SubcommandEntry> entries = {
      {"info", setup_model_info},
      {"dynamics", setup_model_dynamics},
  };
  return entries;
}
}  // namespace

RunFunction setup_model(CLI::App& parent) {
  CLI::App* model = parent.add_subcommand("model", "Inspect arm model files (.urdf, .dcg)");
  model->require_subcommand(1);
  std::vector<std::pair<CLI::App*, RunFunction>> runs;
  for (const auto& entry : model_subcommands()) {
    RunFunction run = entry.setup(*model);
    runs.emplace_back(model->get_subcommands({}).back(), std::move(run));
  }
  return [runs] {
    for (const auto& [sub, run] : runs) {
      if (sub->parsed()) return run();
    }
    return 2;
  };
}

}  // namespace armfarm::cli
