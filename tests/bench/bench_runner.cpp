// `make bench` figures for the farm: speed-up of -j2 over -j1 on 16 CPU-bound fake jobs, the
// runner + store overhead per job (fake jobs that do nothing), and database bytes per recorded
// series against raw float64 bytes.
#include "results/results_store.hpp"
#include "support/fake_job.hpp"
#include "runner/execution/sweep_runner.hpp"
#include "runner/spec/sweep_expansion.hpp"

#include <benchmark/benchmark.h>

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

ExpandedSweep expand_text(const std::string& text) {
  const JobConfigSchema schema = make_fake_job_config_schema();
  return expand_sweep(parse_sweep_spec(text, "bench.json", ".", schema), schema);
}

std::string temp_db(const std::string& name) {
  const fs::path path = fs::temp_directory_path() / ("armfarm_bench_" + std::to_string(::getpid()) + "_" + name);
  for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(path.string() + suffix);
  return path.string();
}

// 16 jobs of ~0.1 s of CPU each; wall time per sweep.
void BM_Sweep16CpuJobs(benchmark::State& state) {
  const ExpandedSweep sweep = expand_text(R"({"name": "cpu", "base": {"fake": {"sleep_ms": 0, "work": 4000000}},
      "sweep": {"repeat": 16}})");
  const std::atomic<bool> no_stop{false};
  for (auto _ : state) {
    RunOptions options;
    options.db_path = temp_db("cpu.db");
    options.threads = static_cast<int>(state.range(0));
    const RunSummary summary = run_sweep(sweep, make_fake_job_executor(), options, no_stop);
    if (summary.done != 16) state.SkipWithError("jobs failed");
  }
  state.SetLabel("-j" + std::to_string(state.range(0)));
}
BENCHMARK(BM_Sweep16CpuJobs)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Jobs that do nothing but return 3 metrics and two 200 × 3 series: the cost of the runner,
// the writer thread and SQLite per job.
void BM_OverheadPerJob(benchmark::State& state) {
  const ExpandedSweep sweep = expand_text(R"({"name": "empty", "base": {"fake": {"sleep_ms": 0}},
      "sweep": {"repeat": 500}})");
  const std::atomic<bool> no_stop{false};
  for (auto _ : state) {
    RunOptions options;
    options.db_path = temp_db("empty.db");
    options.threads = 1;
    run_sweep(sweep, make_fake_job_executor(), options, no_stop);
  }
  state.SetItemsProcessed(state.iterations() * 500);
}
BENCHMARK(BM_OverheadPerJob)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Database bytes per stored series of 2 000 samples × 8 columns (time + 7 smooth joint signals
// with small noise, like a recorded trajectory), against the raw float64 bytes.
void BM_SeriesStorage(benchmark::State& state) {
  const long samples = 2000, columns = 8;
  const int jobs = 50;
  double ratio = 0.0;
  for (auto _ : state) {
    const std::string db = temp_db("series.db");
    {
      ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_write);
      std::vector<JobRegistration> registrations;
      for (int j = 0; j < jobs; ++j) registrations.push_back({"k" + std::to_string(j), {}, {}, j});
      SweepRegistration sweep;
      sweep.name = "series";
      sweep.spec_text = "{}";
      sweep.spec_hash = "h";
      sweep.started_at = make_utc_timestamp();
      store.insert_sweep_run(sweep, registrations);
      JobBatch batch;
      for (int j = 0; j < jobs; ++j) {
        JobResultRecord result;
        result.key = "k" + std::to_string(j);
        result.status = "done";
        Eigen::MatrixXd rows(samples, columns);
        unsigned long long noise = 12345 + j;
        for (long i = 0; i < samples; ++i) {
          rows(i, 0) = 0.01 * i;
          for (long c = 1; c < columns; ++c) {
            noise = noise * 6364136223846793005ULL + 1442695040888963407ULL;
            rows(i, c) = std::sin(0.01 * i * c + j) + 1e-6 * static_cast<double>(noise >> 40) / 16777216.0;
          }
        }
        result.series.push_back({0, "POS", {"t", "q1", "q2", "q3", "q4", "q5", "q6", "q7"}, rows});
        batch.finished.push_back(std::move(result));
      }
      store.insert_job_batch(batch, "series");
    }
    for (const char* suffix : {"-wal", "-shm"}) {
      if (fs::exists(db + suffix) && fs::file_size(db + suffix) > 0) {
        ResultsStore::open(db, ResultsStore::Mode::read_write);  // closing the last connection checkpoints
      }
    }
    const double raw = static_cast<double>(jobs * samples * columns * 8);
    ratio = static_cast<double>(fs::file_size(db)) / raw;
  }
  state.counters["db_bytes_per_raw_byte"] = ratio;
  state.counters["raw_bytes_per_series"] = samples * columns * 8;
}
BENCHMARK(BM_SeriesStorage)->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace armfarm

BENCHMARK_MAIN();
