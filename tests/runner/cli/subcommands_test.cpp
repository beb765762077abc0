// The CLI's top level: --help lists every subcommand, unknown ones exit 2.
#include "runner/cli/subcommand.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_armfarm;

namespace {

TEST(Cli, HelpListsEverySubcommand) {
  const CommandResult result = run_armfarm("--help");
  EXPECT_EQ(result.exit_code, 0);
  for (const auto& entry : armfarm::cli::all_subcommands()) {
    EXPECT_NE(result.output.find(entry.name), std::string::npos) << entry.name;
  }
}

TEST(Cli, EverySubcommandHasHelp) {
  for (const auto& entry : armfarm::cli::all_subcommands()) {
    const CommandResult result = run_armfarm(std::string(entry.name) + " --help");
    EXPECT_EQ(result.exit_code, 0) << entry.name << ": " << result.output;
  }
}

TEST(Cli, UnknownSubcommandExitsTwo) {
  const CommandResult result = run_armfarm("no-such-command");
  EXPECT_EQ(result.exit_code, 2) << result.output;
}

}  // namespace
