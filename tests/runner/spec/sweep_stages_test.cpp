// Specs with stages (runner/spec/sweep_stages.hpp): a stage's problems name the file and the
// stage, and leave out the "(line L, column C)" that a plain spec's problems end with (it would
// point into the stage's merged document, not into the file).
#include "runner/spec/sweep_stages.hpp"

#include "support/fake_job.hpp"
#include "runner/spec/spec_error.hpp"

#include <gtest/gtest.h>

#include "support/test_database.hpp"

#include <fstream>

#include <string>
#include <vector>

namespace armfarm {
namespace {

std::vector<std::string> collect_stage_errors(const std::string& text) {
  try {
    parse_sweep_stages(text, "staged.json", ".", make_fake_job_config_schema());
  } catch (const SpecError& error) {
    return error.lines();
  }
  return {};
}

std::vector<std::string> collect_plain_errors(const std::string& text) {
  try {
    parse_sweep_spec(text, "plain.json", ".", make_fake_job_config_schema());
  } catch (const SpecError& error) {
    return error.lines();
  }
  return {};
}

const char kProblem[] = "base.control.gain_scal: unknown key (did you mean 'gain_scale'?)";

TEST(SweepStages, AStageProblemNamesTheStageAndDropsOnlyThePosition) {
  const std::vector<std::string> plain = collect_plain_errors(R"({"name": "p", "base": {"control": {"gain_scal": 2}}})");
  ASSERT_EQ(plain.size(), 1u);
  // The plain spec's line: the problem, then its position in the file.
  const std::string plain_head = std::string("plain.json: ") + kProblem + " (line 1, column ";
  EXPECT_EQ(plain[0].compare(0, plain_head.size(), plain_head), 0) << plain[0];
  EXPECT_EQ(plain[0].back(), ')') << plain[0];

  const std::vector<std::string> staged = collect_stage_errors(R"({"name": "s", "stages": [
      {"name": "a"},
      {"name": "b", "base": {"control": {"gain_scal": 2}}}]})");
  ASSERT_EQ(staged.size(), 1u);
  // The did-you-mean in parentheses at the end stays; only the position went.
  EXPECT_EQ(staged[0], std::string("staged.json: stages[1] (b, merged with the top-level base): ") + kProblem);
}

TEST(SweepStages, EachStageWithAProblemHasItsLine) {
  const std::vector<std::string> staged = collect_stage_errors(R"({"name": "s", "stages": [
      {"name": "a", "base": {"control": {"gain_scal": 2}}},
      {"name": "b", "base": {"control": {"gain_scal": 3}}}]})");
  ASSERT_EQ(staged.size(), 2u);
  EXPECT_EQ(staged[0], std::string("staged.json: stages[0] (a, merged with the top-level base): ") + kProblem);
  EXPECT_EQ(staged[1], std::string("staged.json: stages[1] (b, merged with the top-level base): ") + kProblem);
}

// An include's problem has a place in a file the user wrote, and a plain spec gives it; a staged
// spec's parser gives none for it either (SpecPositions::omitted), as it did when the positions
// were cut out of the messages afterwards.
TEST(SweepStages, AnIncludesProblemInAStageHasNoPositionAndIsOtherwiseThePlainLine) {
  testing::TemporaryDirectory dir;
  std::ofstream(dir.file("inc.json")) << "{\"control\": {\"gain_scal\": 2}}";
  const std::string include_line = dir.file("inc.json") + ": control.gain_scal: unknown key (did you mean 'gain_scale'?)";
  std::vector<std::string> plain, staged;
  try {
    parse_sweep_spec(R"({"name": "p", "include": "inc.json"})", "plain.json", dir.path.string(), make_fake_job_config_schema());
  } catch (const SpecError& error) {
    plain = error.lines();
  }
  try {
    parse_sweep_stages(R"({"name": "s", "include": "inc.json", "stages": [{"name": "a"}]})", "staged.json", dir.path.string(),
                       make_fake_job_config_schema());
  } catch (const SpecError& error) {
    staged = error.lines();
  }
  ASSERT_EQ(plain.size(), 1u);
  EXPECT_EQ(plain[0], include_line + " (line 1, column 27)");
  EXPECT_EQ(staged, std::vector<std::string>{include_line});
}

}  // namespace
}  // namespace armfarm
