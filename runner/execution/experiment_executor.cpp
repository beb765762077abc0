// TEMPORARY placeholder until the experiment job lands (the experiment helper's branch owns this
// file; the lead replaces it at merge). The schema is a plausible experiment configuration so
// that sweeps/quickstart.json can be parsed, validated and expanded; running a job reports that
// experiment jobs are not built yet.
#include "runner/execution/job_executor.hpp"

namespace armfarm {

JobConfigSchema make_experiment_config_schema() {
  JobConfigSchema schema;
  schema.defaults = nlohmann::json::parse(R"json({
    "model": "models/dlr_lwr3.urdf",
    "seed": 0,
    "active_joints": [2, 4],
    "control": {"kp": [200.0, 100.0], "kd": [20.0, 10.0], "gain_scale": 1.0, "period": 0.001},
    "trajectory": {"kind": "figure8", "period": 4.0, "amplitude": [0.3, 0.3], "center": [0.0, 0.0]},
    "learning": {"mode": "online",
                 "lwpr": {"init_D": 25.0, "init_alpha": 250.0, "w_gen": 0.2, "w_prune": 1.0,
                          "penalty": 1e-6, "meta": false}},
    "recording": {"series": ["POS", "POS_D", "TOR", "FF"], "period": 0.01},
    "simulation": {"duration": 20.0, "test_duration": 4.0, "divergence_limit": 100.0}
  })json");
  schema.validate = [](const nlohmann::json& config) {
    if (config.at("control").at("gain_scale").get<double>() <= 0.0) {
      throw ConfigError("control.gain_scale", "must be positive");
    }
    if (config.at("learning").at("lwpr").at("init_D").get<double>() <= 0.0) {
      throw ConfigError("learning.lwpr.init_D", "must be positive");
    }
    if (config.at("simulation").at("duration").get<double>() <= 0.0) {
      throw ConfigError("simulation.duration", "must be positive");
    }
  };
  return schema;
}

JobExecutor make_experiment_executor() {
  return [](const nlohmann::json&, const JobControl&) -> JobOutcome {
    throw ConfigError("", "experiment jobs are not built yet");
  };
}

}  // namespace armfarm
