// End-to-end job speed per job kind (engine/README.md, "Speed", quotes these): run_experiment on
// the LWR III, 3 DOF (joints 1, 2, 4) and 7 DOF, with the fixed-step runge_kutta_4 (integrator 7)
// and the adaptive runge_kutta_merson (integrator 0) restarted every tick, in one run.
//  - BM_Job/<kind>/<dof>/<integrator>: kind 0 = sine batch (the default 20 s sine, 2 collection
//    repeats, 5 epochs, evaluation), 1 = figure-eight batch (3 loops of 750 points, 7 DOF only), 2 = reaching
//    online (30 minimum-jerk reaches of 100 points, sweeps/thesis/reaching_online.json's base).
//    Every job has the held-out evaluation on (its default). Counters: sim_s_per_cpu_s
//    (simulated_seconds over all passes per CPU second of the job, trajectory build included),
//    and the shares of an evaluation tick (tick_us_* over tick_us_total) with tick_us_total.
//  - BM_Reaching1000: the thesis's 1000-reach 3-DOF online job (reaching_online.json's first
//    job, gain scale 0.2, seed 0, with active_joints [1, 2, 4] and 1000 reaches) at init_D 0.05
//    (the jobs' default) and at init_D 2 (the 20 s goal); counters wall_s and cpu_s of
//    the one job.
// After the table the program prints issue 26's two job figures against their goals, in words
// (JobFigures below): the 30-reach 7-DOF online job's real-time factor (BM_Job/2/7/7) and the
// 1000-reach 3-DOF job's seconds at init_D 2 (BM_Reaching1000/integrator:7/init_D_x100:200);
// "not run" when a --benchmark_filter left one out.
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/model/model_loading.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <ctime>

#include <chrono>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace armfarm;

const ArmModel& lwr3() {
  static const ArmModel model = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf");
  return model;
}

double cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

JobConfig make_job(int kind, int dof, int integrator) {
  JobConfig config;
  if (dof == 3) config.active_joints = {1, 2, 4};
  config.simulation.integrator = static_cast<IntegratorKind>(integrator);
  switch (kind) {
    case 0:
      config.trajectory.kind = TrajectoryKind::sine;
      config.learning.mode = LearningMode::batch;
      break;
    case 1:
      config.trajectory.kind = TrajectoryKind::figure_eight;
      config.learning.mode = LearningMode::batch;
      break;
    default:
      config.trajectory.kind = TrajectoryKind::reaching;
      config.trajectory.reaching.reaches = 30;
      config.learning.mode = LearningMode::online;
      config.recording.series = {"TRIAL", "RF"};
      config.recording.every = 10;
      break;
  }
  return config;
}

