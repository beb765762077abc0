// `armfarm merge` through the command line on small generated databases.
#include "support/test_database.hpp"

#include <gtest/gtest.h>

#include <string>

namespace armfarm {
namespace {

// Timings (learner_us_per_update) are not results: two runs that differ only there merge as
// identical, and compare agrees.
TEST(CmdMerge, RunsDifferingOnlyInTimingMergeWithoutConflictAndExitZero) {
  testing::TemporaryDirectory directory;
  testing::write_test_sweep(directory.file("a.db"), "gains", testing::make_gain_jobs(true, 20.0));
  testing::write_test_sweep(directory.file("b.db"), "gains", testing::make_gain_jobs(true, 31.0));
  const auto merged = testing::run_armfarm("merge " + directory.file("out.db") + " " + directory.file("a.db") + " " +
                                           directory.file("b.db"));
  EXPECT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(merged.output.find("conflict:"), std::string::npos) << merged.output;
  EXPECT_NE(merged.output.find("4 identical, 0 conflicts"), std::string::npos) << merged.output;
  // compare agrees: timing is not a result.
  EXPECT_EQ(testing::run_armfarm("compare " + directory.file("a.db") + " " + directory.file("b.db")).exit_code, 0);
}

}  // namespace
}  // namespace armfarm
