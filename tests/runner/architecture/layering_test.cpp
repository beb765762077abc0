// The architecture's arrows, checked on every #include of base/, engine/, results/, analysis/ and
// runner/ (README.md, "The arrows"; HELPERS' house rules). From the bottom:
//   base/      (header-only) the standard library only; every other folder may include it;
//   engine/    base/ only of ours: nothing of the runner, the store, the analysis, JSON, SQLite or
//              TBB; inside it each folder includes only the engine folders below it
//              (kEngineFolders: config, io, random and learner/ at the bottom, lwpr/ and ssgpr/
//              on learner/, learning/ above them, experiment/ on top; a folder missing from the
//              table fails); only engine/physics/simbody_* include Simbody;
//   results/   base/ only;
//   analysis/  results/ and base/ only;
//   runner/    anything below; inside it runner/spec (sweep specs, expansion, job keys, and the
//              schema interface a job kind fills in) on none of runner/config, runner/execution
//              or runner/cli, runner/config (the experiment job's configuration as JSON) on
//              runner/spec but not on runner/execution or runner/cli, runner/execution not on
//              runner/cli, runner/io (CSV reading and writing) on none of the runner's other
//              folders, runner/search (the samplers) on none of the runner's other folders, the
//              store, JSON, SQLite or TBB.
// A fixture tree with deliberately wrong includes proves the check fails (and its includes of
// base/ from results/ and analysis/, and of runner/spec from runner/config, that it passes).
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
      {"results/", {"engine/", "runner/", "analysis/"}, "results/ depends on base/ only"},
      {"analysis/", {"engine/", "runner/"}, "analysis/ depends on results/ and base/ only"},
      {"runner/spec/", {"runner/execution/", "runner/cli/"}, "spec expansion does not know how jobs run"},
      {"runner/spec/", {"runner/config/"},
       "spec expansion sees a job's configuration only through its schema (runner/spec/config_schema.hpp)"},
      {"runner/config/", {"runner/execution/", "runner/cli/"}, "configuration does not know how jobs run"},
      {"runner/execution/", {"runner/cli/"}, "execution does not know the command line above it"},
      {"runner/io/", {"runner/spec/", "runner/config/", "runner/execution/", "runner/cli/", "runner/search/"},
       "the CSV layer uses none of the runner's other folders"},
      {"runner/search/", {"runner/execution/", "runner/cli/", "runner/spec/", "runner/config/", "results/", "analysis/", "nlohmann/", "sqlite3.h", "tbb/"},
       "the samplers are pure: no spec, store, JSON, SQLite or threads"},
  };
  return rules;
}

// The engine's inner arrows: each folder of engine/ with the engine folders it may include (its own
// always). A folder not listed fails, so a new one takes its place in the order here.
struct EngineFolder {
  std::string name;
  std::vector<std::string> may_include;
};

const std::vector<EngineFolder>& engine_folders() {
  static const std::vector<EngineFolder> folders = {
      {"config", {}},
      {"io", {}},
      {"random", {}},
      {"learner", {}},
      {"model", {"config", "io"}},
      {"physics", {"config", "model"}},
      {"kinematics", {"model", "physics"}},
      {"trajectory", {"config", "kinematics", "model", "physics", "random"}},
      {"control", {"config", "model", "physics"}},
      {"lwpr", {"learner"}},
      {"ssgpr", {"learner", "random"}},
      {"learning", {"config", "learner", "lwpr", "ssgpr"}},
      {"experiment", {"config", "io", "random", "learner", "model", "physics", "kinematics", "trajectory", "control", "lwpr", "ssgpr", "learning"}},
  };
  return folders;
}

/// The folder after "engine/" in a path ("engine/lwpr/x.hpp" -> "lwpr"); empty for other paths.
std::string engine_folder_of(const std::string& path) {
  if (path.compare(0, 7, "engine/") != 0) return {};
  const std::size_t slash = path.find('/', 7);
  return slash == std::string::npos ? std::string() : path.substr(7, slash - 7);
}

