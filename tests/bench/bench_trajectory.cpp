// Trajectory build time (engine/README.md quotes these): the reaching trajectory of
// sweeps/thesis/reaching_online.json (minimum-jerk reaches of 100 points in the thesis's box,
// seed 0, dt = 0.01 s) on the LWR III, all seven joints and the 3-DOF arm of joints 1, 2, 4.
//  - BM_BuildReaching/<dof>/<reaches>: build_trajectory as a job calls it; counter
//    per_100_reaches (CPU time per 100 reaches).
//  - BM_EndEffectorKinematics/<dof>: one end-effector position and 3 × n Jacobian at random
//    states, the serial chain against ArmDynamics (Simbody) in the same run.
#include "engine/kinematics/serial_chain.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/physics/arm_simulation.hpp"
#include "engine/random/random_stream.hpp"
#include "engine/trajectory/trajectory.hpp"

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using namespace armfarm;

const ArmModel& lwr3() {
  static const ArmModel model = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf");
  return model;
}

std::vector<int> active_for(int dof) {
  if (dof == 3) return {0, 1, 3};  // joints 1, 2, 4 (1-based)
  return {};
}

void BM_BuildReaching(benchmark::State& state) {
  const int dof = static_cast<int>(state.range(0));
  const int reaches = static_cast<int>(state.range(1));
  ArmDynamics dynamics(lwr3(), active_for(dof));
  TrajectoryConfig config;
  config.kind = TrajectoryKind::reaching;
  config.reaching.reaches = reaches;
  for (auto _ : state) benchmark::DoNotOptimize(build_trajectory(config, dynamics, 0.01, 0));
  // CPU seconds per 100 reaches (printed as a time: "640ms").
  state.counters["per_100_reaches"] =
      benchmark::Counter(reaches / 100.0 * state.iterations(), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_BuildReaching)->Args({7, 30})->Args({3, 30})->Args({3, 1000})->Unit(benchmark::kMillisecond)->MinTime(2.0);

template <typename Call>
void run_random_states(benchmark::State& state, Call call) {
  RandomStream draws(1, "bench.kinematics.states");
  std::vector<Eigen::VectorXd> states(64, Eigen::VectorXd(state.range(0)));
  for (Eigen::VectorXd& q : states)
    for (Eigen::Index j = 0; j < q.size(); ++j) q[j] = draws.uniform(-1.0, 1.0);
  std::size_t k = 0;
  for (auto _ : state) {
    call(states[k]);
    k = (k + 1) % states.size();
  }
}

void BM_EndEffectorKinematicsSimbody(benchmark::State& state) {
  ArmDynamics dynamics(lwr3(), active_for(static_cast<int>(state.range(0))));
  run_random_states(state, [&](const Eigen::VectorXd& q) {
    benchmark::DoNotOptimize(dynamics.calc_end_effector_position(q));
    benchmark::DoNotOptimize(dynamics.calc_end_effector_jacobian(q));
  });
}
BENCHMARK(BM_EndEffectorKinematicsSimbody)->Arg(7)->Arg(3)->Unit(benchmark::kMicrosecond);

void BM_EndEffectorKinematicsChain(benchmark::State& state) {
  ArmDynamics dynamics(lwr3(), active_for(static_cast<int>(state.range(0))));
  const SerialChain chain = make_end_effector_chain(dynamics);
  Eigen::Vector3d position;
  Eigen::Matrix3Xd jacobian(3, chain.dof());
  run_random_states(state, [&](const Eigen::VectorXd& q) {
    chain.calc_position_and_jacobian(q, position, jacobian);
    benchmark::DoNotOptimize(position);
    benchmark::DoNotOptimize(jacobian.data());
  });
}
BENCHMARK(BM_EndEffectorKinematicsChain)->Arg(7)->Arg(3)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
