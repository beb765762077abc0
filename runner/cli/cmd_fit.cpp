// `armfarm fit`: batch-train LWPR or SSGPR on a recorded CSV (N inputs, then outputs), test it on
// another CSV, report nMSE per output, size, µs per update and predict, memory; optionally save
// the model file (engine/lwpr/lwpr_model_file.hpp, engine/ssgpr/ssgpr_model_file.hpp).
#include "runner/cli/cmd_fit.hpp"

#include "engine/learning/learner_factory.hpp"
#include "engine/learning/learner_model_file.hpp"
#include "engine/lwpr/lwpr_model.hpp"
#include "engine/random/random_stream.hpp"
#include "engine/ssgpr/ssgpr_fitting_learner.hpp"
#include "runner/cli/number_checks.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/io/csv_reader.hpp"
#include "runner/lwpr_params_json.hpp"
#include "runner/ssgpr_params_json.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <ctime>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace armfarm::cli {
namespace {

Eigen::VectorXd calc_column_std(const Eigen::MatrixXd& m) {
  const Eigen::RowVectorXd mean = m.colwise().mean();
  return ((m.rowwise() - mean).array().square().colwise().sum() / std::max<Eigen::Index>(1, m.rows())).sqrt().transpose();
}

LearnerKind parse_learner(const std::string& name) {
  int value = 0;
  if (!find_enum_value(learner_kind_names(), name, value)) {
    throw std::runtime_error("--learner: \"" + name + "\" is not " + make_enum_choice_text(learner_kind_names()));
  }
  return static_cast<LearnerKind>(value);
}

void save_model(const Learner& learner, const std::string& path) {
  const std::string bytes = encode_learner_model(learner);
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(path + ": cannot write");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out.flush()) throw std::runtime_error(path + ": write failed");
  }
  std::filesystem::rename(temporary, path);  // nothing half-written under the final name
}

// CPU time of the calling thread in seconds: on a shared machine wall time also counts the time
// the scheduler gives other processes.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::vector<double> to_list(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

}  // namespace

void add_fit_options(CLI::App& app, FitOptions& opt) {
  app.add_option("--train", opt.train, "Training CSV: header row, N input columns, then output columns")->required();
  app.add_option("--test", opt.test, "Test CSV with the same columns")->required();
  app.add_option("--inputs", opt.inputs, "Number of input columns N")->required()->check(make_positive_check());
  app.add_option("--params", opt.params,
                 "Learner parameters (JSON): LWPR with the published library's names; SSGPR with the learning.ssgpr keys "
                 "(lengthscales in input standard deviations)");
  app.add_option("--epochs", opt.epochs, "Passes over the training data")->check(make_positive_check());
  app.add_option("--shuffle", opt.shuffle, "Shuffle each epoch with this seed")->check(make_non_negative_check());
  app.add_option("--save", opt.save, "Write the trained model to this file (the learner's model file format)");
  app.add_flag("--json", opt.json, "Print one JSON object instead of text");
}

