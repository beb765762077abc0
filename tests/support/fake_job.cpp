#include "support/fake_job.hpp"

#include "engine/experiment/metric_catalog.hpp"
#include "engine/learning/learning_config.hpp"
#include "engine/random/random_stream.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>

namespace armfarm {
namespace {

// Sleeps `milliseconds` in 1 ms slices; false when asked to stop first.
bool sleep_polling(double milliseconds, const JobControl& control) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                          std::chrono::duration<double, std::milli>(milliseconds));
  for (auto now = std::chrono::steady_clock::now(); now < end; now = std::chrono::steady_clock::now()) {
    if (control.should_stop()) return false;
    std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(end - now, std::chrono::milliseconds(1)));
  }
  return !control.should_stop();
}

}  // namespace

JobConfigSchema make_fake_job_config_schema() {
  JobConfigSchema schema;
  schema.defaults = nlohmann::json::parse(R"json({
    "model": "models/fake_arm.urdf",
    "seed": 0,
    "control": {"kp": [100.0, 50.0], "kd": [10.0, 5.0], "gain_scale": 1.0},
    "learning": {"lwpr": {}},
    "trajectory": {"kind": "figure8", "period": 2.0, "amplitude": 0.5},
    "simulation": {"duration": 4.0, "samples": 200},
    "fake": {"sleep_ms": 2.0, "work": 0, "fail": false, "throw": false, "diverge": false, "hang": false}
  })json");
  // The LWPR defaults are the experiment job's (engine/learning/learning_config.hpp), not a copy.
  const lwpr::LwprParams lwpr_defaults = make_job_lwpr_defaults();
  schema.defaults["learning"]["lwpr"] = {{"init_D", lwpr_defaults.init_D(0, 0)}, {"init_alpha", lwpr_defaults.init_alpha}};
  // Checks the JSON and keeps nothing (its executor reads the JSON).
  schema.validate = [](const nlohmann::json& config) -> std::shared_ptr<const CheckedConfig> {
    const auto& control = config.at("control");
    if (control.at("kp").empty()) throw ConfigError("control.kp", "needs one gain per active joint");
    if (control.at("kd").size() != control.at("kp").size()) {
      throw ConfigError("control.kd", "has " + std::to_string(control.at("kd").size()) + " gains, control.kp has " +
                                          std::to_string(control.at("kp").size()));
    }
    for (std::size_t i = 0; i < control.at("kp").size(); ++i) {
      if (control.at("kp")[i].get<double>() < 0.0) {
        throw ConfigError("control.kp[" + std::to_string(i) + "]", "must not be negative");
      }
    }
    if (control.at("gain_scale").get<double>() <= 0.0) throw ConfigError("control.gain_scale", "must be positive");
    if (config.at("learning").at("lwpr").at("init_D").get<double>() <= 0.0) {
      throw ConfigError("learning.lwpr.init_D", "must be positive");
    }
    const std::string kind = config.at("trajectory").at("kind").get<std::string>();
    if (kind != "figure8" && kind != "circle") {
      throw ConfigError("trajectory.kind", "must be \"figure8\" or \"circle\", not \"" + kind + "\"");
    }
    const auto samples = config.at("simulation").at("samples").get<std::int64_t>();
    if (samples < 1 || samples > 1000000) throw ConfigError("simulation.samples", "must be in [1, 1000000]");
    if (config.at("simulation").at("duration").get<double>() <= 0.0) {
      throw ConfigError("simulation.duration", "must be positive");
    }
    if (config.at("fake").at("sleep_ms").get<double>() < 0.0) throw ConfigError("fake.sleep_ms", "must not be negative");
    if (config.at("fake").at("work").get<std::int64_t>() < 0) throw ConfigError("fake.work", "must not be negative");
    return nullptr;
  };
  return schema;
}

