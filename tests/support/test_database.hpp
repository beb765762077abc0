#pragma once
// Small results databases for the analysis tests, written through the store's public API with
// hand-chosen metrics and series so that every expected figure is known in advance.
#include "results/results_store.hpp"
#include "support/command_line.hpp"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace armfarm::testing {

/// A job to put in a test database.
struct TestJob {
  nlohmann::json params;  ///< varying parameters, also written into the config
  std::string status = "done";
  std::string message;
  std::vector<MetricRecord> metrics;
  std::vector<SeriesRecord> series;
};

/// A series `name` of `rows` rows whose cell (r, c) is value(r, c).
inline SeriesRecord make_series(const std::string& name, std::vector<std::string> columns, int rows,
                                const std::function<double(int, int)>& value) {
  SeriesRecord series;
  series.name = name;
  series.columns = std::move(columns);
  series.rows.resize(rows, static_cast<Eigen::Index>(series.columns.size()));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < static_cast<int>(series.columns.size()); ++c) series.rows(r, c) = value(r, c);
  }
  return series;
}

/// A held-out metric's value in the table tests: init_D + 0.1 × joint + 0.01 × checkpoint +
/// 0.001 × seed, so that every cell names the (row, joint, checkpoint) it came from.
inline double make_heldout_value(double init_d, std::optional<int> joint, std::int64_t checkpoint, int seed) {
  return init_d + 0.1 * joint.value_or(0) + 0.01 * static_cast<double>(checkpoint) + 0.001 * seed;
}

/// A fresh temporary directory, removed when the object goes.
struct TemporaryDirectory {
  std::filesystem::path path;
  TemporaryDirectory() {
    std::string pattern = (std::filesystem::temp_directory_path() / "armfarm-analysis-test-XXXXXX").string();
    path = mkdtemp(pattern.data());
  }
  ~TemporaryDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

/// metric_info rows for the names the analysis tests use (what the runner writes from the
/// engine's catalog; written by hand here so that the analysis is tested on what it reads).
inline std::vector<MetricInfoRecord> make_test_metric_info() {
  return {
      {"tracking_nmse", "1", "joint error over target variance", "lower", "joint", "result"},
      {"tracking_rmse", "rad", "joint error", "lower", "joint", "result"},
      {"test_nmse", "1", "held-out error", "lower", "joint", "result"},
      {"same_run_test_nmse", "1", "error on withheld samples of the training runs", "lower", "joint", "result"},
      {"ff_fb_ratio_avg", "1", "feed-forward share", "higher", "joint", "result"},
      {"fb_abs_avg", "N·m", "feedback torque", "lower", "joint", "result"},
      {"torque_saturation_fraction", "1", "saturated ticks", "lower", "joint", "result"},
      {"n_receptive_fields", "count", "receptive fields", "none", "job", "result"},
      {"learner_us_per_update", "µs", "update time", "lower", "job", "timing"},
      {"learner_us_per_predict", "µs", "prediction time", "lower", "job", "timing"},
      {"sim_seconds_per_wall_second", "s/s", "simulation speed", "higher", "job", "timing"},
      {"heldout_test_nmse", "1", "frozen learner on held-out samples", "lower", "checkpoint", "result"},
      {"heldout_ff_fb_ratio_avg", "1", "held-out control pass: feed-forward share", "higher", "checkpoint", "result"},
  };
}

/// A minimal sweep registration for the store's tests: `name`, spec "{}" with hash "h", started now.
inline SweepRegistration make_sweep_registration(const std::string& name) {
  SweepRegistration sweep;
  sweep.name = name;
  sweep.spec_text = "{}";
  sweep.spec_hash = "h";
  sweep.started_at = make_utc_timestamp();
  return sweep;
}

/// Writes a sweep named `sweep` with `jobs` into the database at `path` (created if absent).
inline void write_test_sweep(const std::string& path, const std::string& sweep, const std::vector<TestJob>& jobs) {
  ResultsStore store = ResultsStore::open(path, ResultsStore::Mode::read_write);
  SweepRegistration registration;
  registration.name = sweep;
  registration.description = "test sweep " + sweep;
  registration.spec_text = "{\"name\": \"" + sweep + "\"}";
  registration.spec_hash = "0123456789abcdef0123456789abcdef";
  registration.started_at = make_utc_timestamp();
  registration.provenance = {"0.1.0", "deadbeef", false, "GNU 12", "3.7", "testhost"};
  registration.metric_info = make_test_metric_info();
  std::vector<JobRegistration> registrations;
  JobBatch batch;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    JobRegistration job;
    job.config = {{"sweep", sweep}, {"index", i}};
    for (const auto& item : jobs[i].params.items()) {
      // Dotted paths become nested objects, as in a real configuration.
      nlohmann::json* node = &job.config;
      std::string path = item.key();
      std::size_t start = 0;
      for (std::size_t dot = path.find('.'); dot != std::string::npos; dot = path.find('.', start)) {
        node = &(*node)[path.substr(start, dot - start)];
        start = dot + 1;
      }
      (*node)[path.substr(start)] = item.value();
    }
    job.key = "key_" + sweep + "_" + std::to_string(i);  // the same job index pairs across databases
    job.params = jobs[i].params;
    job.seed = jobs[i].params.value("seed", 0);
    registrations.push_back(job);
    JobResultRecord result;
    result.key = job.key;
    result.status = jobs[i].status;
    result.message = jobs[i].message;
    result.end_time = 1.0;
    result.wall_seconds = 0.5;
    result.started_at = registration.started_at;
    result.finished_at = make_utc_timestamp();
    result.metrics = jobs[i].metrics;
    result.series = jobs[i].series;
    batch.started.push_back(job.key);
    batch.finished.push_back(result);
  }
  const RegisteredRun run = store.insert_sweep_run(registration, registrations);
  store.insert_job_batch(batch, sweep);
  store.update_run_finished(run.run_id, "complete", static_cast<int>(jobs.size()), 0, make_utc_timestamp());
}

/// Two gain scales × two seeds (params control.gain_scale, seed); tracking_nmse per joint 1–3 plus
/// its job mean, as the job writes it; with `with_timing`, a learner_us_per_update of `microseconds`.
inline std::vector<TestJob> make_gain_jobs(bool with_timing = false, double microseconds = 20.0) {
  std::vector<TestJob> jobs;
  for (double gain : {0.2, 1.0}) {
    for (int seed = 1; seed <= 2; ++seed) {
      TestJob job;
      job.params = {{"control.gain_scale", gain}, {"seed", seed}};
      double sum = 0.0;
      for (int joint = 1; joint <= 3; ++joint) {
        const double value = 0.01 * joint / gain + 0.001 * seed;
        sum += value;
        job.metrics.push_back({0, "tracking_nmse", joint, value, ""});
      }
      job.metrics.push_back({0, "tracking_nmse", std::nullopt, sum / 3.0, "mean over 3 of 3 joints"});
      if (with_timing) job.metrics.push_back({0, "learner_us_per_update", std::nullopt, microseconds, ""});
      jobs.push_back(job);
    }
  }
  return jobs;
}

using test_support::CommandResult;
using test_support::run_armfarm;

}  // namespace armfarm::testing