int run_fit(const FitOptions& opt) {
  const LearnerKind kind = parse_learner(opt.learner);
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
  const Eigen::VectorXd input_std = calc_column_std(x_train);

  std::unique_ptr<Learner> learner;
  if (kind == LearnerKind::lwpr) {
    LwprDataScales scales{input_std, calc_column_std(y_train)};
    const lwpr::LwprParams params = opt.params.empty() ? lwpr::LwprParams{} : load_lwpr_params(opt.params, n_in, scales);
    learner = std::make_unique<lwpr::LwprModel>(n_in, n_out, params);
  } else {
    LearningConfig config;
    config.learner = kind;
    if (!opt.params.empty()) config.ssgpr = load_ssgpr_params(opt.params);
    const std::string source = opt.params.empty() ? std::string("SSGPR defaults") : opt.params;
    const double samples = static_cast<double>(x_train.rows()) * opt.epochs;
    if (config.ssgpr.fit_samples > 0 && samples < static_cast<double>(config.ssgpr.fit_samples)) {
      throw std::runtime_error(opt.train + ": " + std::to_string(x_train.rows()) + " rows × " + std::to_string(opt.epochs) +
                               " epochs are fewer than fit_samples = " + std::to_string(config.ssgpr.fit_samples) + " (" +
                               source + "): the hyperparameters would never be fitted");
    }
    // Lengthscales in input standard deviations, as in a job; a constant column keeps its own units.
    const Eigen::VectorXd scale = (input_std.array() > 0.0).select(input_std, 1.0);
    try {
      learner = make_learner(config, n_in, n_out, scale);
    } catch (const std::invalid_argument& error) {
      throw std::runtime_error(source + ": " + error.what());
    }
  }

  std::vector<Eigen::Index> order(x_train.rows());
  std::iota(order.begin(), order.end(), 0);
  RandomStream rng(opt.shuffle >= 0 ? static_cast<std::uint64_t>(opt.shuffle) : 0u, "lwpr_fit.shuffle");
  Eigen::VectorXd x(n_in), y(n_out);
  double update_seconds = 0.0, update_cpu_seconds = 0.0;
  for (int epoch = 0; epoch < opt.epochs; ++epoch) {
    if (opt.shuffle >= 0) rng.shuffle(order.begin(), order.end());
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = thread_cpu_seconds();
    for (Eigen::Index i : order) {
      x = x_train.row(i).transpose();
      y = y_train.row(i).transpose();
      learner->update(x, y);
    }
    update_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    update_cpu_seconds += thread_cpu_seconds() - cpu_start;
  }
  const double fit_seconds = learner->fit_seconds();
  update_seconds = std::max(0.0, update_seconds - fit_seconds);
  update_cpu_seconds = std::max(0.0, update_cpu_seconds - fit_seconds);

  auto workspace = learner->make_workspace();
  Eigen::MatrixXd predicted(x_test.rows(), n_out);
  long long untrusted = 0;
  const auto start = std::chrono::steady_clock::now();
  const double predict_cpu_start = thread_cpu_seconds();
  Prediction p;  // one for all rows: predict_into reuses its vectors
  for (Eigen::Index i = 0; i < x_test.rows(); ++i) {
    x = x_test.row(i).transpose();
    learner->predict_into(x, *workspace, p);
    predicted.row(i) = p.value.transpose();
    if (!p.trustworthy) ++untrusted;
  }
  const double predict_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double predict_cpu_seconds = thread_cpu_seconds() - predict_cpu_start;

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

  if (!opt.save.empty()) save_model(*learner, opt.save);

  const lwpr::LwprModel* lwpr_model = find_lwpr_model(*learner);
  const ssgpr::SsgprModel* ssgpr_model = find_ssgpr_model(*learner);
  if (opt.json) {
    nlohmann::json out;
    out["learner"] = opt.learner;
    out["nmse"] = nmse;
    out["nmse_mean"] = nmse_mean;
    out["us_per_update"] = us_update;
    out["us_per_predict"] = us_predict;
    out["cpu_us_per_update"] = 1e6 * update_cpu_seconds / (static_cast<double>(x_train.rows()) * opt.epochs);
    out["cpu_us_per_predict"] = 1e6 * predict_cpu_seconds / static_cast<double>(x_test.rows());
    out["untrusted_predictions"] = untrusted;
    out["memory_bytes"] = learner->calc_memory_bytes();
    if (lwpr_model) {
      out["n_rf"] = lwpr_model->size();
      std::vector<std::size_t> per_output;
      for (int o = 0; o < n_out; ++o) per_output.push_back(lwpr_model->fields(o).size());
      out["n_rf_per_output"] = per_output;
      out["mean_projections"] = lwpr_model->calc_mean_projections();
    }
    if (ssgpr_model) {
      const ssgpr::SsgprParams& p = ssgpr_model->params();
      out["features"] = p.features;
      out["fit_seconds"] = fit_seconds;
      out["lengthscales"] = to_list(ssgpr::calc_expanded_vector(p.lengthscales, n_in));
      out["signal_variance"] = p.signal_variance;
      out["noise_variance"] = p.noise_variance;
      out["output_scale"] = to_list(ssgpr::calc_expanded_vector(p.output_scale, n_out));
    }
    std::cout << out.dump() << "\n";
    return 0;
  }
  for (int o = 0; o < n_out; ++o) {
    std::printf("output %-12s nMSE %.5f", train.header[n_in + o].c_str(), nmse[o]);
    if (lwpr_model) std::printf("  fields %zu", lwpr_model->fields(o).size());
    std::printf("\n");
  }
  if (lwpr_model) {
    std::printf("overall: nMSE %.5f, %zu fields, %.2f projections per field", nmse_mean, lwpr_model->size(),
                lwpr_model->calc_mean_projections());
  } else {
    std::printf("overall: nMSE %.5f, %zu features", nmse_mean, learner->size());
    if (ssgpr_model) {
      std::printf(" (hyperparameters %s: signal variance %.4g, noise variance %.4g)",
                  fit_seconds > 0.0 ? "fitted" : "as given", ssgpr_model->params().signal_variance,
                  ssgpr_model->params().noise_variance);
    }
  }
  std::printf(", %.2f us/update, %.2f us/predict, %.1f kB", us_update, us_predict,
              static_cast<double>(learner->calc_memory_bytes()) / 1024.0);
  if (fit_seconds > 0.0) std::printf(", fit %.2f s", fit_seconds);
  if (untrusted > 0) std::printf(", %lld test points without a trustworthy prediction (predicted 0)", untrusted);
  std::printf("\n");
  return 0;
}

RunFunction setup_fit(CLI::App& parent) {
  auto opt = std::make_shared<FitOptions>();
  CLI::App* app = parent.add_subcommand("fit", "Batch-train a learner (LWPR or SSGPR) on a CSV (N inputs, then outputs) and test it");
  std::vector<std::string> names;
  for (const EnumName& name : learner_kind_names()) names.push_back(name.name);
  app->add_option("--learner", opt->learner, "Which learner (default lwpr)")->check(CLI::IsMember(names));
  add_fit_options(*app, *opt);
  return [opt] { return run_fit(*opt); };
}

}  // namespace armfarm::cli
