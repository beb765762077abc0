#pragma once
// A cheap, deterministic stand-in for the experiment job, for the runner's tests and
// benchmarks (and the test binary armfarm_fakejobs, never the product armfarm): its metrics and
// series are closed-form functions of the configuration and seed; it can sleep, burn CPU,
// fail, throw, diverge or hang on request (the `fake` section of its configuration).
#include "runner/execution/job_cost.hpp"
#include "runner/execution/job_executor.hpp"

namespace armfarm {

/// Defaults: model, seed, control.{kp,kd,gain_scale}, learning.lwpr.{init_D,init_alpha},
/// trajectory.{kind,period,amplitude}, simulation.{duration,samples},
/// fake.{sleep_ms,work,fail,throw,diverge,hang}.
JobConfigSchema make_fake_job_config_schema();

/// Metrics: tracking_nmse per joint (1-based, one per control.kp entry), same_run_test_nmse and
/// work_checksum per job. Series: POS and TOR, simulation.samples rows of t, q1..qn / tau1..taun.
JobExecutor make_fake_job_executor();

/// The fake job's cost estimate: simulation.duration × joints (control.kp entries) + sleep_ms / 1000;
/// kind "fake N joints"; seconds: sleep_ms / 1000 plus its CPU work.
JobCostFunction make_fake_job_cost_function();

}  // namespace armfarm
