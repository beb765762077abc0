// LWPR speed: the 2-D cross function (published setting) and a robot-like 21 → 7 stream
// (7 joint angles, velocities, accelerations → 7 torques of a smooth synthetic inverse-dynamics
// function, sinusoidal joint trajectories, inputs normalised by their standard deviations,
// the operating points init_D ∈ {0.05, 0.5, 2, 5}·I, each with and without distance-metric
// adaptation). Reports µs per update and per prediction, fields and test nMSE. Run with
// --benchmark_repetitions=N for medians (the stream is the same each repetition). Times are the
// thread's CPU time (clock_gettime(CLOCK_THREAD_CPUTIME_ID)), not wall time.
#include "engine/lwpr/lwpr_model.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include <time.h>

namespace {

// CPU time of the calling thread in seconds: the machine is shared with other builds, and wall
// time would count the time the scheduler gives them.
double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

using armfarm::Prediction;
using armfarm::lwpr::LwprModel;
using armfarm::lwpr::LwprParams;

struct Dataset {
  std::vector<Eigen::VectorXd> x, y;
};

double calc_nmse(const LwprModel& model, const Dataset& test, double& us_per_predict) {
  auto workspace = model.make_workspace();
  const int n_out = static_cast<int>(test.y[0].size());
  Eigen::VectorXd error = Eigen::VectorXd::Zero(n_out), sum = error, sum2 = error;
  std::vector<Eigen::VectorXd> predicted;
  predicted.reserve(test.x.size());
  const double start = thread_seconds();
  for (const auto& x : test.x) predicted.push_back(model.predict(x, *workspace).value);
  us_per_predict = 1e6 * (thread_seconds() - start) / static_cast<double>(test.x.size());
  for (std::size_t i = 0; i < test.x.size(); ++i) {
    error += (predicted[i] - test.y[i]).cwiseAbs2();
    sum += test.y[i];
    sum2 += test.y[i].cwiseAbs2();
  }
  const double n = static_cast<double>(test.x.size());
  const Eigen::VectorXd variance = sum2 / n - (sum / n).cwiseAbs2();
  return (error / n).cwiseQuotient(variance).mean();
}

double cross(double a, double b) {
  return std::max({std::exp(-10 * a * a), std::exp(-50 * b * b), 1.25 * std::exp(-5 * (a * a + b * b))});
}

void BM_LwprCross2D(benchmark::State& state) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.1);
  Dataset train, test;
  for (int i = 0; i < 500; ++i) {
    const double a = uniform(rng), b = uniform(rng);
    train.x.push_back(Eigen::Vector2d(a, b));
    train.y.push_back(Eigen::VectorXd::Constant(1, cross(a, b) + noise(rng)));
  }
  for (int i = 0; i < 41; ++i) {
    for (int j = 0; j < 41; ++j) {
      test.x.push_back(Eigen::Vector2d(-1 + 0.05 * i, -1 + 0.05 * j));
      test.y.push_back(Eigen::VectorXd::Constant(1, cross(-1 + 0.05 * i, -1 + 0.05 * j)));
    }
  }
  LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 25.0);
  params.init_alpha = 250.0;
  params.w_gen = 0.2;
  params.diag_only = false;
  params.meta = true;
  for (auto _ : state) {
    LwprModel model(2, 1, params);
    std::vector<int> order(500);
    std::iota(order.begin(), order.end(), 0);
    const double start = thread_seconds();
    for (int epoch = 0; epoch < 20; ++epoch) {
      std::shuffle(order.begin(), order.end(), rng);
      for (int i : order) model.update(train.x[i], train.y[i]);
    }
    const double seconds = thread_seconds() - start;
    state.SetIterationTime(seconds);
    double us_predict = 0.0;
    state.counters["nmse"] = calc_nmse(model, test, us_predict);
    state.counters["fields"] = static_cast<double>(model.size());
    state.counters["us_per_update"] = 1e6 * seconds / 10000.0;
    state.counters["us_per_predict"] = us_predict;
  }
}
BENCHMARK(BM_LwprCross2D)->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);

// A smooth stand-in for a 7-joint arm's inverse dynamics: inertia coupling through cos(q_i − q_j),
// velocity products, gravity-like sin terms.
Eigen::VectorXd calc_torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
  Eigen::VectorXd tau(7);
  for (int i = 0; i < 7; ++i) {
    double t = 0.0;
    for (int j = 0; j < 7; ++j) {
      const double m = (i == j ? 1.5 : 0.4) / (1.0 + std::abs(i - j)) * (1.0 + 0.3 * std::cos(q(i) - q(j)));
      t += m * qdd(j) + 0.2 / (1.0 + i + j) * std::sin(q(i) + q(j)) * qd(i) * qd(j);
    }
    t += (7.0 - i) * std::sin(q(i) + 0.5 * (i + 1 < 7 ? q(i + 1) : 0.0)) + 0.1 * qd(i);
    tau(i) = t;
  }
  return tau;
}

