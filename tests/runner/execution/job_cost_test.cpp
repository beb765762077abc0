// The experiment job's cost estimate makes each job's arm as the executor does (job_models.hpp):
// a two-leaf arm costs as soon as the job names its end effector, and the estimate follows the
// active joints and the simulated time.
#include "runner/execution/job_cost.hpp"

#include "runner/spec/config_error.hpp"
#include "runner/config/job_config_json.hpp"

#include <gtest/gtest.h>

#include <string>

namespace armfarm {
namespace {

nlohmann::json make_two_leaf_job(const std::string& link) {
  nlohmann::json config = make_job_config_defaults();
  config["model"] = std::string(ARMFARM_TEST_DATA_DIR) + "/arms/kuka_iiwa14.urdf";
  config["end_effector"]["link"] = link;
  config["trajectory"]["sine"]["duration"] = 2.0;
  config["learning"]["mode"] = "none";
  config["learning"]["heldout"] = false;
  config["control"]["feed_forward"] = "none";
  return config;
}

TEST(JobCost, ATwoLeafArmCostsWithTheJobsOwnEndEffector) {
  const JobCostFunction estimate = make_experiment_cost_function();
  const JobCostEstimate all = estimate(make_two_leaf_job("tool_tcp"), nullptr);
  // No learning, one pass: simulated seconds × active joints.
  EXPECT_NEAR(all.cost, 2.0 * 7, 1e-9);
  EXPECT_EQ(all.kind, "none sine 7 joints");
  nlohmann::json three = make_two_leaf_job("iiwa_link_ee");
  three["active_joints"] = {1, 2, 4};
  EXPECT_NEAR(estimate(three, nullptr).cost, 2.0 * 3, 1e-9);
  // Without a choice the job's arm cannot be made, as at expansion.
  EXPECT_THROW(estimate(make_two_leaf_job(""), nullptr), ConfigError);
}

}  // namespace
}  // namespace armfarm
