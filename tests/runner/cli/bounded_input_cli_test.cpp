// Bounded input through the CLI, as issue 30 wrote the cases ("Messages that break the one-line
// rule, and silent acceptance"): each is one line naming the spec place or option, exit 2.
//   - a huge path index printed "armfarm: stoull";
//   - --max-jobs 18446744073709551615 printed "armfarm: vector::reserve";
//   - a seed of 2^63 was echoed as -9223372036854775808;
//   - a CSV value 1e-400 was "not a finite number";
//   - a CSV without a header row lost its first sample;
//   - a two-row recorded CSV passed validation and failed at run time;
//   - a 10 000-link URDF took 20 s to expand (now refused at once, naming the count).
#include <gtest/gtest.h>

#include "support/big_models.hpp"
#include "support/command_line.hpp"
#include "support/scratch_file.hpp"

#include <filesystem>
#include <fstream>
#include <string>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

class BoundedInputCli : public ::testing::Test {
 protected:
  void SetUp() override { folder_ = test_support::make_scratch_folder("bounded_input"); }
  void TearDown() override { fs::remove_all(folder_); }

  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(folder_ / name, std::ios::binary) << text;
    return (folder_ / name).string();
  }

  // `armfarm expand SPEC EXTRA` with the spec text written first; asserts exit 2 and one line.
  std::string refused(const std::string& spec_text, const std::string& extra = "") {
    const std::string spec = write("spec.json", spec_text);
    const test_support::CommandResult result = test_support::run_armfarm("expand '" + spec + "' " + extra);
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_EQ(result.output.find('\n'), result.output.size() - 1) << result.output;  // one line
    EXPECT_EQ(result.output.rfind("armfarm: " + spec + ": ", 0), 0u) << result.output;
    return result.output;
  }

  // A spec replaying `csv` (one joint column) on the LWR's first joint.
  std::string recorded_spec(const std::string& csv) {
    const std::string file = write("motion.csv", csv);
    return R"({"name": "rec", "base": {"model": ")" + std::string(ARMFARM_SOURCE_DIR) +
           R"(/models/dlr_lwr3.urdf", "active_joints": [1], "trajectory": {"kind": "recorded", "recorded": {"file": ")" + file +
           R"(", "sample_rate": 100, "task_space": false}}}})";
  }

  fs::path folder_;
};

TEST_F(BoundedInputCli, HugePathIndexNamesThePath) {
  const std::string out = refused(R"({"name": "idx", "sweep": {"grid": {"control.kp[99999999999999999999999]": [1.0]}}})");
  EXPECT_NE(out.find(R"(sweep.grid["control.kp[99999999999999999999999]"]: )"), std::string::npos) << out;
  EXPECT_NE(out.find("index 99999999999999999999999 is too large for an array index"), std::string::npos) << out;
  EXPECT_EQ(out.find("stoull"), std::string::npos) << out;
}

TEST_F(BoundedInputCli, MaxJobsAtUint64MaxNamesTheOptionAndTheCeiling) {
  // 10^6 random samples × 10^5 repeats × 2 × 2 grid values: 4·10^11 jobs.
  const std::string out =
      refused(R"({"name": "many", "sweep": {"random": {"samples": 1000000, "params": {"control.gain_scale": {"uniform": [0.5, 1.0]}}},
                  "repeat": 100000, "grid": {"learning.lwpr.init_D": [0.1, 0.2], "trajectory.sine.duration": [1, 2]}}})",
              "--max-jobs 18446744073709551615");
  EXPECT_NE(out.find("sweep: expands to 400000000000 jobs, over armfarm's ceiling of 10000000 jobs per sweep (--max-jobs "
                     "18446744073709551615 cannot raise it past that"),
            std::string::npos)
      << out;
  EXPECT_EQ(out.find("reserve"), std::string::npos) << out;
}

TEST_F(BoundedInputCli, SeedOfTwoToTheSixtyThreeIsRefusedAsWritten) {
  std::string out = refused(R"({"name": "s", "sweep": {"repeat": [1, 9223372036854775808]}})");
  EXPECT_NE(out.find("sweep.repeat[1]: seed 9223372036854775808 is outside the seed range [0, 9.2e+18]"), std::string::npos) << out;
  out = refused(R"({"name": "s", "base": {"seed": 9223372036854775808}})");
  EXPECT_NE(out.find("base.seed: 9223372036854775808 does not fit a 64-bit signed integer"), std::string::npos) << out;
  EXPECT_EQ(out.find("-9223372036854775808"), std::string::npos) << out;
}

TEST_F(BoundedInputCli, CsvUnderflowIsSaidToUnderflow) {
  const std::string out = refused(recorded_spec("q1\n0.1\n1e-400\n0.2\n"));
  EXPECT_NE(out.find("motion.csv:3: column 'q1': '1e-400' underflows to zero"), std::string::npos) << out;
}

TEST_F(BoundedInputCli, CsvWithoutHeaderRowIsRefusedAtItsFirstLine) {
  const std::string out = refused(recorded_spec("0.1\n0.2\n0.3\n"));
  EXPECT_NE(out.find("motion.csv:1: no header row: the first row holds numbers"), std::string::npos) << out;
}

TEST_F(BoundedInputCli, RecordedCsvTooShortForItsFilterFailsValidation) {
  const std::string out = refused(recorded_spec("q1\n0.1\n0.2\n"));
  EXPECT_NE(out.find("base.trajectory.recorded.file: "), std::string::npos) << out;
  EXPECT_NE(out.find("motion.csv is too short for its filter: 2 rows at 100 Hz are 2 control ticks of 0.01 s, fewer than the "
                     "Savitzky–Golay window of 15"),
            std::string::npos)
      << out;
  // Long enough (15 ticks at 100 Hz and dt 0.01 s): expands.
  std::string rows = "q1\n";
  for (int i = 0; i < 15; ++i) rows += std::to_string(0.01 * i) + "\n";
  const std::string spec = write("spec.json", recorded_spec(rows));
  EXPECT_EQ(test_support::run_armfarm("expand '" + spec + "'").exit_code, 0);
}

TEST_F(BoundedInputCli, TenThousandLinkUrdfIsRefusedNamingTheCount) {
  write("big.urdf", test_support::make_big_urdf(10000, false));
  const std::string out = refused(R"({"name": "big", "base": {"model": "big.urdf"}})");
  EXPECT_NE(out.find("big.urdf: 10001 links, over the cap of 1000 per arm model"), std::string::npos) << out;
}

}  // namespace
}  // namespace armfarm