/// What the summary lines print: filled by the two benchmarks the goals are about, when they run.
struct JobFigures {
  bool reaching7_ran = false;
  double reaching7_sim_s = 0.0, reaching7_cpu_s = 0.0, reaching7_wall_s = 0.0;  // the median run's
  std::vector<double> reaching7_factors;  // simulated s per CPU s of every run, ascending
  bool reaching1000_ran = false;
  double reaching1000_cpu_s = 0.0, reaching1000_wall_s = 0.0, reaching1000_fields = 0.0;
};
JobFigures& job_figures() {
  static JobFigures figures;
  return figures;
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The goal lines of issue 26 ("Jobs"), after Google Benchmark's table.
void print_job_figures(const JobFigures& figures) {
  std::printf("\nissue 26 job figures (goals: the 30-reach 7-DOF online job at >= 100x real time, the 1000-reach 3-DOF job at init_D 2 in <= 20 s):\n");
  if (figures.reaching7_ran) {
    const double cpu_factor = figures.reaching7_sim_s / figures.reaching7_cpu_s;
    const double wall_factor = figures.reaching7_sim_s / figures.reaching7_wall_s;
    const std::vector<double>& runs = figures.reaching7_factors;
    std::printf("  30-reach 7-DOF online job (BM_Job/2/7/7, the median of %zu runs): %.1fx real time per CPU second (%.1fx per wall second; %.1f simulated s in %.3f CPU s), goal >= 100x: %s\n",
                runs.size(), cpu_factor, wall_factor, figures.reaching7_sim_s, figures.reaching7_cpu_s, cpu_factor >= 100.0 ? "met" : "not met");
    std::printf("    every run, ascending:");
    for (double factor : runs) std::printf(" %.1fx", factor);
    std::printf("\n");
  } else {
    std::printf("  30-reach 7-DOF online job (BM_Job/2/7/7): not run (--benchmark_filter)\n");
  }
  if (figures.reaching1000_ran) {
    std::printf("  1000-reach 3-DOF online job at init_D 2 (BM_Reaching1000/integrator:7/init_D_x100:200): %.1f CPU s (%.1f wall s; %.0f receptive fields), goal <= 20 s: %s\n",
                figures.reaching1000_cpu_s, figures.reaching1000_wall_s, figures.reaching1000_fields,
                figures.reaching1000_cpu_s <= 20.0 ? "met" : "not met");
  } else {
    std::printf("  1000-reach 3-DOF online job at init_D 2 (BM_Reaching1000/integrator:7/init_D_x100:200): not run (--benchmark_filter)\n");
  }
}

std::map<std::string, double> job_metrics(const JobOutcome& outcome) {
  std::map<std::string, double> values;
  for (const Metric& metric : outcome.metrics) {
    if (!metric.joint && !metric.checkpoint && metric.value) values[metric.name] = *metric.value;
  }
  return values;
}

/// One job on the LWR III and the CPU and wall seconds it took (run_experiment's exceptions pass).
struct TimedJob {
  JobOutcome outcome;
  double cpu_s = 0.0, wall_s = 0.0;
};
TimedJob run_timed_job(const JobConfig& config) {
  const double wall_start = wall_seconds();
  const double start = cpu_seconds();
  TimedJob run;
  run.outcome = run_experiment(lwr3(), config);
  run.cpu_s = cpu_seconds() - start;
  run.wall_s = wall_seconds() - wall_start;
  return run;
}

void BM_Job(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const int dof = static_cast<int>(state.range(1));
  const int integrator = static_cast<int>(state.range(2));
  const JobConfig config = make_job(kind, dof, integrator);
  double simulated = 0.0, cpu = 0.0, wall = 0.0;
  std::map<std::string, double> metrics;
  for (auto _ : state) {
    TimedJob run;
    try {
      run = run_timed_job(config);
    } catch (const std::exception& error) {
      state.SkipWithError(error.what());
      return;
    }
    const JobOutcome& outcome = run.outcome;
    cpu += run.cpu_s;
    wall += run.wall_s;
    if (outcome.status != JobStatus::done) state.SkipWithError(outcome.message.c_str());
    metrics = job_metrics(outcome);
    simulated += metrics[metric_names::simulated_seconds];
  }
  state.counters["sim_s_per_cpu_s"] = simulated / cpu;
  if (!state.error_occurred() && kind == 2 && dof == 7 && integrator == static_cast<int>(IntegratorKind::runge_kutta_4)) {
    // The goal's figure: one run takes about half a second, and on a shared or virtual machine
    // one run's rate varied from 92x to 124x, so the goal line takes the median of kGoalRuns runs
    // (this one and more, outside the library's timing; the table keeps this run's counters).
    constexpr int kGoalRuns = 7;
    struct Run {
      double sim_s, cpu_s, wall_s;
    };
    std::vector<Run> runs = {{simulated, cpu, wall}};
    for (int extra = 1; extra < kGoalRuns; ++extra) {
      TimedJob run;
      try {
        run = run_timed_job(config);
      } catch (const std::exception&) {
        break;
      }
      if (run.outcome.status != JobStatus::done) break;
      runs.push_back({job_metrics(run.outcome)[metric_names::simulated_seconds], run.cpu_s, run.wall_s});
    }
    std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.sim_s / a.cpu_s < b.sim_s / b.cpu_s; });
    const Run& median = runs[runs.size() / 2];
    JobFigures& figures = job_figures();
    figures.reaching7_ran = true;
    figures.reaching7_sim_s = median.sim_s;
    figures.reaching7_cpu_s = median.cpu_s;
    figures.reaching7_wall_s = median.wall_s;
    figures.reaching7_factors.clear();
    for (const Run& run : runs) figures.reaching7_factors.push_back(run.sim_s / run.cpu_s);
  }
  const double total = metrics[metric_names::tick_us_total];
  state.counters["tick_us"] = total;
  namespace n = metric_names;
  for (const auto& [name, label] : std::map<std::string, std::string>{{n::tick_us_physics, "physics"},
                                                                     {n::tick_us_feed_forward, "ff"},
                                                                     {n::tick_us_control, "control"},
                                                                     {n::tick_us_true_dynamics, "true_id"},
                                                                     {n::tick_us_statistics, "stats"},
                                                                     {n::tick_us_learning, "learn"}}) {
    state.counters[label] = metrics[name] / total;
  }
  static const char* const kinds[] = {"sine batch", "figure-eight batch", "reaching online"};
  state.SetLabel(std::string(kinds[kind]) + ", " + std::to_string(dof) + " DOF, " +
                 (integrator == static_cast<int>(IntegratorKind::runge_kutta_4) ? "runge_kutta_4" : "runge_kutta_merson"));
}
void register_jobs(benchmark::internal::Benchmark* bench) {
  for (const int integrator : {static_cast<int>(IntegratorKind::runge_kutta_4), static_cast<int>(IntegratorKind::runge_kutta_merson)}) {
    // No 3-DOF figure-eight: the figure (constant x, in the y-z plane) is out of the 3-DOF arm's
    // reach at the default centre and at the centres tried; the thesis ran it on 7 DOF.
    for (const auto& [kind, dof] : {std::pair{0, 3}, {0, 7}, {1, 7}, {2, 3}, {2, 7}}) bench->Args({kind, dof, integrator});
  }
}
BENCHMARK(BM_Job)->Apply(register_jobs)->Unit(benchmark::kSecond)->Iterations(1);

