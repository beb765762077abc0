// `make bench` figures for searches (issue 25, "Benchmarks"): on the two problems at
// their shipped sizes, a dense full grid against the method and against random search, each
// search given 25 % of the grid's estimated CPU-seconds (calc_search_cpu_seconds, what
// `budget.cpu_seconds` counts), over 10 search seeds; median and spread of the best objective,
// and the measured CPU-seconds.
//   1. fig6_1_kernel_width (the base of sweeps/thesis/fig6_1_kernel_width.json as shipped: 53
//      collection passes): learning.lwpr.init_D × update_D, objective heldout_test_nmse of joint
//      2; the method TPE. The grid: 24 log-spaced init_D in [0.01, 3] (the shipped spec's 6 and
//      18 between) × update_D off/on, 48 jobs, so the budget buys 12 jobs (TPE's start-up by
//      the budget rule: 3). The shipped 6 × 2 grid leaves a budget of 3 jobs, below any start-up.
//   2. reaching (the base of sweeps/thesis/table6_5_7_heldout_reaching.json: sigmoid reaches of
//      100 points, 9 held-out transitions), 200 reaches: init_D × init_alpha ×
//      control.gain_scale, objective the mean heldout_test_nmse at 200; the method ASHA (η 3)
//      with the TPE sampler. The grid: 4 × 4 × 4 (init_D and init_alpha log-spaced, gain_scale
//      evenly), 64 jobs. Two layouts of rungs over the checkpoints 10/50/200: 10/200 (as
//      sweeps/search/reaching_asha.json ships it; BM_SearchReaching) and all three
//      (BM_SearchReachingAllCheckpoints).
//   1b. fig6_1_kernel_width with held-out checkpoints after 1 and 5 training epochs, searched by
//      ASHA (η 3, TPE sampler) over them (BM_SearchKernelWidthAsha).
// ARMFARM_BENCH_SEARCH_REDUCED=1 runs both problems reduced as the first version of this benchmark
// did (fig6_1: 4 collection passes, not 53; reaching: 40 points per reach, not 100, and 3
// held-out transitions, not 9), with the same grids and budgets: for a machine that cannot give
// the full problems their hours (say so beside the figures).
// ARMFARM_BENCH_SEARCH_FULL_NORMALISATION=1 normalises every reaching job by the full trajectory
// (apply_full_normalisation), so that ASHA's short rungs rank as the full jobs' checkpoints do.
// ARMFARM_BENCH_SEARCH_RUNGS=10,50,200 sets BM_SearchReaching's checkpoints (ASHA's rungs).
// ARMFARM_BENCH_SEARCH_SEEDS=N runs seeds 1 … N only (a stated subset, when time is short);
// --benchmark_filter=KernelWidth or =Reaching runs one problem (each with its variant). Each seed's line is printed as it
// finishes. Each search runs in a database of its own, so its measured CPU is its own jobs'.
// On a problem with checkpoints the grid is followed by the rung measurement (measure_rungs:
// Spearman's ρ of each rung against the last, in the grid's jobs and as short rung jobs);
// ARMFARM_BENCH_SEARCH_SEEDS=0 stops after it. ARMFARM_BENCH_SEARCH_FOLDER=DIR keeps the grids'
// databases and measured CPU in DIR for later runs.
// BM_SearchCostFactor measures the cost factor of calc_search_cpu_seconds (see there).
#include "analysis/search_summary.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "results/results_store.hpp"
#include "runner/config/job_config_json.hpp"
#include "runner/execution/job_kind.hpp"
#include "runner/execution/job_models.hpp"
#include "runner/execution/search_runner.hpp"
#include "runner/execution/sweep_runner.hpp"
#include "runner/spec/input_files.hpp"
#include "runner/spec/sweep_stages.hpp"

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

constexpr int kDefaultSeeds = 10;
constexpr double kBudgetFraction = 0.25;

bool is_reduced() {
  const char* text = std::getenv("ARMFARM_BENCH_SEARCH_REDUCED");
  return text != nullptr && std::string(text) == "1";
}

// ARMFARM_BENCH_SEARCH_SEEDS=0 runs the grids and the rung measurement only.
int seed_count() {
  const char* text = std::getenv("ARMFARM_BENCH_SEARCH_SEEDS");
  if (text != nullptr && std::string(text) == "0") return 0;
  const int n = text != nullptr ? std::atoi(text) : kDefaultSeeds;
  return n > 0 ? n : kDefaultSeeds;
}

// `count` values from low to high evenly in log (geometric), or evenly when `log` is false; four
// significant digits, so the grid reads as a user would write it.
nlohmann::json make_axis_values(double low, double high, int count, bool log) {
  nlohmann::json values = nlohmann::json::array();
  for (int i = 0; i < count; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(count - 1);
    const double value = log ? low * std::pow(high / low, t) : low + (high - low) * t;
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", value);
    values.push_back(std::strtod(text, nullptr));
  }
  return values;
}