/// Why `file` may not include `include` by the engine's inner arrows; empty when it may.
std::string check_engine_arrow(const std::string& file, const std::string& include) {
  const std::string from = engine_folder_of(file), to = engine_folder_of(include);
  if (from.empty() || to.empty() || from == to) return {};
  const auto& folders = engine_folders();
  const auto entry = std::find_if(folders.begin(), folders.end(), [&](const EngineFolder& f) { return f.name == from; });
  if (entry == folders.end()) return "engine/" + from + "/ is not in the engine's layering table";
  if (std::find(entry->may_include.begin(), entry->may_include.end(), to) != entry->may_include.end()) return {};
  std::string allowed;
  for (const std::string& name : entry->may_include) allowed += (allowed.empty() ? "" : ", ") + name;
  return "engine/" + from + "/ includes only engine/{" + allowed + "}/ (the engine's inner arrows)";
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
        if (std::string inner = check_engine_arrow(file, include); !inner.empty()) why.push_back(inner);
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
  // Every folder of the engine has its row in the table (the check above would name a missing one
  // only once it includes another folder), and every row names a folder that exists.
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(ARMFARM_SOURCE_DIR) / "engine")) {
    if (!entry.is_directory()) continue;
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(std::any_of(engine_folders().begin(), engine_folders().end(), [&](const EngineFolder& f) { return f.name == name; }))
        << "engine/" << name << "/ is not in the engine's layering table";
  }
  for (const EngineFolder& folder : engine_folders()) {
    EXPECT_TRUE(std::filesystem::is_directory(std::filesystem::path(ARMFARM_SOURCE_DIR) / "engine" / folder.name)) << folder.name;
  }
}

TEST(LayeringTest, FixtureWithWrongIncludesFails) {
  const std::vector<std::string> violations =
      find_layering_violations(std::filesystem::path(ARMFARM_TEST_DATA_DIR) / "layering");
  const std::vector<std::string> expected = {
      "analysis/table.cpp:3: includes engine/model/arm_model.hpp: analysis/ depends on results/ and base/ only",
      "base/text.hpp:3: includes engine/io/number_text.hpp: base/ depends on the standard library only",
      "engine/control/gains.hpp:3: includes runner/spec/sweep_spec.hpp: engine/ knows nothing of the runner, the store, the analysis, JSON, SQLite or TBB",
      "engine/control/gains.hpp:4: includes nlohmann/json.hpp: engine/ knows nothing of the runner, the store, the analysis, JSON, SQLite or TBB",
      "engine/control/gains.hpp:5: includes engine/experiment/run_experiment.hpp: engine/control/ includes only engine/{config, model, physics}/ (the engine's inner arrows)",
      "engine/control/gains.hpp:6: includes Simbody.h: only engine/physics/simbody_* include Simbody",
      "engine/learner/learner.hpp:3: includes engine/lwpr/lwpr_model.hpp: engine/learner/ includes only engine/{}/ (the engine's inner arrows)",
      "engine/lwpr/lwpr_model.hpp:3: includes engine/learning/learner_factory.hpp: engine/lwpr/ includes only engine/{learner}/ (the engine's inner arrows)",
      "engine/plugins/extra.cpp:2: includes engine/model/arm_model.hpp: engine/plugins/ is not in the engine's layering table",
      "engine/ssgpr/ssgpr_model.hpp:3: includes engine/lwpr/lwpr_params.hpp: engine/ssgpr/ includes only engine/{learner, random}/ (the engine's inner arrows)",
      "results/store.cpp:2: includes engine/model/arm_model.hpp: results/ depends on base/ only",
      "runner/config/reader.cpp:3: includes runner/execution/job_kind.hpp: configuration does not know how jobs run",
      "runner/execution/runner.cpp:4: includes runner/cli/subcommand.hpp: execution does not know the command line above it",
      "runner/io/table_writer.cpp:4: includes runner/spec/sweep_spec.hpp: the CSV layer uses none of the runner's other folders",
      "runner/io/table_writer.cpp:5: includes runner/execution/job_kind.hpp: the CSV layer uses none of the runner's other folders",
      "runner/search/sampler.cpp:3: includes nlohmann/json.hpp: the samplers are pure: no spec, store, JSON, SQLite or threads",
      "runner/spec/expand.cpp:2: includes runner/execution/job_executor.hpp: spec expansion does not know how jobs run",
      "runner/spec/expand.cpp:4: includes runner/config/job_config_json.hpp: spec expansion sees a job's configuration only through its schema (runner/spec/config_schema.hpp)",
  };
  EXPECT_EQ(violations, expected);
}

}  // namespace
