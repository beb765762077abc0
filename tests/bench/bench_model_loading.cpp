// `make bench` figures for linear model loading (issue 30): the CPU time of loading a URDF chain
// and a DCG chain of 125, 250, 500 and 1000 links (the cap, kMaxModelLinks). Linear loading
// doubles us_per_load from one size to the next; the loaders before the fix grew faster (the
// tree check walked to the root from every link, each joint looked its links up by a linear
// search). Counters: us_per_load (process CPU time; the machine is shared), us_per_link.
#include "engine/model/model_loading.hpp"
#include "tests/support/big_models.hpp"

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>

namespace armfarm {
namespace {

double cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

void run_loading(benchmark::State& state, const std::string& extension) {
  const int links = static_cast<int>(state.range(0));
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("armfarm-bench-" + std::to_string(::getpid()) + "-chain." + extension)).string();
  // The URDF has links + 1 links (the base); the DCG's bodies are the links.
  std::ofstream(path) << (extension == "urdf" ? test_support::make_big_urdf(links - 1, false) : test_support::make_big_dcg(links));
  double seconds = 0.0;
  int loads = 0;
  for (auto _ : state) {
    const double start = cpu_seconds();
    const ArmModel model = load_arm_model(path);
    seconds += cpu_seconds() - start;
    ++loads;
    benchmark::DoNotOptimize(model.links.data());
  }
  std::filesystem::remove(path);
  state.counters["us_per_load"] = seconds * 1e6 / loads;
  state.counters["us_per_link"] = seconds * 1e6 / loads / links;
}

void BM_LoadUrdfChain(benchmark::State& state) { run_loading(state, "urdf"); }
BENCHMARK(BM_LoadUrdfChain)->Arg(125)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);

void BM_LoadDcgChain(benchmark::State& state) { run_loading(state, "dcg"); }
BENCHMARK(BM_LoadDcgChain)->Arg(125)->Arg(250)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace armfarm

BENCHMARK_MAIN();