Dataset make_robot_stream(int samples, double t0, std::mt19937_64& rng) {
  // A repeated task: each joint sums two harmonics of a 10 s period, and the amplitudes drift
  // slowly (97 s period), so the data lie near a 2-D surface in the 21-D input space, as
  // recorded arm motions do.
  std::uniform_real_distribution<double> amplitude(0.3, 0.9), phase(0.0, 6.28);
  std::uniform_int_distribution<int> harmonic(1, 3);
  std::vector<std::array<double, 6>> joint(7);
  std::mt19937_64 fixed(42);  // the same trajectory family for training and test
  for (auto& j : joint) {
    j = {amplitude(fixed), 0.1 * harmonic(fixed), phase(fixed), 0.5 * amplitude(fixed), 0.1 * (3 + harmonic(fixed)),
         phase(fixed)};
  }
  std::normal_distribution<double> noise(0.0, 0.01);
  Dataset data;
  const double dt = 0.01;
  for (int k = 0; k < samples; ++k) {
    const double t = t0 + k * dt;
    const double drift = 1.0 + 0.2 * std::sin(2 * M_PI * t / 97.0);  // slow: its derivatives are negligible
    Eigen::VectorXd q(7), qd(7), qdd(7);
    for (int i = 0; i < 7; ++i) {
      std::array<double, 6> j = joint[i];
      j[0] *= drift;
      const double w1 = 2 * M_PI * j[1], w2 = 2 * M_PI * j[4];
      q(i) = j[0] * std::sin(w1 * t + j[2]) + j[3] * std::sin(w2 * t + j[5]);
      qd(i) = j[0] * w1 * std::cos(w1 * t + j[2]) + j[3] * w2 * std::cos(w2 * t + j[5]);
      qdd(i) = -j[0] * w1 * w1 * std::sin(w1 * t + j[2]) - j[3] * w2 * w2 * std::sin(w2 * t + j[5]);
    }
    Eigen::VectorXd x(21);
    x << q, qd, qdd;
    Eigen::VectorXd tau = calc_torque(q, qd, qdd);
    for (int i = 0; i < 7; ++i) tau(i) += noise(rng);
    data.x.push_back(x);
    data.y.push_back(tau);
  }
  return data;
}

// One operating point of the robot stream: init_D = (state.range(0)/100)·I, distance-metric
// adaptation on (range(1) = 1) or off. 30 000 training samples in time order (one pass, online),
// 3 000 test samples from a later stretch of the same task. Counters: test nMSE (mean over the 7
// outputs), fields per output, mean projections per field, the share of test outputs without a
// trustworthy field (those predict 0), µs per update and per predict.
void BM_LwprRobot21to7(benchmark::State& state) {
  std::mt19937_64 rng(2);
  const Dataset train = make_robot_stream(30000, 0.0, rng);
  const Dataset test = make_robot_stream(3000, 1000.0, rng);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(21), sum2 = sum;
  for (const auto& x : train.x) {
    sum += x;
    sum2 += x.cwiseAbs2();
  }
  const double n = static_cast<double>(train.x.size());
  LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, static_cast<double>(state.range(0)) / 100.0);
  params.update_D = state.range(1) != 0;
  params.norm_in = (sum2 / n - (sum / n).cwiseAbs2()).cwiseSqrt();
  for (auto _ : state) {
    LwprModel model(21, 7, params);
    const double start = thread_seconds();
    for (std::size_t i = 0; i < train.x.size(); ++i) model.update(train.x[i], train.y[i]);
    const double seconds = thread_seconds() - start;
    state.SetIterationTime(seconds);
    double us_predict = 0.0;
    state.counters["nmse"] = calc_nmse(model, test, us_predict);
    state.counters["fields"] = static_cast<double>(model.size());
    state.counters["projections"] = model.calc_mean_projections();
    state.counters["us_per_update"] = 1e6 * seconds / n;
    state.counters["us_per_predict"] = us_predict;
    auto workspace = model.make_workspace();
    std::size_t untrusted = 0;
    for (const auto& x : test.x) {
      const Prediction p = model.predict(x, *workspace);
      for (bool trusted : p.output_trusted) untrusted += trusted ? 0 : 1;
    }
    state.counters["untrusted"] = static_cast<double>(untrusted) / (7.0 * static_cast<double>(test.x.size()));
  }
}
BENCHMARK(BM_LwprRobot21to7)
    ->ArgNames({"init_D_x100", "update_D"})
    ->ArgsProduct({{5, 50, 200, 500}, {0, 1}})
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