void BM_Reaching1000(benchmark::State& state) {
  JobConfig config = make_job(2, 3, static_cast<int>(state.range(0)));
  config.trajectory.reaching.reaches = 1000;
  const double init_d = 0.01 * static_cast<double>(state.range(1));
  config.learning.lwpr.init_D = Eigen::MatrixXd::Constant(1, 1, init_d);
  config.control.gain_scale = 0.2;
  double wall = 0.0, cpu = 0.0;
  for (auto _ : state) {
    const TimedJob run = run_timed_job(config);
    const JobOutcome& outcome = run.outcome;
    cpu += run.cpu_s;
    wall += run.wall_s;
    if (outcome.status != JobStatus::done) state.SkipWithError(outcome.message.c_str());
    const auto metrics = job_metrics(outcome);
    state.counters["fields"] = metrics.count(metric_names::n_receptive_fields) ? metrics.at(metric_names::n_receptive_fields) : 0.0;
    state.counters["tick_us"] = metrics.at(metric_names::tick_us_total);
    state.counters["learn_share"] = metrics.at(metric_names::tick_us_learning) / metrics.at(metric_names::tick_us_total);
    state.counters["ff_share"] = metrics.at(metric_names::tick_us_feed_forward) / metrics.at(metric_names::tick_us_total);
    state.counters["physics_share"] = metrics.at(metric_names::tick_us_physics) / metrics.at(metric_names::tick_us_total);
  }
  state.counters["wall_s"] = wall;
  state.counters["cpu_s"] = cpu;
  if (!state.error_occurred() && state.range(0) == static_cast<int>(IntegratorKind::runge_kutta_4) && state.range(1) == 200) {
    job_figures().reaching1000_ran = true;
    job_figures().reaching1000_cpu_s = cpu;
    job_figures().reaching1000_wall_s = wall;
    job_figures().reaching1000_fields = state.counters["fields"];
  }
}
BENCHMARK(BM_Reaching1000)->ArgNames({"integrator", "init_D_x100"})->Args({static_cast<int>(IntegratorKind::runge_kutta_4), 5})->Args({static_cast<int>(IntegratorKind::runge_kutta_4), 200})->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_job_figures(job_figures());
  return 0;
}
