// Physics speed and integrator accuracy of the 7-DOF LWR III (engine/README.md quotes these).
//  - BM_PdSimulation/<integrator>: sample-and-hold PD + exact inverse-dynamics feed-forward at dt = 0.01 s on
//    a 0.3 rad, 0.25 Hz sine about the start posture; counter sim_s_per_cpu_s (runge_kutta_4 = 7, runge_kutta_merson = 0).
//  - BM_InverseDynamics / BM_Jacobian / BM_MassMatrix: one call each at random states.
//  - BM_IntegratorAccuracy/<kind>/<-log10 accuracy>: the same PD run over 10 s; counters
//    final_error_rad (max joint-angle difference from a reference run at accuracy 1e-10 with
//    Runge–Kutta–Merson) and steps_per_tick.
#include "engine/model/model_loading.hpp"
#include "engine/physics/arm_simulation.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

namespace {

using namespace armfarm;

const ArmModel& lwr3() {
  static const ArmModel model = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf");
  return model;
}

// Runs the PD job for `seconds`; returns the final joint angles (every tick's in `angles` when set).
Eigen::VectorXd run_pd(const ArmSimulationOptions& options, double seconds, long* steps, Eigen::MatrixXd* angles = nullptr) {
  ArmSimulation plant(lwr3(), options);
  ArmDynamics dynamics(lwr3());
  const Eigen::VectorXd start = dynamics.start_positions();
  const Eigen::VectorXd inertia = dynamics.calc_mass_matrix(start).diagonal();
  const Eigen::VectorXd kp = inertia * 400.0, kd = inertia * 40.0;  // 20 rad/s, critically damped
  plant.set_state(0.0, start, Eigen::VectorXd::Zero(7));
  const double dt = 0.01, w = 2.0 * M_PI * 0.25;
  const int ticks = static_cast<int>(std::lround(seconds / dt));
  if (angles) angles->resize(ticks, 7);
  for (int k = 0; k < ticks; ++k) {
    const double t = k * dt;
    const Eigen::VectorXd q_d = start.array() + 0.3 * std::sin(w * t);
    const Eigen::VectorXd qd_d = Eigen::VectorXd::Constant(7, 0.3 * w * std::cos(w * t));
    const Eigen::VectorXd qdd_d = Eigen::VectorXd::Constant(7, -0.3 * w * w * std::sin(w * t));
    const Eigen::VectorXd tau = kp.cwiseProduct(q_d - plant.q()) + kd.cwiseProduct(qd_d - plant.qd()) +
                                dynamics.calc_inverse_dynamics(q_d, qd_d, qdd_d);
    plant.step(tau, dt);
    if (angles) angles->row(k) = plant.q().transpose();
  }
  if (steps) *steps = plant.integrator_steps();
  return plant.q();
}

void BM_PdSimulation(benchmark::State& state) {
  const double seconds = 5.0;
  ArmSimulationOptions options;
  options.integrator = static_cast<IntegratorKind>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(run_pd(options, seconds, nullptr));
  state.counters["sim_s_per_cpu_s"] = benchmark::Counter(seconds * state.iterations(), benchmark::Counter::kIsRate);
  state.SetLabel(options.integrator == IntegratorKind::runge_kutta_4 ? "runge_kutta_4" : "runge_kutta_merson");
}
BENCHMARK(BM_PdSimulation)
    ->Arg(static_cast<int>(IntegratorKind::runge_kutta_4))
    ->Arg(static_cast<int>(IntegratorKind::runge_kutta_merson))
    ->Unit(benchmark::kMillisecond);

template <typename Call>
void run_random_states(benchmark::State& state, Call call) {
  ArmDynamics dynamics(lwr3());
  std::mt19937_64 generator(1);
  std::uniform_real_distribution<double> angle(-1.0, 1.0);
  std::vector<Eigen::VectorXd> states(64, Eigen::VectorXd(7));
  for (auto& q : states) for (int j = 0; j < 7; ++j) q[j] = angle(generator);
  std::size_t i = 0;
  for (auto _ : state) {
    call(dynamics, states[i % states.size()]);
    ++i;
  }
}

void BM_InverseDynamics(benchmark::State& state) {
  run_random_states(state, [](ArmDynamics& d, const Eigen::VectorXd& q) { benchmark::DoNotOptimize(d.calc_inverse_dynamics(q, q, q)); });
}
void BM_Jacobian(benchmark::State& state) {
  run_random_states(state, [](ArmDynamics& d, const Eigen::VectorXd& q) { benchmark::DoNotOptimize(d.calc_end_effector_jacobian(q)); });
}
void BM_MassMatrix(benchmark::State& state) {
  run_random_states(state, [](ArmDynamics& d, const Eigen::VectorXd& q) { benchmark::DoNotOptimize(d.calc_mass_matrix(q)); });
}
BENCHMARK(BM_InverseDynamics)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Jacobian)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MassMatrix)->Unit(benchmark::kMicrosecond);

