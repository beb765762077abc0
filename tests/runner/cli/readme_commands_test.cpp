// Every command in README.md runs as written: the ```sh blocks are extracted and each line is
// run by bash in a fresh folder that looks like a checkout (sweeps/ and models/ linked in,
// `armfarm` on PATH), in order, so later commands use the databases earlier ones made. `make
// run` runs its Makefile recipe (the build is this test's own binary); `make test` and
// `make bench` are this suite and the benchmarks, so they are not run from inside it; blocks
// that need a cluster or an install prefix say in their fence what runs them instead.
// The quick start's 12 real jobs make this the slowest test (about 40 s on 2 idle cores).
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "support/command_line.hpp"
#include "support/text_file.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_command_line;

namespace armfarm {
namespace {

namespace fs = std::filesystem;


// The commands of the ```sh blocks, in order: blank lines left out, a line ending in a
// backslash joined with the next. A block whose fence says more than `sh` ("```sh (needs a
// Slurm cluster: make test-slurm runs it)") is not run here; its note goes to `not_run`.
std::vector<std::string> extract_shell_lines(const std::string& markdown, std::vector<std::string>* not_run = nullptr) {
  std::vector<std::string> lines;
  std::istringstream in(markdown);
  bool inside = false;
  bool runnable = false;
  std::string pending;
  for (std::string line; std::getline(in, line);) {
    if (!inside && line.rfind("```sh", 0) == 0) {
      inside = true;
      const std::size_t note = line.find_first_not_of(" \t", 5);
      runnable = note == std::string::npos;
      if (!runnable && not_run != nullptr) not_run->push_back(line.substr(note));
    } else if (inside && line.rfind("```", 0) == 0) {
      inside = false;
    } else if (inside && runnable && line.find_first_not_of(" \t") != std::string::npos) {
      if (!line.empty() && line.back() == '\\') {
        pending += line.substr(0, line.size() - 1);
        continue;
      }
      lines.push_back(pending + line);
      pending.clear();
    }
  }
  return lines;
}

// The recipe of Makefile target `target`, its $(VAR) references replaced by the `VAR ?= value`
// defaults and $(ARMFARM) by `armfarm`.
std::vector<std::string> find_make_recipe(const std::string& makefile, const std::string& target) {
  std::map<std::string, std::string> variables = {{"ARMFARM", "armfarm"}};
  const std::regex assignment(R"(^([A-Z_]+)\s*\?=\s*(.*?)\s*$)");
  std::istringstream in(makefile);
  std::vector<std::string> recipe;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    std::smatch match;
    if (std::regex_match(line, match, assignment)) variables.emplace(match[1], match[2]);
    if (line.rfind(target + ":", 0) == 0) {
      inside = true;
      continue;
    }
    if (inside && !line.empty() && line[0] == '\t') {
      // make's own syntax: '@' (do not echo), '\' continuations and '$$' (a literal '$').
      std::string command = line.substr(line.size() > 1 && line[1] == '@' ? 2 : 1);
      if (!recipe.empty() && !recipe.back().empty() && recipe.back().back() == '\\') {
        recipe.back().pop_back();
        recipe.back() += command;
      } else {
        recipe.push_back(command);
      }
    } else if (inside) {
      inside = false;
    }
  }
  for (std::string& command : recipe) {
    for (std::size_t at = command.find("$$"); at != std::string::npos; at = command.find("$$", at + 1)) command.erase(at, 1);
    for (const auto& [name, value] : variables) {
      for (std::size_t at = command.find("$(" + name + ")"); at != std::string::npos; at = command.find("$(" + name + ")")) {
        command.replace(at, name.size() + 3, value);
      }
    }
  }
  return recipe;
}

CommandResult run_in(const fs::path& folder, const fs::path& bin, const std::string& line) {
  const fs::path script = folder / ".readme_command.sh";
  std::ofstream(script) << "cd '" << folder.string() << "' && export PATH='" << bin.string() << "':\"$PATH\" && " << line
                        << "\n";
  return run_command_line("bash " + script.string());
}

TEST(Readme, EveryCommandRunsAsWritten) {
  const fs::path source = ARMFARM_SOURCE_DIR;
  std::vector<std::string> blocks_not_run;
  const std::vector<std::string> lines = extract_shell_lines(test_support::read_text_file(source / "README.md"), &blocks_not_run);
  ASSERT_GE(lines.size(), 10u) << "README.md has lost its command blocks";
  for (const std::string& note : blocks_not_run) {
    EXPECT_NE(note.find("runs it"), std::string::npos) << "a block not run here says what runs it: " << note;
  }
  const std::string makefile = test_support::read_text_file(source / "Makefile");

  const fs::path folder = fs::temp_directory_path() / ("armfarm_readme_" + std::to_string(::getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder / "bin");
  for (const char* linked : {"sweeps", "models"}) fs::create_directory_symlink(source / linked, folder / linked);
  fs::create_symlink(ARMFARM_BINARY, folder / "bin" / "armfarm");

  std::vector<std::string> not_run;
  int commands = 0;
  for (const std::string& line : lines) {
    std::smatch make;
    if (std::regex_search(line, make, std::regex(R"(^make\s+(\w+))"))) {
      const std::string target = make[1];
      if (target == "test" || target == "bench") {
        not_run.push_back(target);
        continue;
      }
      const std::vector<std::string> recipe = find_make_recipe(makefile, target);
      ASSERT_FALSE(recipe.empty()) << "make " << target << ": no recipe in the Makefile";
      for (const std::string& command : recipe) {
        const CommandResult result = run_in(folder, folder / "bin", command);
        EXPECT_EQ(result.exit_code, 0) << "README: " << line << "\n  recipe line: " << command << "\n" << result.output;
        ++commands;
      }
      continue;
    }
    const CommandResult result = run_in(folder, folder / "bin", line);
    EXPECT_EQ(result.exit_code, 0) << "README: " << line << "\n" << result.output;
    ++commands;
  }
  EXPECT_EQ(not_run, (std::vector<std::string>{"test"})) << "only `make test` (this suite) is left out";
  EXPECT_GE(commands, 12);
  if (!HasFailure()) fs::remove_all(folder);
}

TEST(Readme, ShellBlocksAndMakeRecipesAreReadAsWritten) {
  std::vector<std::string> not_run;
  EXPECT_EQ(extract_shell_lines("text\n```sh\na b\n\n  c \\\n  --x\n```\n```json\n{}\n```\n```sh (cluster: X runs it)\nsbatch\n```\n```sh\nd\n```\n",
                                &not_run),
            (std::vector<std::string>{"a b", "  c   --x", "d"}));
  EXPECT_EQ(not_run, std::vector<std::string>{"(cluster: X runs it)"});
  EXPECT_EQ(find_make_recipe("DB ?= r.db\nX = 1\nrun: build\n\t$(ARMFARM) run s --db $(DB)\n\t$(ARMFARM) table $(DB)\n\ntest:\n\tctest\n", "run"),
            (std::vector<std::string>{"armfarm run s --db r.db", "armfarm table r.db"}));
  EXPECT_EQ(find_make_recipe("run: x\n\t@printf '%s' \"$$HOME\" \\\n\t  \"b\"\n\techo\n", "run"),
            (std::vector<std::string>{"printf '%s' \"$HOME\"   \"b\"", "echo"}));
}

}  // namespace
}  // namespace armfarm
