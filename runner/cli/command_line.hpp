#pragma once
// armfarm's command line as a function of the runner library, so that the executables' main.cpp
// includes no CLI11 (header-only: every file that includes it compiles its inline code again).

namespace armfarm::cli {

/// Parses `argv` against the subcommand table (subcommands.cpp), runs the chosen subcommand and
/// returns armfarm's exit status (subcommand.hpp; a usage error or an escaping exception: one
/// line on standard error, 2).
int run_main(int argc, char** argv);

}  // namespace armfarm::cli
