// `armfarm lwpr predict MODEL | --db DB --job KEY (--x V,V,... | --csv FILE)`: the model's
// prediction at given inputs, in the model's units (a job's model: q, q̇, q̈ of each active joint in
// that order → torques, N·m). Prints CSV: the inputs, then y<o> and confidence<o> per output (one
// standard deviation, same units); an output the model cannot predict at x (no trustworthy field)
// has an empty y and confidence inf.
#include "base/number_format.hpp"
#include "runner/cli/lwpr_model_input.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/io/csv_reader.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace armfarm::cli {
namespace {

struct PredictOptions {
  ModelInput input;
  std::vector<std::string> points;  ///< --x, each "v,v,..."
  std::string csv;
};

Eigen::VectorXd parse_point(const std::string& text, int n_in) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string field;
  while (std::getline(stream, field, ',')) {
    std::size_t used = 0;
    double value = 0.0;
    try {
      value = std::stod(field, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    while (used < field.size() && std::isspace(static_cast<unsigned char>(field[used]))) ++used;
    if (used == 0 || used != field.size() || !std::isfinite(value)) {
      throw std::runtime_error("--x " + text + ": \"" + field + "\" is not a finite number");
    }
    values.push_back(value);
  }
  if (static_cast<int>(values.size()) != n_in) {
    throw std::runtime_error("--x " + text + ": " + std::to_string(values.size()) + " values; the model has " +
                             std::to_string(n_in) + " inputs");
  }
  return Eigen::Map<Eigen::VectorXd>(values.data(), n_in);
}

int run_predict(const PredictOptions& opt) {
  if (opt.points.empty() == opt.csv.empty()) throw std::runtime_error("give the inputs with --x or with --csv (one of them)");
  const LoadedModel loaded = load_model_input(opt.input);
  const Learner& learner = *loaded.learner;
  const int n_in = learner.input_dim(), n_out = learner.output_dim();
  Eigen::MatrixXd inputs;
  std::vector<std::string> header;
  if (!opt.csv.empty()) {
    const io::CsvTable table = io::load_csv(opt.csv);
    if (static_cast<int>(table.header.size()) != n_in) {
      throw std::runtime_error(opt.csv + ":1: " + std::to_string(table.header.size()) + " columns; the model (" + loaded.source +
                               ") has " + std::to_string(n_in) + " inputs");
    }
    inputs = table.values;
    header = table.header;
  } else {
    inputs.resize(static_cast<Eigen::Index>(opt.points.size()), n_in);
    for (std::size_t i = 0; i < opt.points.size(); ++i) inputs.row(static_cast<Eigen::Index>(i)) = parse_point(opt.points[i], n_in).transpose();
    for (int i = 0; i < n_in; ++i) header.push_back("x" + std::to_string(i + 1));
  }
  std::string line;
  for (const std::string& name : header) line += (line.empty() ? "" : ",") + name;
  for (int o = 1; o <= n_out; ++o) line += ",y" + std::to_string(o) + ",confidence" + std::to_string(o);
  std::cout << line << "\n";
  auto workspace = learner.make_workspace();
  for (Eigen::Index r = 0; r < inputs.rows(); ++r) {
    const Eigen::VectorXd x = inputs.row(r).transpose();
    const Prediction p = learner.predict(x, *workspace);
    line.clear();
    for (int i = 0; i < n_in; ++i) line += (i ? "," : "") + format_number(x(i), 17);
    for (int o = 0; o < n_out; ++o) {
      const bool trusted = p.output_trusted.empty() || p.output_trusted[static_cast<std::size_t>(o)];
      line += "," + (trusted ? format_number(p.value(o), 17) : std::string()) + "," +
              (trusted ? format_number(p.confidence(o), 17) : std::string("inf"));
    }
    std::cout << line << "\n";
  }
  std::cout.flush();
  return std::cout ? 0 : 2;
}

}  // namespace

RunFunction setup_lwpr_predict(CLI::App& group) {
  auto opt = std::make_shared<PredictOptions>();
  CLI::App* app = group.add_subcommand("predict", "Predict with a saved or stored model at inputs given as --x or a CSV");
  add_model_input_options(*app, opt->input);
  app->add_option("--x", opt->points, "One input point, comma-separated (repeatable)");
  app->add_option("--csv", opt->csv, "CSV of input points: a header row, one column per model input");
  return [opt] { return run_predict(*opt); };
}

}  // namespace armfarm::cli
