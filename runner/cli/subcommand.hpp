#pragma once
// The armfarm CLI is a table of subcommands (subcommands.cpp), each in one small file
// cmd_<name>.cpp that registers its options on a CLI11 sub-app and returns the function
// that runs it once the command line has been parsed.
//
// Exit codes, for every subcommand: 0 success; 1 the command ran but found failures
// (failed jobs, a regressed metric); 2 bad usage or bad input (an exception escaping
// the run function is reported on one line and exits 2); 3 finished results were lost (not
// saved: a full disk), which a batch system must never count as success. A result discarded
// by the claims' fence is not lost (its job is the runner's that took the claim over): `run`
// exits 0 when such jobs are done in the file at its end, 1 when not (README.md, exit status).
#include <CLI/CLI.hpp>

#include <functional>
#include <vector>

namespace armfarm::cli {

/// The exit status of a run whose finished jobs could not all be saved.
inline constexpr int kExitResultsNotSaved = 3;

using RunFunction = std::function<int()>;
using SetupFunction = RunFunction (*)(CLI::App& parent);

struct SubcommandEntry {
  const char* name;
  SetupFunction setup;
};

/// All subcommands, in the order `armfarm --help` lists them.
const std::vector<SubcommandEntry>& all_subcommands();

}  // namespace armfarm::cli
