#pragma once
// The plan the `armfarm slurm` tests start from (tests/runner/cli/slurm_script_test.cpp and
// cmd_slurm_test.cpp): 12 jobs in 4 tasks of 3 CPUs, a spec path with a quote and a sweep name
// with a space.
#include "runner/cli/slurm_script.hpp"

namespace armfarm::test_support {

inline cli::SlurmPlan make_plan() {
  cli::SlurmPlan plan;
  plan.armfarm = "/opt/armfarm/bin/armfarm";
  plan.spec = "/home/me/sweeps/it's here.json";
  plan.db = "/scratch/me/results.db";
  plan.work_dir = "/home/me";
  plan.sweep = "quick start";
  plan.jobs = 12;
  plan.tasks = 4;
  plan.cpus_per_task = 3;
  return plan;
}

}  // namespace armfarm::test_support
