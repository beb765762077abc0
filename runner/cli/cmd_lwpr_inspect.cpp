// `armfarm lwpr inspect MODEL | --db DB --job KEY`: what a learned model holds — per output its
// receptive fields (trustworthy ones), the samples they saw (n_data) and their distance metrics D.
#include "engine/lwpr/lwpr_model.hpp"
#include "engine/learning/learner_model_file.hpp"
#include "runner/cli/lwpr_model_input.hpp"
#include "runner/cli/subcommand.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <vector>

namespace armfarm::cli {
namespace {

/// min, median, max and mean of a list (all 0 for an empty one).
nlohmann::json make_stats(std::vector<double> values) {
  if (values.empty()) return {{"min", 0.0}, {"median", 0.0}, {"max", 0.0}, {"mean", 0.0}};
  std::sort(values.begin(), values.end());
  double sum = 0.0;
  for (double v : values) sum += v;
  const std::size_t n = values.size();
  const double median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return {{"min", values.front()}, {"median", median}, {"max", values.back()}, {"mean", sum / static_cast<double>(n)}};
}

// Per output: fields, trustworthy fields, n_data of each field (samples seen, discounted by
// forgetting; its first projection's count), the diagonal entries D_ii of every field's metric
// (normalised input units⁻²) and projections per field.
nlohmann::json describe_lwpr(const lwpr::LwprModel& model) {
  nlohmann::json outputs = nlohmann::json::array();
  for (int o = 0; o < model.output_dim(); ++o) {
    const std::vector<lwpr::ReceptiveField> fields = model.fields(o);
    std::vector<double> n_data, diagonal, projections;
    int trusted = 0;
    for (const lwpr::ReceptiveField& rf : fields) {
      if (rf.trustworthy) ++trusted;
      n_data.push_back(rf.n_data.size() ? rf.n_data(0) : 0.0);
      projections.push_back(static_cast<double>(rf.beta.size()));
      const Eigen::VectorXd d = rf.metric.cols() == 1 ? Eigen::VectorXd(rf.metric.col(0)) : Eigen::VectorXd(rf.metric.diagonal());
      for (Eigen::Index i = 0; i < d.size(); ++i) diagonal.push_back(d(i));
    }
    outputs.push_back({{"output", o + 1},
                       {"fields", fields.size()},
                       {"trustworthy_fields", trusted},
                       {"n_data", make_stats(n_data)},
                       {"D_diagonal", make_stats(diagonal)},
                       {"projections", make_stats(projections)}});
  }
  return outputs;
}

int run_inspect(const ModelInput& input, bool json) {
  const LoadedModel loaded = load_model_input(input);
  const Learner& learner = *loaded.learner;
  nlohmann::json out = {{"source", loaded.source},
                        {"learner", find_learner_model_kind(loaded.bytes)},
                        {"bytes", loaded.bytes.size()},
                        {"inputs", learner.input_dim()},
                        {"outputs", learner.output_dim()},
                        {"size", learner.size()},
                        {"n_updates", learner.n_updates()}};
  const lwpr::LwprModel* lwpr = find_lwpr_model(learner);
  if (lwpr != nullptr) {
    out["per_output"] = describe_lwpr(*lwpr);
    out["update_D"] = lwpr->params().update_D;
    out["diag_only"] = lwpr->params().diag_only;
  }
  if (json) {
    std::cout << out.dump() << "\n";
    return 0;
  }
  std::printf("%s: %s model, %d inputs -> %d outputs, %zu bytes, %llu samples learnt, %zu %s\n", loaded.source.c_str(),
              out["learner"].get<std::string>().c_str(), learner.input_dim(), learner.output_dim(), loaded.bytes.size(),
              static_cast<unsigned long long>(learner.n_updates()), learner.size(), lwpr ? "receptive fields" : "local models");
  if (lwpr == nullptr) return 0;
  std::printf("update_D %s, diag_only %s\n", lwpr->params().update_D ? "on" : "off", lwpr->params().diag_only ? "on" : "off");
  std::printf("%-6s %6s %7s  %-28s %-34s %s\n", "output", "fields", "trusted", "n_data min/median/max",
              "D_ii min/median/max (normalised)", "projections (mean)");
  for (const nlohmann::json& o : out["per_output"]) {
    const nlohmann::json &n = o["n_data"], &d = o["D_diagonal"];
    std::printf("%-6d %6zu %7d  %-8.4g %-8.4g %-10.4g %-10.4g %-10.4g %-12.4g %.2f\n", o["output"].get<int>(),
                o["fields"].get<std::size_t>(), o["trustworthy_fields"].get<int>(), n["min"].get<double>(),
                n["median"].get<double>(), n["max"].get<double>(), d["min"].get<double>(), d["median"].get<double>(),
                d["max"].get<double>(), o["projections"]["mean"].get<double>());
  }
  return 0;
}

}  // namespace

RunFunction setup_lwpr_inspect(CLI::App& group) {
  auto input = std::make_shared<ModelInput>();
  auto json = std::make_shared<bool>(false);
  CLI::App* app = group.add_subcommand("inspect", "What a saved or stored model holds: fields per output, n_data, D");
  add_model_input_options(*app, *input);
  app->add_flag("--json", *json, "Print one JSON object instead of text");
  return [input, json] { return run_inspect(*input, *json); };
}

}  // namespace armfarm::cli