double process_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// ARMFARM_BENCH_SEARCH_FOLDER=DIR keeps the grids' databases (and their measured CPU) in DIR, so
// a later run with other seeds or another method reuses them instead of running the grid again.
std::optional<fs::path> kept_folder() {
  const char* text = std::getenv("ARMFARM_BENCH_SEARCH_FOLDER");
  if (text == nullptr || *text == '\0') return std::nullopt;
  return fs::path(text);
}

fs::path scratch_folder() {
  const fs::path folder = kept_folder().value_or(fs::temp_directory_path() / ("armfarm_bench_search_" + std::to_string(::getpid())));
  fs::create_directories(folder);
  return folder;
}

void remove_scratch(const fs::path& folder) {
  if (!kept_folder()) fs::remove_all(folder);
}

// A grid's measured CPU, kept beside its database: runs that reuse the database report it.
double run_grid_once(const fs::path& folder, const std::string& name, const std::function<void()>& run) {
  const fs::path file = folder / (name + "_cpu.txt");
  if (fs::exists(file)) {
    std::ifstream in(file);
    double cpu = 0.0;
    in >> cpu;
    run();  // nothing left to run: every job is done in the kept database
    return cpu;
  }
  const double start = process_cpu_seconds();
  run();
  const double cpu = process_cpu_seconds() - start;
  std::ofstream(file) << cpu << "\n";
  return cpu;
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

struct Problem {
  std::string name;
  nlohmann::json base;
  nlohmann::json grid;       ///< sweep.grid
  nlohmann::json search;     ///< sweep.search without seed and budget
  std::string metric;
  std::optional<int> joint;  ///< empty: the mean row
  std::vector<std::int64_t> checkpoints;  ///< the rungs' checkpoints (empty: one rung)
  std::string length_path;                ///< the key a short rung job sets to its checkpoint
};

// The objective of a done job: the metric row of `joint` at its highest checkpoint.
std::optional<double> find_objective(const ResultsStore& store, const JobRecord& job, const Problem& problem) {
  std::optional<double> value;
  std::optional<std::int64_t> checkpoint;
  for (const MetricRecord& m : store.find_metrics(job.id)) {
    if (m.name != problem.metric || m.joint != problem.joint) continue;
    if (!value || (m.checkpoint && (!checkpoint || *m.checkpoint > *checkpoint))) {
      value = m.value;
      checkpoint = m.checkpoint;
    }
  }
  return value;
}

// The objective of a done job at `checkpoint`.
std::optional<double> find_objective_at(const ResultsStore& store, const JobRecord& job, const Problem& problem,
                                        std::int64_t checkpoint) {
  for (const MetricRecord& m : store.find_metrics(job.id)) {
    if (m.name == problem.metric && m.joint == problem.joint && m.checkpoint == checkpoint) return m.value;
  }
  return std::nullopt;
}

std::string write_spec(const fs::path& folder, const std::string& name, const nlohmann::json& spec) {
  const fs::path file = folder / (name + ".json");
  std::ofstream(file) << spec.dump(2);
  return file.string();
}

struct SearchOutcome {
  double best = std::numeric_limits<double>::infinity();
  double spent = 0.0;  ///< estimated, in the budget's unit
  double cpu = 0.0;    ///< measured
  std::size_t steps = 0;
};

struct Summary {
  double median = 0.0, low = 0.0, high = 0.0;
};

Summary summarise(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return {n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]), values.front(), values.back()};
}

