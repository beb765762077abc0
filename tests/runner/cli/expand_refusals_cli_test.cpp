// `armfarm expand` refuses a spec from the command line with exit 2 and one line naming the file
// and the JSON path: a search block whose objective has no direction, and a grid over the job
// limit (with --max-jobs raising it). These run the executables, so they live with the CLI tests
// and not in the spec suites, which the sanitizer subset builds without the executables.
#include "support/command_line.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace armfarm {
namespace {

TEST(ExpandRefusalsCli, ABadSearchBlockGivesExitTwoAndWritesNothing) {
  const std::filesystem::path folder = test_support::make_scratch_folder("expand refusals search");
  const std::filesystem::path file = folder / "bad search.json";  // a space in the name
  std::ofstream(file) << R"({"name": "s", "base": {"trajectory": {"kind": "reaching"},
      "learning": {"heldout_checkpoints": [10, 50, 200]}},
      "sweep": {"search": {"method": "tpe", "objective": {"metric": "n_training_samples"},
      "space": {"learning.lwpr.init_D": {"uniform": [1, 2]}}, "budget": {"jobs": 9}}}})";
  const test_support::CommandResult result = test_support::run_armfarm("expand '" + file.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(file.string() + ": sweep.search.objective.metric: 'n_training_samples' has no direction"),
            std::string::npos)
      << result.output;
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), std::filesystem::directory_iterator()), 1)
      << "expand wrote a file beside the spec";
  std::filesystem::remove_all(folder);
}

TEST(ExpandRefusalsCli, AGridOverTheJobLimitGivesExitTwoAndMaxJobsRaisesTheLimit) {
  const std::filesystem::path folder = test_support::make_scratch_folder("expand refusals grid");
  const std::string spec = (folder / "bounded_expansion.json").string();
  std::string values;
  for (int i = 0; i < 1000; ++i) values += (i ? "," : "") + std::to_string(1 + i) + ".5";
  std::ofstream(spec) << R"({"name": "big", "sweep": {"grid": {"control.gain_scale": [)" + values +
                             R"(], "trajectory.period": [)" + values + "]}}}";
  const auto refused = test_support::run_armfarm_with_fake_jobs("expand '" + spec + "'");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_EQ(refused.output, "armfarm: " + spec + ": sweep: expands to 1000000 jobs, over the limit of 100000 (--max-jobs N raises it)\n");
  const auto raised = test_support::run_armfarm_with_fake_jobs("expand '" + spec + "' --max-jobs 999999");
  EXPECT_EQ(raised.exit_code, 2) << raised.output;
  EXPECT_NE(raised.output.find("over the limit of 999999"), std::string::npos) << raised.output;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace armfarm
