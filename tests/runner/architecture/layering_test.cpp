// The architecture's arrows, checked on every #include of base/, engine/, results/, analysis/ and
// runner/ (README.md, "Where things are"; HELPERS' house rules): base (below every other folder,
// usable by all) depends on the standard library only; engine knows nothing of the
// runner, the store, the analysis, JSON, SQLite or TBB; results depends on nothing of ours;
// analysis on results only; engine/control not on engine/experiment; runner/spec and
// runner/config not on runner/execution; runner/search (the samplers) on none of the runner's
// other folders, the store, JSON, SQLite or TBB; only engine/physics/simbody_* include Simbody.
// A fixture tree with deliberately wrong includes proves the check fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

namespace {

struct Rule {
  std::string from;                    // files under this folder (prefix of the relative path)
  std::vector<std::string> forbidden;  // include prefixes they must not use
  std::string why;
};

const std::vector<Rule>& layering_rules() {
  static const std::vector<Rule> rules = {
      {"base/", {"engine/", "results/", "analysis/", "runner/", "nlohmann/", "sqlite3.h", "tbb/", "CLI/", "Eigen/"},
       "base/ depends on the standard library only"},
      {"engine/", {"runner/", "results/", "analysis/", "nlohmann/", "sqlite3.h", "tbb/", "CLI/"},
       "engine/ knows nothing of the runner, the store, the analysis, JSON, SQLite or TBB"},
      {"results/", {"engine/", "runner/", "analysis/"}, "results/ depends on nothing of ours"},
      {"analysis/", {"engine/", "runner/"}, "analysis/ depends on results/ only"},
      {"engine/control/", {"engine/experiment/"}, "control is a part the experiment assembles, not the other way"},
      {"runner/spec/", {"runner/execution/", "runner/cli/"}, "spec expansion does not know how jobs run"},
      {"runner/config/", {"runner/execution/", "runner/cli/"}, "configuration does not know how jobs run"},
      {"runner/search/", {"runner/execution/", "runner/cli/", "runner/spec/", "runner/config/", "results/", "analysis/", "nlohmann/", "sqlite3.h", "tbb/"},
       "the samplers are pure: no spec, store, JSON, SQLite or threads"},
  };
  return rules;
}

const std::vector<std::string> kSimbodyHeaders = {"Simbody.h", "SimTKcommon", "SimTKmath", "SimTKsimbody", "simbody/"};

bool starts_with(const std::string& text, const std::string& prefix) { return text.compare(0, prefix.size(), prefix) == 0; }

// One line per wrong include: "engine/a.hpp:3: includes runner/b.hpp: engine/ knows nothing of ...".
std::vector<std::string> find_layering_violations(const std::filesystem::path& root) {
  const std::regex include_line(R"(^\s*#\s*include\s*[<"]([^>"]+)[>"])");
  std::vector<std::string> violations;
  for (const char* top : {"base", "engine", "results", "analysis", "runner"}) {
    if (!std::filesystem::exists(root / top)) continue;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root / top)) {
      const std::string extension = entry.path().extension().string();
      if (!entry.is_regular_file() || (extension != ".hpp" && extension != ".cpp" && extension != ".h" && extension != ".in")) continue;
      const std::string file = std::filesystem::relative(entry.path(), root).generic_string();
      std::ifstream in(entry.path());
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        std::smatch match;
        if (!std::regex_search(line, match, include_line)) continue;
        const std::string include = match[1].str();
        std::vector<std::string> why;
        for (const Rule& rule : layering_rules()) {
          if (!starts_with(file, rule.from)) continue;
          for (const std::string& prefix : rule.forbidden) {
            if (starts_with(include, prefix)) why.push_back(rule.why);
          }
        }
        const bool simbody_file = starts_with(file, "engine/physics/simbody_");
        for (const std::string& header : kSimbodyHeaders) {
          if (!simbody_file && starts_with(include, header)) why.push_back("only engine/physics/simbody_* include Simbody");
        }
        if (why.empty()) continue;
        violations.push_back(file + ":" + std::to_string(number) + ": includes " + include + ": " + why.front());
      }
    }
  }
  std::sort(violations.begin(), violations.end());
  return violations;
}

TEST(LayeringTest, RealTreeFollowsTheArchitecture) {
  const std::vector<std::string> violations = find_layering_violations(ARMFARM_SOURCE_DIR);
  std::string text;
  for (const std::string& v : violations) text += v + "\n";
  EXPECT_TRUE(violations.empty()) << text;
  // The engine, the runner and the checker's folders were read (a typo in a folder name would pass silently).
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(ARMFARM_SOURCE_DIR) / "engine/control"));
}

TEST(LayeringTest, FixtureWithWrongIncludesFails) {
  const std::vector<std::string> violations =
      find_layering_violations(std::filesystem::path(ARMFARM_TEST_DATA_DIR) / "layering");
  const std::vector<std::string> expected = {
      "analysis/table.cpp:3: includes engine/model/arm_model.hpp: analysis/ depends on results/ only",
      "base/text.hpp:3: includes engine/io/number_text.hpp: base/ depends on the standard library only",
      "engine/control/gains.hpp:3: includes runner/spec/sweep_spec.hpp: engine/ knows nothing of the runner, the store, the analysis, JSON, SQLite or TBB",
      "engine/control/gains.hpp:4: includes nlohmann/json.hpp: engine/ knows nothing of the runner, the store, the analysis, JSON, SQLite or TBB",
      "engine/control/gains.hpp:5: includes engine/experiment/run_experiment.hpp: control is a part the experiment assembles, not the other way",
      "engine/control/gains.hpp:6: includes Simbody.h: only engine/physics/simbody_* include Simbody",
      "results/store.cpp:2: includes engine/model/arm_model.hpp: results/ depends on nothing of ours",
      "runner/search/sampler.cpp:3: includes nlohmann/json.hpp: the samplers are pure: no spec, store, JSON, SQLite or threads",
      "runner/spec/expand.cpp:2: includes runner/execution/job_executor.hpp: spec expansion does not know how jobs run",
  };
  EXPECT_EQ(violations, expected);
}

}  // namespace