// The best `count` of `values` (lower is better), as indices.
std::vector<std::size_t> best_indices(const std::vector<double>& values, std::size_t count) {
  std::vector<std::size_t> order(values.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  order.resize(std::min(count, order.size()));
  return order;
}

// The input scale a job with learning.normalize_inputs learns with (calc_trajectory_input_scale
// of its training trajectory, what run_experiment passes to make_learner), for a configuration
// with its inputs recorded (an expanded job's).
Eigen::VectorXd calc_job_input_scale(const nlohmann::json& recorded, JobModels& models) {
  const nlohmann::json* resolved = find_resolved_input(recorded, "model");
  const std::string path = (resolved != nullptr ? *resolved : recorded.at("model")).get<std::string>();
  const ValidJobConfig job = parse_recorded_job_config(recorded, *models.get_facts(path));
  return calc_trajectory_input_scale(build_job_trajectories(*models.get(path, job), job).training);
}

// The grid's full jobs' one input scale, as a JSON list (for learning.lwpr.norm_in), or null
// when the points' scales differ (an axis changes the training trajectory).
nlohmann::json find_common_input_scale(const ExpandedSweep& grid) {
  JobModels models;
  std::optional<Eigen::VectorXd> common;
  for (const ExpandedJob& job : grid.jobs) {
    const Eigen::VectorXd scale = calc_job_input_scale(job.config(), models);
    if (common && (common->size() != scale.size() || *common != scale)) return nullptr;
    common = scale;
  }
  if (!common) return nullptr;
  return std::vector<double>(common->data(), common->data() + common->size());
}

// The short jobs of rung k: the grid again with the rung's length and checkpoints (and `extra`
// merged into base); their objectives at the rung's checkpoint per grid point (`index`: params →
// point; +∞ where a job failed), their estimated and measured CPU.
struct ShortRungJobs {
  std::vector<double> values;
  std::size_t jobs = 0;
  double estimated = 0.0, cpu = 0.0;
};

ShortRungJobs run_short_rung(const Problem& problem, const fs::path& folder, const JobKind& kind, const RunOptions& options,
                             std::size_t k, const std::string& variant, const nlohmann::json& extra,
                             const std::map<std::string, std::size_t>& index, const std::atomic<bool>& no_stop) {
  const std::int64_t c = problem.checkpoints[k];
  nlohmann::json base = problem.base;
  base[nlohmann::json::json_pointer("/" + std::regex_replace(problem.length_path, std::regex("\\."), "/"))] = c;
  base["learning"]["heldout_checkpoints"] =
      std::vector<std::int64_t>(problem.checkpoints.begin(), problem.checkpoints.begin() + static_cast<std::ptrdiff_t>(k) + 1);
  base.merge_patch(extra);
  const std::string file = problem.name + "_rung" + std::to_string(k) + variant;
  const std::string name = problem.name + " rung " + std::to_string(k) + variant;
  const std::vector<SweepSpec> spec = load_sweep_stages(
      write_spec(folder, file, {{"name", name}, {"base", base}, {"sweep", {{"grid", problem.grid}}}}), kind.schema);
  const ExpandedSweep sweep = expand_sweep(spec.front(), kind.schema);
  ShortRungJobs out;
  out.jobs = sweep.jobs.size();
  for (const ExpandedJob& job : sweep.jobs) out.estimated += calc_search_cpu_seconds(kind, job.config());
  RunOptions one = options;
  one.db_path = (folder / (file + ".db")).string();
  out.cpu = run_grid_once(folder, file, [&] { run_sweep(sweep, kind.executor, one, no_stop); });
  out.values.assign(index.size(), std::numeric_limits<double>::infinity());
  const ResultsStore store = ResultsStore::open(one.db_path, ResultsStore::Mode::read_only);
  for (const JobRecord& job : store.find_jobs(name)) {
    const auto found = index.find(job.params.dump());
    const std::optional<double> v = job.status == "done" ? find_objective_at(store, job, problem, c) : std::nullopt;
    if (found != index.end() && v) out.values[found->second] = *v;
  }
  return out;
}

// How well each rung orders the grid's points as the last rung does: Spearman's ρ
// (calc_rank_correlation) between the objective at the rung and at the last checkpoint, over the
// grid's points, (a) at checkpoint c of the grid's own jobs, which run to the end, and (b) of the
// short job that a search step to that rung runs (length_path = c, the checkpoints up to c): a
// job of its own, which for online reaching normalises its inputs by its shorter trajectory, and
// (c) for an online job, the same short job normalised by the full job's trajectory instead
// (learning.normalize_inputs false, learning.lwpr.norm_in the full job's input scale,
// calc_job_input_scale): what a rung job that keeps the full job's normalisation would score.
// Also, of the last rung's best 1/η (η = 3) of the points, how many are among the rung's best
// 1/η (what a promotion keeps), and the rung rank of the last rung's best point. Prints the short
// jobs' estimated and measured CPU, what the budget counts for a rung.
void measure_rungs(const Problem& problem, const fs::path& folder, const JobKind& kind, const RunOptions& options,
                   const ExpandedSweep& grid, const std::string& grid_db, const std::string& grid_name,
                   const std::atomic<bool>& no_stop) {
  if (problem.checkpoints.size() < 2) return;
  const std::int64_t last = problem.checkpoints.back();
  std::map<std::string, std::size_t> index;  // params → point
  std::vector<double> final_values;
  std::vector<std::vector<double>> in_job(problem.checkpoints.size() - 1);
  {
    const ResultsStore store = ResultsStore::open(grid_db, ResultsStore::Mode::read_only);
    for (const JobRecord& job : store.find_jobs(grid_name)) {
      const std::optional<double> at_last = job.status == "done" ? find_objective_at(store, job, problem, last) : std::nullopt;
      if (!at_last) continue;
      std::vector<double> early;
      for (std::size_t k = 0; k + 1 < problem.checkpoints.size(); ++k) {
        const std::optional<double> v = find_objective_at(store, job, problem, problem.checkpoints[k]);
        early.push_back(v.value_or(std::numeric_limits<double>::infinity()));
      }
      index[job.params.dump()] = final_values.size();
      final_values.push_back(*at_last);
      for (std::size_t k = 0; k < early.size(); ++k) in_job[k].push_back(early[k]);
    }
  }
  const std::size_t n = final_values.size();
  const std::size_t third = n / 3;
  const std::vector<std::size_t> best_final = best_indices(final_values, third);
  const auto describe = [&](const std::vector<double>& rung_values) {
    const std::vector<std::size_t> best_rung = best_indices(rung_values, third);
    std::size_t kept = 0;
    for (std::size_t i : best_final) kept += std::count(best_rung.begin(), best_rung.end(), i) != 0 ? 1 : 0;
    const std::vector<std::size_t> order = best_indices(rung_values, n);
    const std::size_t best_rank = static_cast<std::size_t>(std::find(order.begin(), order.end(), best_final.front()) - order.begin()) + 1;
    const std::optional<double> rho = calc_rank_correlation(rung_values, final_values);
    char text[160];
    std::snprintf(text, sizeof text, "rho %+.3f, best third kept %zu of %zu, the grid's best ranks %zu of %zu", rho.value_or(NAN), kept,
                  third, best_rank, n);
    return std::string(text);
  };
  // (c) only where a job normalises by its training trajectory: online jobs.
  const bool online = problem.base.at("learning").value("mode", "online") == "online";
  const nlohmann::json scale = online ? find_common_input_scale(grid) : nlohmann::json();
  if (online && scale.is_null()) {
    std::printf("%s: the grid's points have different input scales: no full-normalisation rung jobs\n", problem.name.c_str());
  }
  for (std::size_t k = 0; k + 1 < problem.checkpoints.size(); ++k) {
    const std::int64_t c = problem.checkpoints[k];
    const ShortRungJobs plain = run_short_rung(problem, folder, kind, options, k, "", nlohmann::json::object(), index, no_stop);
    std::printf("%s rung %zu (checkpoint %lld) against checkpoint %lld, %zu points: in the grid's jobs %s; as short jobs %s "
                "(%zu short jobs: estimated %.4g, measured %.2f CPU s)\n",
                problem.name.c_str(), k, static_cast<long long>(c), static_cast<long long>(last), n, describe(in_job[k]).c_str(),
                describe(plain.values).c_str(), plain.jobs, plain.estimated, plain.cpu);
    if (!scale.is_null()) {
      const ShortRungJobs kept = run_short_rung(problem, folder, kind, options, k, "_fullnorm",
                                                {{"learning", {{"normalize_inputs", false}, {"lwpr", {{"norm_in", scale}}}}}}, index, no_stop);
      double largest = 0.0;  // the largest relative difference from the grid's own checkpoint
      for (std::size_t i = 0; i < n; ++i) largest = std::max(largest, std::fabs(kept.values[i] / in_job[k][i] - 1.0));
      std::printf("%s rung %zu as short jobs normalised by the full job's trajectory: %s; largest relative difference from "
                  "checkpoint %lld in the grid's jobs %.3g (%zu short jobs: estimated %.4g, measured %.2f CPU s)\n",
                  problem.name.c_str(), k, describe(kept.values).c_str(), static_cast<long long>(c), largest, kept.jobs,
                  kept.estimated, kept.cpu);
    }
    std::fflush(stdout);
  }
}

void run_problem(benchmark::State& state, const Problem& problem) {
  const JobKind kind = make_experiment_job_kind();
  const fs::path folder = scratch_folder();
  const std::atomic<bool> no_stop{false};
  RunOptions options;
  options.threads = 1;

  // The grid.
  const std::string grid_name = problem.name + " grid";
  const std::string grid_db = (folder / (problem.name + "_grid.db")).string();
  const std::vector<SweepSpec> grid_spec = load_sweep_stages(
      write_spec(folder, problem.name + "_grid", {{"name", grid_name}, {"base", problem.base}, {"sweep", {{"grid", problem.grid}}}}),
      kind.schema);
  const ExpandedSweep grid = expand_sweep(grid_spec.front(), kind.schema);
  double grid_cost = 0.0;
  for (const ExpandedJob& job : grid.jobs) grid_cost += calc_search_cpu_seconds(kind, job.config());
  options.db_path = grid_db;
  const double grid_cpu = run_grid_once(folder, problem.name + "_grid", [&] { run_sweep(grid, kind.executor, options, no_stop); });
  double grid_best = std::numeric_limits<double>::infinity();
  {
    const ResultsStore store = ResultsStore::open(grid_db, ResultsStore::Mode::read_only);
    for (const JobRecord& job : store.find_jobs(grid_name)) {
      const std::optional<double> objective = job.status == "done" ? find_objective(store, job, problem) : std::nullopt;
      if (objective) grid_best = std::min(grid_best, *objective);
    }
  }

  measure_rungs(problem, folder, kind, options, grid, grid_db, grid_name, no_stop);

  // The searches: the method and random, 25 % of the grid's estimated cost each.
  const double budget = kBudgetFraction * grid_cost;
  const auto run_one = [&](const nlohmann::json& method, std::uint64_t seed) {
    nlohmann::json search = problem.search;
    search.erase("method_settings");
    search.update(method);
    search["seed"] = seed;
    search["budget"] = {{"cpu_seconds", budget}};
    const std::string name = problem.name + " " + method.at("method").get<std::string>() + " " + std::to_string(seed);
    const std::vector<SweepSpec> spec = load_sweep_stages(
        write_spec(folder, problem.name + "_search", {{"name", name}, {"base", problem.base}, {"sweep", {{"search", search}}}}),
        kind.schema);
    RunOptions one = options;
    one.db_path = (folder / (problem.name + "_search.db")).string();
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(one.db_path + suffix);
    const double start = process_cpu_seconds();
    const SearchRunSummary summary = run_search(spec.front(), kind, one, ExpansionLimits{}, no_stop);
    SearchOutcome outcome;
    outcome.cpu = process_cpu_seconds() - start;
    outcome.best = summary.best.value_or(std::numeric_limits<double>::infinity());
    outcome.spent = summary.spent;
    outcome.steps = summary.steps;
    return outcome;
  };
  const nlohmann::json method = problem.search.at("method_settings");
  const nlohmann::json random = {{"method", "random"}};
  std::vector<double> method_best, random_best, method_spent, random_spent, method_cpu, random_cpu, method_steps, random_steps;
  int wins = 0;
  const int seeds = seed_count();
  std::printf("%s%s: grid %zu jobs, best %.6g, estimated %.4g CPU s, measured %.2f CPU s; budget %.4g (%.0f %%); %d seeds\n",
              problem.name.c_str(), is_reduced() ? " (REDUCED)" : "", grid.jobs.size(), grid_best, grid_cost, grid_cpu, budget, 100.0 * kBudgetFraction, seeds);
  std::fflush(stdout);
  if (seeds == 0) {
    remove_scratch(folder);
    return;
  }
  for (std::uint64_t seed = 1; seed <= static_cast<std::uint64_t>(seeds); ++seed) {
    const SearchOutcome m = run_one(method, seed);
    const SearchOutcome r = run_one(random, seed);
    method_best.push_back(m.best);
    random_best.push_back(r.best);
    method_spent.push_back(m.spent);
    random_spent.push_back(r.spent);
    method_cpu.push_back(m.cpu);
    random_cpu.push_back(r.cpu);
    method_steps.push_back(static_cast<double>(m.steps));
    random_steps.push_back(static_cast<double>(r.steps));
    wins += m.best < r.best;
    std::printf("  %s seed %2llu: %s best %.6g (%zu jobs, %.3g est, %.2f CPU s); random best %.6g (%zu jobs, %.3g est, %.2f CPU s)\n",
                problem.name.c_str(), static_cast<unsigned long long>(seed), method.at("method").get<std::string>().c_str(), m.best,
                m.steps, m.spent, m.cpu, r.best, r.steps, r.spent, r.cpu);
    std::fflush(stdout);
  }
  const Summary mb = summarise(method_best), rb = summarise(random_best);
  const Summary ms = summarise(method_spent), rs = summarise(random_spent);
  const Summary mc = summarise(method_cpu), rc = summarise(random_cpu);
  std::printf("%s: grid %zu jobs, best %.6g, estimated %.4g, measured %.2f CPU s\n", problem.name.c_str(), grid.jobs.size(),
              grid_best, grid_cost, grid_cpu);
  std::printf("%s: budget %.4g estimated (%.0f %% of the grid's)\n", problem.name.c_str(), budget, 100.0 * kBudgetFraction);
  std::printf("%s: method  best median %.6g [%.6g, %.6g], spent median %.4g est (%.0f %% of grid), CPU median %.2f s (%.0f %% of grid), jobs median %.0f\n",
              problem.name.c_str(), mb.median, mb.low, mb.high, ms.median, 100.0 * ms.median / grid_cost, mc.median,
              100.0 * mc.median / grid_cpu, summarise(method_steps).median);
  std::printf("%s: random  best median %.6g [%.6g, %.6g], spent median %.4g est (%.0f %% of grid), CPU median %.2f s (%.0f %% of grid), jobs median %.0f\n",
              problem.name.c_str(), rb.median, rb.low, rb.high, rs.median, 100.0 * rs.median / grid_cost, rc.median,
              100.0 * rc.median / grid_cpu, summarise(random_steps).median);
  std::printf("%s: goal 1 (method median within 5 %% of grid best): %.1f %% above it: %s; goal 2 (better than random): median %s, %d of %d seeds\n",
              problem.name.c_str(), 100.0 * (mb.median / grid_best - 1.0), mb.median <= 1.05 * grid_best ? "met" : "not met",
              mb.median < rb.median ? "better" : "not better", wins, seeds);
  std::printf("| %s | %.4g (%zu jobs, %.1f CPU s) | %.4g [%.4g, %.4g], %.0f jobs, %.0f %% of grid CPU | %.4g [%.4g, %.4g], %.0f jobs, %.0f %% | %+.1f %% | %d of %d |\n",
              problem.name.c_str(), grid_best, grid.jobs.size(), grid_cpu, mb.median, mb.low, mb.high,
              summarise(method_steps).median, 100.0 * mc.median / grid_cpu, rb.median, rb.low, rb.high,
              summarise(random_steps).median, 100.0 * rc.median / grid_cpu, 100.0 * (mb.median / grid_best - 1.0), wins, seeds);
  std::fflush(stdout);
  state.counters["grid_best"] = grid_best;
  state.counters["method_median"] = mb.median;
  state.counters["random_median"] = rb.median;
  state.counters["wins"] = wins;
  remove_scratch(folder);
}

Problem make_kernel_width_problem() {
  const nlohmann::json shipped = read_json(fs::path(ARMFARM_SOURCE_DIR) / "sweeps/thesis/fig6_1_kernel_width.json");
  Problem p;
  p.name = "fig6_1_kernel_width";
  p.base = shipped.at("base");  // 53 collection passes, as shipped
  p.base["recording"] = {{"series", nlohmann::json::array()}};
  if (is_reduced()) p.base["learning"]["collect_repeats"] = 4;
  p.grid = {{"learning.lwpr.update_D", {false, true}}, {"learning.lwpr.init_D", make_axis_values(0.01, 3.0, 24, true)}};
  p.search = {{"slots", 2},
              {"objective", {{"metric", "heldout_test_nmse"}, {"joint", 2}}},
              {"space",
               {{"learning.lwpr.init_D", {{"log_uniform", {0.01, 3.0}}}},
                {"learning.lwpr.update_D", {{"categorical", {false, true}}}}}},
              {"method_settings", {{"method", "tpe"}}}};
  p.metric = "heldout_test_nmse";
  p.joint = 2;
  return p;
}

Problem make_reaching_problem(const std::vector<std::int64_t>& rungs) {
  const nlohmann::json shipped = read_json(fs::path(ARMFARM_SOURCE_DIR) / "sweeps/thesis/table6_5_7_heldout_reaching.json");
  Problem p;
  p.name = "reaching_rungs";
  for (std::int64_t c : rungs) p.name += "_" + std::to_string(c);
  p.base = shipped.at("base");  // 100 points per reach, 9 held-out transitions, as shipped
  p.base["trajectory"]["reaching"]["reaches"] = 200;  // the last checkpoint
  p.base["learning"]["heldout_checkpoints"] = rungs;
  p.base["recording"] = {{"series", nlohmann::json::array()}};
  if (is_reduced()) {
    p.base["trajectory"]["reaching"]["points_per_reach"] = 40;
    p.base["learning"]["heldout_segments"] = 3;
  }
  p.grid = {{"learning.lwpr.init_D", make_axis_values(0.1, 2.5, 4, true)},
            {"learning.lwpr.init_alpha", make_axis_values(25.0, 400.0, 4, true)},
            {"control.gain_scale", make_axis_values(0.2, 1.0, 4, false)}};
  p.search = {{"slots", 2},
              {"objective", {{"metric", "heldout_test_nmse"}, {"joint", "mean"}}},
              {"space",
               {{"learning.lwpr.init_D", {{"log_uniform", {0.1, 2.5}}}},
                {"learning.lwpr.init_alpha", {{"log_uniform", {25.0, 400.0}}}},
                {"control.gain_scale", {{"uniform", {0.2, 1.0}}}}}},
              {"method_settings", {{"method", "asha"}, {"sampler", "tpe"}, {"eta", 3}}}};
  p.metric = "heldout_test_nmse";
  p.checkpoints = rungs;
  p.length_path = "trajectory.reaching.reaches";
  return p;
}

// The cost factor (kSearchCpuSecondsPerJointSecond): each job of a shipped spec run alone at
// -j1, its process CPU-seconds against the job-cost model's joint-seconds. `seeds` keeps the
// jobs of the spec's first seeds (a repeat axis multiplies the same configurations). Also, from
// the 5-seed thesis databases in ARMFARM_BENCH_SEARCH_RUNS (a folder of *.db, read only), the
// stored wall seconds of their done jobs against the same estimate: wall time, an upper bound
// of CPU time for jobs that ran at -j2 on two cores.
struct FactorSample {
  double joint_seconds = 0.0, cpu = 0.0;
};

void print_factor(const std::string& what, const std::vector<FactorSample>& samples, const char* measured) {
  if (samples.empty()) return;
  double joint_seconds = 0.0, cpu = 0.0;
  std::vector<double> ratios;
  for (const FactorSample& f : samples) {
    joint_seconds += f.joint_seconds;
    cpu += f.cpu;
    ratios.push_back(f.cpu / f.joint_seconds);
  }
  const Summary r = summarise(ratios);
  std::printf("factor %s: %zu jobs, estimated %.5g joint-s, %s %.2f s: %.5f s per joint-s overall; per job median %.5f [%.5f, %.5f]\n",
              what.c_str(), samples.size(), joint_seconds, measured, cpu, cpu / joint_seconds, r.median, r.low, r.high);
  std::fflush(stdout);
}

void run_factor_spec(const JobKind& kind, const fs::path& folder, const std::string& relative, std::size_t seeds) {
  const std::vector<SweepSpec> stages = load_sweep_stages((fs::path(ARMFARM_SOURCE_DIR) / relative).string(), kind.schema);
  const ExpandedSweep sweep = expand_sweep(stages.front(), kind.schema);
  std::vector<std::int64_t> kept_seeds;
  const std::atomic<bool> no_stop{false};
  std::vector<FactorSample> samples;
  for (const ExpandedJob& job : sweep.jobs) {
    if (std::find(kept_seeds.begin(), kept_seeds.end(), job.seed) == kept_seeds.end()) {
      if (kept_seeds.size() >= seeds) continue;
      kept_seeds.push_back(job.seed);
    }
    ExpandedSweep one = sweep;
    one.jobs = {job};
    RunOptions options;
    options.threads = 1;
    options.db_path = (folder / "factor.db").string();
    for (const char* suffix : {"", "-wal", "-shm"}) fs::remove(options.db_path + suffix);
    const double start = process_cpu_seconds();
    run_sweep(one, kind.executor, options, no_stop);
    const double cpu = process_cpu_seconds() - start;
    samples.push_back({kind.estimate_cost(job.config(), nullptr).cost, cpu});
  }
  print_factor(relative + " (measured)", samples, "process CPU");
}

void BM_SearchCostFactor(benchmark::State& state) {
  for (auto _ : state) {
    const JobKind kind = make_experiment_job_kind();
    const fs::path folder = fs::temp_directory_path() / ("armfarm_bench_factor_" + std::to_string(::getpid()));
    fs::create_directories(folder);
    run_factor_spec(kind, folder, "sweeps/quickstart.json", 1);
    run_factor_spec(kind, folder, "sweeps/thesis/fig6_1_kernel_width.json", 1);
    run_factor_spec(kind, folder, "sweeps/thesis/table6_5_7_heldout_reaching.json", 1);
    const char* runs = std::getenv("ARMFARM_BENCH_SEARCH_RUNS");
    if (runs != nullptr) {
      std::vector<fs::path> files;
      for (const fs::directory_entry& entry : fs::directory_iterator(runs)) {
        if (entry.path().extension() == ".db") files.push_back(entry.path());
      }
      std::sort(files.begin(), files.end());
      std::vector<FactorSample> all;
      for (const fs::path& file : files) {
        const ResultsStore store = ResultsStore::open(file.string(), ResultsStore::Mode::read_only);
        std::vector<FactorSample> samples;
        for (const SweepRecord& sweep : store.find_sweeps()) {
          for (const JobRecord& job : store.find_jobs(sweep.name)) {
            if (job.status != "done" || !job.wall_seconds) continue;
            try {
              samples.push_back({kind.estimate_cost(job.config, nullptr).cost, *job.wall_seconds});
            } catch (const std::exception&) {
              // its model file is not on this machine: left out
            }
          }
        }
        print_factor(file.filename().string() + " (stored wall)", samples, "wall");
        all.insert(all.end(), samples.begin(), samples.end());
      }
      print_factor("all of " + std::string(runs) + " (stored wall)", all, "wall");
    }
    fs::remove_all(folder);
  }
}
BENCHMARK(BM_SearchCostFactor)->Unit(benchmark::kSecond)->Iterations(1);

void BM_SearchKernelWidth(benchmark::State& state) {
  for (auto _ : state) run_problem(state, make_kernel_width_problem());
}
BENCHMARK(BM_SearchKernelWidth)->Unit(benchmark::kSecond)->Iterations(1);

// fig6_1's batch job has learning checkpoints: held-out evaluation after 1 … 5 epochs (the base's
// learning.epochs, 5). The same problem and grid with checkpoints after 1 and 5 epochs, searched
// by ASHA (η 3, TPE sampler): a rung-0 job is the job with learning.epochs 1. Its collection
// passes are the full job's, and the job-cost model has no term for the training epochs
// (runner/execution/job_cost.cpp), so the budget counts a rung-0 job as a whole job; the rung
// lines print the short jobs' estimated and measured CPU.
Problem make_kernel_width_asha_problem() {
  Problem p = make_kernel_width_problem();
  p.name = "fig6_1_kernel_width_asha_epochs_1_5";
  p.base["learning"]["epochs"] = 5;
  p.base["learning"]["heldout_checkpoints"] = {1, 5};
  p.search["method_settings"] = {{"method", "asha"}, {"sampler", "tpe"}, {"eta", 3}};
  p.checkpoints = {1, 5};
  p.length_path = "learning.epochs";
  return p;
}

void BM_SearchKernelWidthAsha(benchmark::State& state) {
  for (auto _ : state) run_problem(state, make_kernel_width_asha_problem());
}
BENCHMARK(BM_SearchKernelWidthAsha)->Unit(benchmark::kSecond)->Iterations(1);

// ARMFARM_BENCH_SEARCH_FULL_NORMALISATION=1: every job of the reaching problem (grid, searches,
// rungs) normalises its inputs by the full 200-reach trajectory, as a spec can ask today: base
// learning.normalize_inputs false and learning.lwpr.norm_in the full job's input scale
// (calc_job_input_scale; no axis of this problem changes the training trajectory). A full job
// then learns as with normalize_inputs, and a short rung job as the full job's first reaches do.
bool is_full_normalisation() {
  const char* text = std::getenv("ARMFARM_BENCH_SEARCH_FULL_NORMALISATION");
  return text != nullptr && std::string(text) == "1";
}

void apply_full_normalisation(Problem& problem, const JobKind& kind, const fs::path& folder) {
  const std::vector<SweepSpec> spec =
      load_sweep_stages(write_spec(folder, problem.name + "_base", {{"name", problem.name + " base"}, {"base", problem.base}}), kind.schema);
  const ExpandedSweep one = expand_sweep(spec.front(), kind.schema);
  JobModels models;
  const Eigen::VectorXd scale = calc_job_input_scale(one.jobs.front().config(), models);
  problem.base["learning"]["normalize_inputs"] = false;
  problem.base["learning"]["lwpr"]["norm_in"] = std::vector<double>(scale.data(), scale.data() + scale.size());
  problem.name += "_fullnorm";
  std::printf("%s: learning.normalize_inputs false, learning.lwpr.norm_in %s\n", problem.name.c_str(),
              problem.base["learning"]["lwpr"]["norm_in"].dump().c_str());
}

// The reaching problem's rungs: ARMFARM_BENCH_SEARCH_RUNGS=10,200 (increasing, ending at 200)
// if given, else `shipped`.
std::vector<std::int64_t> find_rungs(const std::vector<std::int64_t>& shipped) {
  const char* text = std::getenv("ARMFARM_BENCH_SEARCH_RUNGS");
  if (text == nullptr || *text == '\0') return shipped;
  std::vector<std::int64_t> rungs;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) rungs.push_back(std::atoll(item.c_str()));
  if (rungs.size() < 2 || rungs.back() != 200 || !std::is_sorted(rungs.begin(), rungs.end())) {
    std::fprintf(stderr, "ARMFARM_BENCH_SEARCH_RUNGS=%s: expected increasing checkpoints ending at 200\n", text);
    std::exit(2);
  }
  return rungs;
}

