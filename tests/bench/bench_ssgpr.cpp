// I-SSGPR speed and accuracy on a robot-like 21 → 7 stream (7 joint angles, velocities and
// accelerations → 7 torques of a smooth synthetic inverse-dynamics function along slowly
// drifting multi-sine joint trajectories sampled at 100 Hz). Hyperparameters are fitted once by
// the GP marginal likelihood on 400 samples spread over the training stream, then for
// D = 100, 200, 500 the model learns 10 000 samples one by one and predicts 2 000 held-out
// samples from a later stretch of the same task. Reports µs per update and per prediction
// (mean and variance), held-out nMSE (mean over outputs of MSE / variance) and model memory.
#include "engine/random/random_stream.hpp"
#include "engine/ssgpr/ssgpr_fit.hpp"
#include "engine/ssgpr/ssgpr_model.hpp"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <vector>

namespace {

using armfarm::Prediction;
using armfarm::RandomStream;
using armfarm::ssgpr::SsgprModel;
using armfarm::ssgpr::SsgprParams;

struct Stream {
  std::vector<Eigen::VectorXd> x, y;
};

// Torques of a made-up 7-joint arm: a configuration-dependent inertia (coupling falls off with
// joint distance and varies with cos of the joint differences), Coriolis-like velocity
// products, gravity-like terms in the sums of the preceding angles, viscous friction.
Eigen::VectorXd calc_arm_torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
  Eigen::VectorXd tau(7);
  double angle_sum = 0.0;
  for (int i = 0; i < 7; ++i) {
    angle_sum += q(i);
    double t = 0.0;
    for (int j = 0; j < 7; ++j) {
      const double coupling = (i == j ? 1.2 : 0.5 / (1 + std::abs(i - j))) * (1.0 + 0.25 * std::cos(q(i) - q(j)));
      t += coupling * qdd(j) + 0.15 / (1 + i + j) * std::sin(q(j) - q(i)) * qd(i) * qd(j);
    }
    tau(i) = t + 0.9 * (7 - i) * std::cos(angle_sum) + 0.2 * qd(i);
  }
  return tau;
}

// Each joint: two sines (periods 2.5–10 s), amplitudes drifting by ±15 % over 120 s; the same
// trajectory family for every call, the noise (σ = 0.02 N·m) from `noise`.
Stream make_arm_stream(int samples, double t0, RandomStream& noise) {
  RandomStream shape(42, "bench.ssgpr.trajectory");
  double a1[7], f1[7], p1[7], a2[7], f2[7], p2[7];
  for (int i = 0; i < 7; ++i) {
    a1[i] = shape.uniform(0.4, 1.0);
    f1[i] = 0.1 * (1 + static_cast<int>(shape.uniform_index(2)));
    p1[i] = shape.uniform(0.0, 2 * M_PI);
    a2[i] = shape.uniform(0.1, 0.4);
    f2[i] = 0.1 * (3 + static_cast<int>(shape.uniform_index(2)));
    p2[i] = shape.uniform(0.0, 2 * M_PI);
  }
  Stream s;
  for (int k = 0; k < samples; ++k) {
    const double t = t0 + 0.01 * k;
    const double drift = 1.0 + 0.15 * std::sin(2 * M_PI * t / 120.0);
    Eigen::VectorXd q(7), qd(7), qdd(7);
    for (int i = 0; i < 7; ++i) {
      const double w1 = 2 * M_PI * f1[i], w2 = 2 * M_PI * f2[i], b1 = drift * a1[i];
      q(i) = b1 * std::sin(w1 * t + p1[i]) + a2[i] * std::sin(w2 * t + p2[i]);
      qd(i) = b1 * w1 * std::cos(w1 * t + p1[i]) + a2[i] * w2 * std::cos(w2 * t + p2[i]);
      qdd(i) = -b1 * w1 * w1 * std::sin(w1 * t + p1[i]) - a2[i] * w2 * w2 * std::sin(w2 * t + p2[i]);
    }
    Eigen::VectorXd x(21);
    x << q, qd, qdd;
    Eigen::VectorXd tau = calc_arm_torque(q, qd, qdd);
    for (int i = 0; i < 7; ++i) tau(i) += 0.02 * noise.normal();
    s.x.push_back(x);
    s.y.push_back(tau);
  }
  return s;
}