JobExecutor make_fake_job_executor() {
  return [](const nlohmann::json& config, const CheckedConfig*, const JobControl& control) {
    const auto& fake = config.at("fake");
    const auto& kp = config.at("control").at("kp");
    const double gain_scale = config.at("control").at("gain_scale").get<double>();
    const double init_D = config.at("learning").at("lwpr").at("init_D").get<double>();
    const double duration = config.at("simulation").at("duration").get<double>();
    const auto samples = config.at("simulation").at("samples").get<long>();
    const double period = config.at("trajectory").at("period").get<double>();
    const double amplitude = config.at("trajectory").at("amplitude").get<double>();
    const auto seed = config.at("seed").get<std::int64_t>();
    const long n_joints = static_cast<long>(kp.size());

    JobOutcome outcome;
    if (fake.at("throw").get<bool>()) throw std::runtime_error("fake job asked to throw");
    if (fake.at("hang").get<bool>()) {
      while (!control.should_stop()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      outcome.status = JobStatus::timeout;
      outcome.message = "stopped while hanging";
      return outcome;
    }
    if (!sleep_polling(fake.at("sleep_ms").get<double>(), control)) {
      outcome.status = JobStatus::timeout;
      outcome.message = "stopped while sleeping";
      return outcome;
    }
    // CPU work whose result is a metric, so that it cannot be optimized away.
    double checksum = 0.0;
    const auto work = fake.at("work").get<std::int64_t>();
    for (std::int64_t i = 0; i < work; ++i) {
      checksum += std::sin(static_cast<double>(i) * 1e-3) * std::cos(static_cast<double>(i) * 7e-4);
      if ((i & 0xFFFF) == 0 && control.should_stop()) {
        outcome.status = JobStatus::timeout;
        outcome.message = "stopped while working";
        return outcome;
      }
    }

    RandomStream generator(static_cast<std::uint64_t>(seed), "fake_job.noise");
    double mean = 0.0;
    for (long j = 0; j < n_joints; ++j) {
      const double base = 0.01 * std::pow(init_D, 0.3) / (1.0 + kp[j].get<double>() * gain_scale / 100.0);
      const double value = base * (1.0 + 0.1 * (generator.uniform() - 0.5));
      outcome.metrics.push_back({metric_names::tracking_nmse, static_cast<int>(j + 1), std::nullopt, value, {}});
      mean += value / static_cast<double>(n_joints);
    }
    outcome.metrics.push_back({metric_names::same_run_test_nmse, std::nullopt, std::nullopt, mean, {}});
    outcome.metrics.push_back({metric_names::work_checksum, std::nullopt, std::nullopt, checksum, {}});

    Series pos{"POS", {"t"}, Eigen::MatrixXd(samples, n_joints + 1)};
    Series tor{"TOR", {"t"}, Eigen::MatrixXd(samples, n_joints + 1)};
    for (long j = 1; j <= n_joints; ++j) {
      pos.columns.push_back("q" + std::to_string(j));
      tor.columns.push_back("tau" + std::to_string(j));
    }
    for (long i = 0; i < samples; ++i) {
      const double t = duration * static_cast<double>(i) / static_cast<double>(samples);
      pos.rows(i, 0) = tor.rows(i, 0) = t;
      for (long j = 1; j <= n_joints; ++j) {
        const double phase = 2.0 * M_PI * t / period + static_cast<double>(j);
        pos.rows(i, j) = amplitude * std::sin(phase) + 1e-4 * (generator.uniform() - 0.5);
        tor.rows(i, j) = kp[j - 1].get<double>() * gain_scale * 0.01 * std::cos(phase) + 1e-3 * (generator.uniform() - 0.5);
      }
    }
    outcome.series.push_back(std::move(pos));
    outcome.series.push_back(std::move(tor));

    outcome.end_time = duration;
    if (fake.at("diverge").get<bool>()) {
      outcome.status = JobStatus::diverged;
      outcome.end_time = duration / 2.0;
      outcome.message = "joint 1 position exceeded the divergence limit at t = " + std::to_string(duration / 2.0) + " s";
    } else if (fake.at("fail").get<bool>()) {
      outcome.status = JobStatus::failed;
      outcome.message = "fake job asked to fail";
    }
    return outcome;
  };
}

JobCostFunction make_fake_job_cost_function() {
  return [](const nlohmann::json& config, const CheckedConfig*) {
    const std::size_t n = config.at("control").at("kp").size();
    JobCostEstimate estimate;
    estimate.cost = config.at("simulation").at("duration").get<double>() * static_cast<double>(std::max<std::size_t>(1, n)) +
                    config.at("fake").at("sleep_ms").get<double>() / 1000.0;
    estimate.kind = "fake " + std::to_string(n) + " joints";
    // Its wall time is its sleep; the CPU work (about 10 ns an iteration) and the series are small.
    estimate.seconds = config.at("fake").at("sleep_ms").get<double>() / 1000.0 +
                       static_cast<double>(config.at("fake").at("work").get<std::int64_t>()) * 1e-8 + 0.01;
    return estimate;
  };
}

}  // namespace armfarm
