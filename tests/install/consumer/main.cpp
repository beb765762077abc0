// Loads an arm, runs one 2 s job on the default sinusoid with online LWPR, prints a metric.
// With an expected value (from `armfarm job` on the same configuration) exits 1 unless equal.
#include "engine/experiment/run_experiment.hpp"
#include "engine/model/model_loading.hpp"

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  if (argc < 2) return std::fprintf(stderr, "usage: consumer MODEL [EXPECTED_TRACKING_NMSE]\n"), 2;
  const armfarm::ArmModel model = armfarm::load_arm_model(argv[1]);
  armfarm::JobConfig config;
  config.trajectory.sine.duration = 2.0;  // s
  const armfarm::JobOutcome outcome = armfarm::run_experiment(model, config);
  for (const armfarm::Metric& metric : outcome.metrics) {
    if (metric.name != "tracking_nmse" || metric.joint || metric.checkpoint || !metric.value) continue;
    std::printf("%s: %s, tracking_nmse %.17g\n", argv[1], armfarm::to_string(outcome.status), *metric.value);
    return argc > 2 && *metric.value != std::strtod(argv[2], nullptr) ? 1 : 0;
  }
  return std::fprintf(stderr, "no tracking_nmse in the outcome\n"), 1;
}