void run_reaching(benchmark::State& state, const std::vector<std::int64_t>& rungs) {
  for (auto _ : state) {
    Problem problem = make_reaching_problem(rungs);
    if (is_full_normalisation()) apply_full_normalisation(problem, make_experiment_job_kind(), scratch_folder());
    run_problem(state, problem);
  }
}

// Two layouts of ASHA's rungs over the checkpoints 10/50/200. Rungs at 10 and 200 reaches,
// as sweeps/search/reaching_asha.json ships them (or ARMFARM_BENCH_SEARCH_RUNGS): checkpoint 10
// orders the grid's points as 200 does (ρ +0.97 in the full jobs, +0.71 as short jobs), 50 does
// not (ρ +0.39: the learning curves cross there; runner/search/README.md).
void BM_SearchReaching(benchmark::State& state) { run_reaching(state, find_rungs({10, 200})); }
BENCHMARK(BM_SearchReaching)->Unit(benchmark::kSecond)->Iterations(1);

// The checkpoints all as rungs, 10/50/200: printed beside the shipped layout.
void BM_SearchReachingAllCheckpoints(benchmark::State& state) { run_reaching(state, {10, 50, 200}); }
BENCHMARK(BM_SearchReachingAllCheckpoints)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace armfarm

BENCHMARK_MAIN();
