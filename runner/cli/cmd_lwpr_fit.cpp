// `armfarm lwpr fit`: the alias of `armfarm fit --learner lwpr` (runner/cli/cmd_fit.cpp): batch-train
// an LWPR model on a recorded CSV and report its test nMSE, size and speed.
#include "runner/cli/cmd_fit.hpp"
#include "runner/cli/subcommand.hpp"

#include <memory>

namespace armfarm::cli {

RunFunction setup_lwpr_fit(CLI::App& group) {
  auto opt = std::make_shared<FitOptions>();
  opt->learner = "lwpr";
  CLI::App* app = group.add_subcommand("fit", "Batch-train LWPR on a CSV (N inputs, then outputs) and test it (= armfarm fit --learner lwpr)");
  add_fit_options(*app, *opt);
  return [opt] { return run_fit(*opt); };
}

}  // namespace armfarm::cli
