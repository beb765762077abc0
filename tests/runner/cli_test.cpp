// The CLI's top level: --help lists every subcommand, unknown ones exit 2.
#include "runner/cli/subcommand.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

namespace {

struct CommandResult {
  int exit_code;
  std::string output;
};

CommandResult run_command(const std::string& arguments) {
  const std::string command = std::string(ARMFARM_BINARY) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) output += buffer.data();
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), output};
}

TEST(Cli, HelpListsEverySubcommand) {
  const CommandResult result = run_command("--help");
  EXPECT_EQ(result.exit_code, 0);
  for (const auto& entry : armfarm::cli::all_subcommands()) {
    EXPECT_NE(result.output.find(entry.name), std::string::npos) << entry.name;
  }
}

TEST(Cli, EverySubcommandHasHelp) {
  for (const auto& entry : armfarm::cli::all_subcommands()) {
    const CommandResult result = run_command(std::string(entry.name) + " --help");
    EXPECT_EQ(result.exit_code, 0) << entry.name << ": " << result.output;
  }
}

TEST(Cli, UnknownSubcommandExitsTwo) {
  const CommandResult result = run_command("no-such-command");
  EXPECT_EQ(result.exit_code, 2) << result.output;
}

}  // namespace
