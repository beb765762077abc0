// `armfarm lwpr fit`: batch-train an LWPR model on a recorded CSV and report its test nMSE, size
// and speed (the thesis's "creating LWPR models" phase).
#include "engine/lwpr/lwpr_model.hpp"
#include "engine/lwpr/lwpr_model_file.hpp"
#include "engine/random/random_stream.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/io/csv_reader.hpp"
#include "runner/lwpr_params_json.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace armfarm::cli {
namespace {

struct FitOptions {
  std::string train, test, params, save;
  int inputs = 0;
  int epochs = 1;
  long long shuffle = -1;
  bool json = false;
};

Eigen::VectorXd calc_column_std(const Eigen::MatrixXd& m) {
  const Eigen::RowVectorXd mean = m.colwise().mean();
  return ((m.rowwise() - mean).array().square().colwise().sum() / std::max<Eigen::Index>(1, m.rows())).sqrt().transpose();
}

int run_fit(const FitOptions& opt) {
  const io::CsvTable train = io::load_csv(opt.train);
  const io::CsvTable test = io::load_csv(opt.test);
  const int n_cols = static_cast<int>(train.header.size());
  if (opt.inputs < 1 || opt.inputs >= n_cols) {
    throw std::runtime_error(opt.train + ": --inputs " + std::to_string(opt.inputs) + " leaves no output columns (" +
                             std::to_string(n_cols) + " columns)");
  }
  if (static_cast<int>(test.header.size()) != n_cols) {
    throw std::runtime_error(opt.test + ": " + std::to_string(test.header.size()) + " columns, the training file has " +
                             std::to_string(n_cols));
  }
  if (train.values.rows() == 0) throw std::runtime_error(opt.train + ": no data rows");
  if (test.values.rows() == 0) throw std::runtime_error(opt.test + ": no data rows");
  const int n_in = opt.inputs;
  const int n_out = n_cols - n_in;
  const Eigen::MatrixXd x_train = train.values.leftCols(n_in), y_train = train.values.rightCols(n_out);
  const Eigen::MatrixXd x_test = test.values.leftCols(n_in), y_test = test.values.rightCols(n_out);

  LwprDataScales scales{calc_column_std(x_train), calc_column_std(y_train)};
  const lwpr::LwprParams params = opt.params.empty() ? lwpr::LwprParams{} : load_lwpr_params(opt.params, n_in, scales);
  lwpr::LwprModel model(n_in, n_out, params);

  std::vector<Eigen::Index> order(x_train.rows());
  std::iota(order.begin(), order.end(), 0);
  RandomStream rng(opt.shuffle >= 0 ? static_cast<std::uint64_t>(opt.shuffle) : 0u, "lwpr_fit.shuffle");
  Eigen::VectorXd x(n_in), y(n_out);
  double update_seconds = 0.0;
  for (int epoch = 0; epoch < opt.epochs; ++epoch) {
    if (opt.shuffle >= 0) rng.shuffle(order.begin(), order.end());
    const auto start = std::chrono::steady_clock::now();
    for (Eigen::Index i : order) {
      x = x_train.row(i).transpose();
      y = y_train.row(i).transpose();
      model.update(x, y);
    }
    update_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  auto workspace = model.make_workspace();
  Eigen::MatrixXd predicted(x_test.rows(), n_out);
  long long untrusted = 0;
  const auto start = std::chrono::steady_clock::now();
  for (Eigen::Index i = 0; i < x_test.rows(); ++i) {
    x = x_test.row(i).transpose();
    const Prediction p = model.predict(x, *workspace);
    predicted.row(i) = p.value.transpose();
    if (!p.trustworthy) ++untrusted;
  }
  const double predict_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::vector<double> nmse(n_out);
  for (int o = 0; o < n_out; ++o) {
    const double mse = (predicted.col(o) - y_test.col(o)).squaredNorm() / y_test.rows();
    const double mean = y_test.col(o).mean();
    const double variance = (y_test.col(o).array() - mean).square().sum() / y_test.rows();
    nmse[o] = variance > 0.0 ? mse / variance : std::numeric_limits<double>::infinity();
  }
  const double nmse_mean = std::accumulate(nmse.begin(), nmse.end(), 0.0) / n_out;
  const double us_update = 1e6 * update_seconds / (static_cast<double>(x_train.rows()) * opt.epochs);
  const double us_predict = 1e6 * predict_seconds / static_cast<double>(x_test.rows());

  if (!opt.save.empty()) {
    const std::string temporary = opt.save + ".tmp";
    {
      std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
      if (!out) throw std::runtime_error(opt.save + ": cannot write");
      lwpr::write_lwpr_model(model, out);
    }
    std::filesystem::rename(temporary, opt.save);  // nothing half-written under the final name
  }

  if (opt.json) {
    nlohmann::json out;
    out["nmse"] = nmse;
    out["nmse_mean"] = nmse_mean;
    out["n_rf"] = model.size();
    std::vector<std::size_t> per_output;
    for (int o = 0; o < n_out; ++o) per_output.push_back(model.fields(o).size());
    out["n_rf_per_output"] = per_output;
    out["mean_projections"] = model.calc_mean_projections();
    out["us_per_update"] = us_update;
    out["us_per_predict"] = us_predict;
    out["untrusted_predictions"] = untrusted;
    std::cout << out.dump() << "\n";
    return 0;
  }
  for (int o = 0; o < n_out; ++o) {
    std::printf("output %-12s nMSE %.5f  fields %zu\n", train.header[n_in + o].c_str(), nmse[o], model.fields(o).size());
  }
  std::printf("overall: nMSE %.5f, %zu fields, %.2f projections per field, %.2f us/update, %.2f us/predict",
              nmse_mean, model.size(), model.calc_mean_projections(), us_update, us_predict);
  if (untrusted > 0) std::printf(", %lld test points without a trustworthy field (predicted 0)", untrusted);
  std::printf("\n");
  return 0;
}

}  // namespace

RunFunction setup_lwpr_fit(CLI::App& group) {
  auto opt = std::make_shared<FitOptions>();
  CLI::App* app = group.add_subcommand("fit", "Batch-train LWPR on a CSV (N inputs, then outputs) and test it");
  app->add_option("--train", opt->train, "Training CSV: header row, N input columns, then output columns")->required();
  app->add_option("--test", opt->test, "Test CSV with the same columns")->required();
  app->add_option("--inputs", opt->inputs, "Number of input columns N")->required()->check(CLI::PositiveNumber);
  app->add_option("--params", opt->params, "LWPR parameters (JSON, the published library's names)");
  app->add_option("--epochs", opt->epochs, "Passes over the training data")->check(CLI::PositiveNumber);
  app->add_option("--shuffle", opt->shuffle, "Shuffle each epoch with this seed")->check(CLI::NonNegativeNumber);
  app->add_option("--save", opt->save, "Write the trained model to this file");
  app->add_flag("--json", opt->json, "Print one JSON object instead of text");
  return [opt] { return run_fit(*opt); };
}

}  // namespace armfarm::cli
