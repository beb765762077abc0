// Sweeps over an arm with two leaf frames (tests/data/arms/kuka_iiwa14.urdf: the flange
// 'iiwa_link_ee' and a tool point 'tool_tcp'): `armfarm run` sweeps it with end_effector.link in
// the spec's base and as a grid axis (sharded too: the job-cost estimate makes each job's arm as
// the executor does), `slurm` writes its scripts, and a missing or unknown choice is refused at
// expansion by run, expand and slurm alike, in one line naming the spec, the leaves and the key,
// before any database is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/command_line.hpp"
#include "support/scratch_file.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_armfarm;

namespace {

class CmdRunEndEffector : public ::testing::Test {
 protected:
  void SetUp() override { folder_ = armfarm::test_support::make_scratch_folder("run_ee"); }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  // A sweep of short feedback-only sine jobs on the two-leaf arm; `base` and `sweep` are JSON
  // members added to the spec's base and its sweep block. pd_substeps 10: the arm has no rotor
  // inertia, and its wrist needs a finer PD period than 10 ms (issue 22).
  std::string write_spec(const std::string& name, const std::string& base, const std::string& sweep) const {
    const std::string path = (folder_ / (name + ".json")).string();
    std::ofstream(path) << R"({"name": ")" << name << R"(", "base": {"model": ")" << ARMFARM_TEST_DATA_DIR
                        << R"(/arms/kuka_iiwa14.urdf", "pd_substeps": 10,
        "trajectory": {"sine": {"duration": 0.5}}, "control": {"mode": "feedback", "feed_forward": "none"},
        "learning": {"mode": "none"})" << base << R"(}, "sweep": {)" << sweep << "}}";
    return path;
  }
  std::string db(const std::string& name) const { return (folder_ / (name + ".db")).string(); }

  std::filesystem::path folder_;
};

int count_lines(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')); }

TEST_F(CmdRunEndEffector, ChoiceInTheBaseRuns) {
  const std::string spec = write_spec("in_base", R"(, "end_effector": {"link": "tool_tcp"})",
                                      R"("grid": {"control.gain_scale": [0.2, 1.0]})");
  const CommandResult result = run_armfarm("run " + spec + " --db " + db("in_base") + " -j 2 --quiet");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("sweep in_base: 2 done, 0 failed, 0 diverged"), std::string::npos) << result.output;
}

TEST_F(CmdRunEndEffector, ChoiceAsAGridAxisRunsOneJobPerLink) {
  const std::string spec = write_spec("on_axis", "", R"("grid": {"end_effector.link": ["tool_tcp", "iiwa_link_ee"]})");
  const CommandResult expanded = run_armfarm("expand " + spec);
  ASSERT_EQ(expanded.exit_code, 0) << expanded.output;
  EXPECT_NE(expanded.output.find("end_effector.link=\"tool_tcp\""), std::string::npos) << expanded.output;
  EXPECT_NE(expanded.output.find("end_effector.link=\"iiwa_link_ee\""), std::string::npos) << expanded.output;
  const CommandResult result = run_armfarm("run " + spec + " --db " + db("on_axis") + " -j 2 --quiet");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("sweep on_axis: 2 done, 0 failed, 0 diverged"), std::string::npos) << result.output;
}

TEST_F(CmdRunEndEffector, ShardedRunAndSlurmScriptsCostTheJobsOnTheChosenArm) {
  const std::string spec = write_spec("sharded", R"(, "end_effector": {"link": "iiwa_link_ee"})",
                                      R"("grid": {"control.gain_scale": [0.2, 0.5, 1.0]})");
  // What each array task of `armfarm slurm` runs: a shard, dealt by the jobs' estimated costs.
  const CommandResult shard = run_armfarm("run " + spec + " --shard 1/2 --db " + db("shard1") + " -j 2 --quiet");
  EXPECT_EQ(shard.exit_code, 0) << shard.output;
  EXPECT_NE(shard.output.find(" done, 0 failed, 0 diverged"), std::string::npos) << shard.output;
  EXPECT_NE(shard.output.find("of 3 jobs in this shard"), std::string::npos) << shard.output;
  const CommandResult slurm = run_armfarm("slurm " + spec + " --db " + db("cluster") + " --tasks 2");
  EXPECT_EQ(slurm.exit_code, 0) << slurm.output;
  EXPECT_TRUE(std::filesystem::exists(db("cluster") + ".array.sbatch")) << slurm.output;
}

TEST_F(CmdRunEndEffector, MissingChoiceIsRefusedAtExpansionNamingTheSpecTheLeavesAndTheKey) {
  const std::string spec = write_spec("no_choice", "", R"("grid": {"control.gain_scale": [0.2, 1.0]})");
  for (const std::string& command : {"run " + spec + " --db " + db("no_choice"), "expand " + spec,
                                     "slurm " + spec + " --db " + db("no_choice") + " --tasks 2"}) {
    SCOPED_TRACE(command);
    const CommandResult result = run_armfarm(command);
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_EQ(result.output.rfind("armfarm: " + spec + ": base.end_effector.link: ", 0), 0u) << result.output;
    EXPECT_NE(result.output.find("kuka_iiwa14.urdf: 2 leaf links ('iiwa_link_ee', 'tool_tcp'): set end_effector.link"),
              std::string::npos)
        << result.output;
    EXPECT_EQ(count_lines(result.output), 1) << result.output;
  }
  EXPECT_FALSE(std::filesystem::exists(db("no_choice"))) << "nothing is written for a refused sweep";
  EXPECT_FALSE(std::filesystem::exists(db("no_choice") + ".array.sbatch"));
}

TEST_F(CmdRunEndEffector, UnknownLinkOnAGridAxisIsRefusedNamingTheAxisValue) {
  const std::string spec = write_spec("unknown", "", R"("grid": {"end_effector.link": ["tool_tcp", "flange"]})");
  const CommandResult result = run_armfarm("run " + spec + " --db " + db("unknown"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_EQ(result.output.rfind("armfarm: " + spec + ": sweep.grid[\"end_effector.link\"][1]: ", 0), 0u) << result.output;
  EXPECT_NE(result.output.find("no link 'flange' (leaf links: 'iiwa_link_ee', 'tool_tcp')"), std::string::npos) << result.output;
  EXPECT_EQ(count_lines(result.output), 1) << result.output;
  EXPECT_FALSE(std::filesystem::exists(db("unknown")));
}

}  // namespace