void BM_IntegratorAccuracy(benchmark::State& state) {
  static const Eigen::VectorXd reference = [] {
    ArmSimulationOptions options;
    options.integrator = IntegratorKind::runge_kutta_merson;
    options.accuracy = 1e-10;
    return run_pd(options, 10.0, nullptr);
  }();
  ArmSimulationOptions options;
  options.integrator = static_cast<IntegratorKind>(state.range(0));
  options.accuracy = std::pow(10.0, -static_cast<double>(state.range(1)));
  long steps = 0;
  Eigen::VectorXd final_q;
  for (auto _ : state) final_q = run_pd(options, 10.0, &steps);
  state.counters["final_error_rad"] = (final_q - reference).cwiseAbs().maxCoeff();
  state.counters["steps_per_tick"] = static_cast<double>(steps) / 1000.0;
  state.SetLabel(std::vector<const char*>{"runge_kutta_merson", "runge_kutta_3", "runge_kutta_feldberg", "explicit_euler",
                                          "semi_explicit_euler2", "verlet", "cpodes"}[state.range(0)]);
}
BENCHMARK(BM_IntegratorAccuracy)
    ->ArgsProduct({{0, 1, 2, 4, 5, 6}, {3, 5, 7}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// The accuracy criterion of the default (engine/README.md): the largest joint-angle difference at
// any tick of the 10 s PD job from the reference (Runge–Kutta–Merson at accuracy 1e-10).
// BM_FixedStepAccuracy/<steps per tick>: runge_kutta_4; BM_AdaptiveAccuracy/<-log10 accuracy>:
// runge_kutta_merson as before. Counters max_error_rad, steps_per_tick.
const Eigen::MatrixXd& reference_angles() {
  static const Eigen::MatrixXd angles = [] {
    ArmSimulationOptions options;
    options.accuracy = 1e-10;
    options.integrator = IntegratorKind::runge_kutta_merson;
    Eigen::MatrixXd result;
    run_pd(options, 10.0, nullptr, &result);
    return result;
  }();
  return angles;
}

void report_accuracy(benchmark::State& state, const ArmSimulationOptions& options) {
  long steps = 0;
  Eigen::MatrixXd angles;
  for (auto _ : state) run_pd(options, 10.0, &steps, &angles);
  state.counters["max_error_rad"] = (angles - reference_angles()).cwiseAbs().maxCoeff();
  state.counters["steps_per_tick"] = static_cast<double>(steps) / 1000.0;
}

void BM_FixedStepAccuracy(benchmark::State& state) {
  ArmSimulationOptions options;
  options.integrator = IntegratorKind::runge_kutta_4;
  options.steps_per_tick = static_cast<int>(state.range(0));
  report_accuracy(state, options);
}
BENCHMARK(BM_FixedStepAccuracy)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_AdaptiveAccuracy(benchmark::State& state) {
  ArmSimulationOptions options;
  options.integrator = IntegratorKind::runge_kutta_merson;
  options.accuracy = std::pow(10.0, -static_cast<double>(state.range(0)));
  report_accuracy(state, options);
}
BENCHMARK(BM_AdaptiveAccuracy)->Arg(5)->Arg(7)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