struct Data {
  Stream train, test;
  SsgprParams fitted;
  double fit_seconds = 0.0;
  double log_likelihood_start = 0.0, log_likelihood_end = 0.0;
};

const Data& get_data() {
  static const Data data = [] {
    Data d;
    RandomStream noise(2, "bench.ssgpr.noise");
    d.train = make_arm_stream(10000, 0.0, noise);
    d.test = make_arm_stream(2000, 1000.0, noise);
    const int batch = 400, stride = 10000 / batch;
    Eigen::MatrixXd X(batch, 21), Y(batch, 7);
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(21), sum2 = sum;
    for (int i = 0; i < batch; ++i) {
      X.row(i) = d.train.x[i * stride].transpose();
      Y.row(i) = d.train.y[i * stride].transpose();
      sum += d.train.x[i * stride];
      sum2 += d.train.x[i * stride].cwiseAbs2();
    }
    SsgprParams start;
    start.lengthscales = 2.0 * (sum2 / batch - (sum / batch).cwiseAbs2()).cwiseSqrt();  // 2 σ of each input
    start.noise_variance = 0.01;
    armfarm::ssgpr::SsgprFitReport report;
    const auto t = std::chrono::steady_clock::now();
    d.fitted = armfarm::ssgpr::calc_fitted_params(X, Y, start, armfarm::ssgpr::SsgprFitConfig{}, &report);
    d.fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    d.log_likelihood_start = report.log_likelihood_start;
    d.log_likelihood_end = report.log_likelihood_end;
    return d;
  }();
  return data;
}

void BM_SsgprRobot21to7(benchmark::State& state) {
  const Data& data = get_data();
  SsgprParams params = data.fitted;
  params.features = static_cast<int>(state.range(0));
  for (auto _ : state) {
    SsgprModel model(21, 7, params);
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < data.train.x.size(); ++i) model.update(data.train.x[i], data.train.y[i]);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(seconds);
    auto workspace = model.make_workspace();
    std::vector<Prediction> predicted;
    predicted.reserve(data.test.x.size());
    const auto p0 = std::chrono::steady_clock::now();
    for (const auto& x : data.test.x) predicted.push_back(model.predict(x, *workspace));
    const double predict_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
    Eigen::VectorXd error = Eigen::VectorXd::Zero(7), sum = error, sum2 = error;
    int trusted = 0;
    for (std::size_t i = 0; i < predicted.size(); ++i) {
      trusted += predicted[i].trustworthy ? 1 : 0;
      // The posterior mean whether or not trusted (an untrusted value is 0 by contract; counted apart).
      armfarm::ssgpr::SsgprPredictionDetail detail;
      model.predict(data.test.x[i], *workspace, detail);
      error += (detail.mean - data.test.y[i]).cwiseAbs2();
      sum += data.test.y[i];
      sum2 += data.test.y[i].cwiseAbs2();
    }
    const double n = static_cast<double>(predicted.size());
    const Eigen::VectorXd variance = sum2 / n - (sum / n).cwiseAbs2();
    state.counters["nmse"] = (error / n).cwiseQuotient(variance).mean();
    state.counters["trusted_fraction"] = trusted / n;
    state.counters["us_per_update"] = 1e6 * seconds / static_cast<double>(data.train.x.size());
    state.counters["us_per_predict"] = 1e6 * predict_seconds / n;
    state.counters["memory_kB"] = static_cast<double>(model.calc_memory_bytes()) / 1024.0;
    state.counters["fit_s"] = data.fit_seconds;
    state.counters["fit_loglik_gain"] = data.log_likelihood_end - data.log_likelihood_start;
  }
}
BENCHMARK(BM_SsgprRobot21to7)->Arg(100)->Arg(200)->Arg(500)->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
