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
#include "runner/config/lwpr_params_json.hpp"
#include "runner/config/ssgpr_params_json.hpp"

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

// The training and test files split into inputs (the first N columns) and outputs.
struct FitData {
  std::vector<std::string> header;  ///< the training file's column names
  int n_in = 0, n_out = 0;
  Eigen::MatrixXd x_train, y_train, x_test, y_test;
};

FitData load_fit_data(const FitOptions& opt) {
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
  FitData data;
  data.header = train.header;
  data.n_in = opt.inputs;
  data.n_out = n_cols - opt.inputs;
  data.x_train = train.values.leftCols(data.n_in);
  data.y_train = train.values.rightCols(data.n_out);
  data.x_test = test.values.leftCols(data.n_in);
  data.y_test = test.values.rightCols(data.n_out);
  return data;
}

// An SSGPR learner from --params (or the defaults); lengthscales in input standard deviations,
// as in a job, a constant column keeping its own units.
std::unique_ptr<Learner> make_ssgpr_learner(const FitOptions& opt, LearnerKind kind, const FitData& data,
                                            const Eigen::VectorXd& input_std) {
  LearningConfig config;
  config.learner = kind;
  if (!opt.params.empty()) config.ssgpr = load_ssgpr_params(opt.params);
  const std::string source = opt.params.empty() ? std::string("SSGPR defaults") : opt.params;
  const double samples = static_cast<double>(data.x_train.rows()) * opt.epochs;
  if (config.ssgpr.fit_samples > 0 && samples < static_cast<double>(config.ssgpr.fit_samples)) {
    throw std::runtime_error(opt.train + ": " + std::to_string(data.x_train.rows()) + " rows × " + std::to_string(opt.epochs) +
                             " epochs are fewer than fit_samples = " + std::to_string(config.ssgpr.fit_samples) + " (" +
                             source + "): the hyperparameters would never be fitted");
  }
  const Eigen::VectorXd scale = (input_std.array() > 0.0).select(input_std, 1.0);
  try {
    return make_learner(config, data.n_in, data.n_out, scale);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(source + ": " + error.what());
  }
}

// The learner --learner names, with the parameters of --params.
std::unique_ptr<Learner> make_fit_learner(const FitOptions& opt, LearnerKind kind, const FitData& data) {
  const Eigen::VectorXd input_std = calc_column_std(data.x_train);
  if (kind != LearnerKind::lwpr) return make_ssgpr_learner(opt, kind, data, input_std);
  LwprDataScales scales{input_std, calc_column_std(data.y_train)};
  const lwpr::LwprParams params = opt.params.empty() ? lwpr::LwprParams{} : load_lwpr_params(opt.params, data.n_in, scales);
  return std::make_unique<lwpr::LwprModel>(data.n_in, data.n_out, params);
}

// Wall and thread CPU seconds of one phase.
struct PhaseTime {
  double wall = 0.0, cpu = 0.0;
};

// Presents the training rows --epochs times (shuffled each epoch with --shuffle), timed; the
// hyperparameter fit's seconds (SSGPR) are not update time.
PhaseTime train_learner(Learner& learner, const FitOptions& opt, const FitData& data) {
  std::vector<Eigen::Index> order(data.x_train.rows());
  std::iota(order.begin(), order.end(), 0);
  RandomStream rng(opt.shuffle >= 0 ? static_cast<std::uint64_t>(opt.shuffle) : 0u, "lwpr_fit.shuffle");
  Eigen::VectorXd x(data.n_in), y(data.n_out);
  PhaseTime time;
  for (int epoch = 0; epoch < opt.epochs; ++epoch) {
    if (opt.shuffle >= 0) rng.shuffle(order.begin(), order.end());
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = thread_cpu_seconds();
    for (Eigen::Index i : order) {
      x = data.x_train.row(i).transpose();
      y = data.y_train.row(i).transpose();
      learner.update(x, y);
    }
    time.wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    time.cpu += thread_cpu_seconds() - cpu_start;
  }
  time.wall = std::max(0.0, time.wall - learner.fit_seconds());
  time.cpu = std::max(0.0, time.cpu - learner.fit_seconds());
  return time;
}

// The learner's predictions of the test rows, timed, and how many were not trustworthy.
struct TestPredictions {
  Eigen::MatrixXd values;
  long long untrusted = 0;
  PhaseTime time;
};

TestPredictions predict_test_rows(const Learner& learner, const FitData& data) {
  auto workspace = learner.make_workspace();
  TestPredictions out;
  out.values.resize(data.x_test.rows(), data.n_out);
  Eigen::VectorXd x(data.n_in);
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  Prediction p;  // one for all rows, its vectors reused; values only: the fit reads no confidence
  for (Eigen::Index i = 0; i < data.x_test.rows(); ++i) {
    x = data.x_test.row(i).transpose();
    learner.predict_values_into(x, *workspace, p);
    out.values.row(i) = p.value.transpose();
    if (!p.trustworthy) ++out.untrusted;
  }
  out.time.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.time.cpu = thread_cpu_seconds() - cpu_start;
  return out;
}

// nMSE per output: mean squared error over the test outputs' variance (infinite for a constant output).
std::vector<double> calc_output_nmse(const Eigen::MatrixXd& predicted, const Eigen::MatrixXd& y_test) {
  std::vector<double> nmse(y_test.cols());
  for (Eigen::Index o = 0; o < y_test.cols(); ++o) {
    const double mse = (predicted.col(o) - y_test.col(o)).squaredNorm() / y_test.rows();
    const double mean = y_test.col(o).mean();
    const double variance = (y_test.col(o).array() - mean).square().sum() / y_test.rows();
    nmse[o] = variance > 0.0 ? mse / variance : std::numeric_limits<double>::infinity();
  }
  return nmse;
}

