// `make bench` figures for bounded expansion (issue 16): the time of expanding 10^5 jobs (two
// grid axes of 1000 and 100 values; the goal is under 5 s) and the memory a sweep keeps per
// expanded job (goal: under 2 KB), for the fake job kind and the experiment job (whose check
// parses each configuration against the LWR model). Counters: jobs, jobs_per_s and us_per_job
// (process CPU time, since the machine is shared; wall_s beside it), bytes_per_job (glibc's
// in-use heap, mallinfo2, after expansion minus before, over the job count).
#include "support/fake_job.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <benchmark/benchmark.h>

#include <malloc.h>

#include <chrono>
#include <ctime>
#include <string>

namespace armfarm {
namespace {

// A grid over two real-valued keys with `a` × `b` values.
std::string make_grid(const std::string& first, int a, const std::string& second, int b) {
  auto list = [](int n, double start, double step) {
    std::string text;
    for (int i = 0; i < n; ++i) text += (i ? "," : "") + std::to_string(start + step * i);
    return text;
  };
  return R"({"name": "bench", "sweep": {"grid": {")" + first + "\": [" + list(a, 0.5, 0.001) + "], \"" + second + "\": [" +
         list(b, 1.0, 0.01) + "]}}}";
}

std::size_t heap_in_use() { return mallinfo2().uordblks; }

double cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

void run_expansion(benchmark::State& state, const JobConfigSchema& schema, const std::string& text) {
  ExpansionLimits limits;
  limits.max_jobs = 1000000;
  double bytes_per_job = 0.0, seconds = 0.0, wall = 0.0;
  std::size_t jobs = 0;
  for (auto _ : state) {
    const std::size_t before = heap_in_use();
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_seconds();
    ExpandedSweep sweep = expand_sweep(parse_sweep_spec(text, "bench.json", ".", schema), schema, limits);
    seconds = cpu_seconds() - cpu_start;
    wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::size_t after = heap_in_use();
    jobs = sweep.jobs.size();
    bytes_per_job = (static_cast<double>(after) - static_cast<double>(before)) / static_cast<double>(jobs);
    benchmark::DoNotOptimize(sweep.jobs.data());
  }
  state.counters["jobs"] = static_cast<double>(jobs);
  state.counters["bytes_per_job"] = bytes_per_job;
  state.counters["us_per_job"] = seconds * 1e6 / static_cast<double>(jobs);
  state.counters["jobs_per_s"] = static_cast<double>(jobs) / seconds;
  state.counters["cpu_s"] = seconds;
  state.counters["wall_s"] = wall;
}

void BM_Expand100kFakeJobs(benchmark::State& state) {
  run_expansion(state, make_fake_job_config_schema(), make_grid("control.gain_scale", 1000, "trajectory.period", 100));
}
BENCHMARK(BM_Expand100kFakeJobs)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_Expand100kExperimentJobs(benchmark::State& state) {
  run_expansion(state, make_experiment_config_schema(),
                make_grid("control.gain_scale", 1000, "learning.lwpr.init_alpha", 100));
}
BENCHMARK(BM_Expand100kExperimentJobs)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace armfarm

BENCHMARK_MAIN();