// What the fit reports, in either form.
struct FitReport {
  std::vector<double> nmse;
  double nmse_mean = 0.0;
  double us_update = 0.0, us_predict = 0.0, cpu_us_update = 0.0, cpu_us_predict = 0.0;
  double fit_seconds = 0.0;
  long long untrusted = 0;
};

FitReport make_fit_report(const Learner& learner, const FitOptions& opt, const FitData& data, const PhaseTime& training,
                          const TestPredictions& test) {
  FitReport report;
  report.nmse = calc_output_nmse(test.values, data.y_test);
  report.nmse_mean = std::accumulate(report.nmse.begin(), report.nmse.end(), 0.0) / data.n_out;
  const double updates = static_cast<double>(data.x_train.rows()) * opt.epochs;
  const double predictions = static_cast<double>(data.x_test.rows());
  report.us_update = 1e6 * training.wall / updates;
  report.us_predict = 1e6 * test.time.wall / predictions;
  report.cpu_us_update = 1e6 * training.cpu / updates;
  report.cpu_us_predict = 1e6 * test.time.cpu / predictions;
  report.fit_seconds = learner.fit_seconds();
  report.untrusted = test.untrusted;
  return report;
}

void print_fit_json(const Learner& learner, const FitOptions& opt, const FitData& data, const FitReport& report) {
  nlohmann::json out;
  out["learner"] = opt.learner;
  out["nmse"] = report.nmse;
  out["nmse_mean"] = report.nmse_mean;
  out["us_per_update"] = report.us_update;
  out["us_per_predict"] = report.us_predict;
  out["cpu_us_per_update"] = report.cpu_us_update;
  out["cpu_us_per_predict"] = report.cpu_us_predict;
  out["untrusted_predictions"] = report.untrusted;
  out["memory_bytes"] = learner.calc_memory_bytes();
  if (const lwpr::LwprModel* lwpr_model = find_lwpr_model(learner)) {
    out["n_rf"] = lwpr_model->size();
    std::vector<std::size_t> per_output;
    for (int o = 0; o < data.n_out; ++o) per_output.push_back(lwpr_model->field_count(o));
    out["n_rf_per_output"] = per_output;
    out["mean_projections"] = lwpr_model->calc_mean_projections();
  }
  if (const ssgpr::SsgprModel* ssgpr_model = find_ssgpr_model(learner)) {
    const ssgpr::SsgprParams& p = ssgpr_model->params();
    out["features"] = p.features;
    out["fit_seconds"] = report.fit_seconds;
    out["lengthscales"] = to_list(ssgpr::calc_expanded_vector(p.lengthscales, data.n_in));
    out["signal_variance"] = p.signal_variance;
    out["noise_variance"] = p.noise_variance;
    out["output_scale"] = to_list(ssgpr::calc_expanded_vector(p.output_scale, data.n_out));
  }
  std::cout << out.dump() << "\n";
}

void print_fit_text(const Learner& learner, const FitData& data, const FitReport& report) {
  const lwpr::LwprModel* lwpr_model = find_lwpr_model(learner);
  const ssgpr::SsgprModel* ssgpr_model = find_ssgpr_model(learner);
  for (int o = 0; o < data.n_out; ++o) {
    std::printf("output %-12s nMSE %.5f", data.header[data.n_in + o].c_str(), report.nmse[o]);
    if (lwpr_model) std::printf("  fields %zu", lwpr_model->field_count(o));
    std::printf("\n");
  }
  if (lwpr_model) {
    std::printf("overall: nMSE %.5f, %zu fields, %.2f projections per field", report.nmse_mean, lwpr_model->size(),
                lwpr_model->calc_mean_projections());
  } else {
    std::printf("overall: nMSE %.5f, %zu features", report.nmse_mean, learner.size());
    if (ssgpr_model) {
      std::printf(" (hyperparameters %s: signal variance %.4g, noise variance %.4g)",
                  report.fit_seconds > 0.0 ? "fitted" : "as given", ssgpr_model->params().signal_variance,
                  ssgpr_model->params().noise_variance);
    }
  }
  std::printf(", %.2f us/update, %.2f us/predict, %.1f kB", report.us_update, report.us_predict,
              static_cast<double>(learner.calc_memory_bytes()) / 1024.0);
  if (report.fit_seconds > 0.0) std::printf(", fit %.2f s", report.fit_seconds);
  if (report.untrusted > 0) std::printf(", %lld test points without a trustworthy prediction (predicted 0)", report.untrusted);
  std::printf("\n");
}

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
  const LearnerKind kind = parse_learner(opt.learner);  // refused before any file is read
  const FitData data = load_fit_data(opt);
  const std::unique_ptr<Learner> learner = make_fit_learner(opt, kind, data);
  const PhaseTime training = train_learner(*learner, opt, data);
  const TestPredictions test = predict_test_rows(*learner, data);
  const FitReport report = make_fit_report(*learner, opt, data, training, test);
  if (!opt.save.empty()) save_model(*learner, opt.save);
  if (opt.json) {
    print_fit_json(*learner, opt, data, report);
  } else {
    print_fit_text(*learner, data, report);
  }
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
