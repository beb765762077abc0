#include "runner/cli/command_line.hpp"

#include "analysis/printable_text.hpp"
#include "engine/io/message_text.hpp"
#include "runner/cli/subcommand.hpp"
#include "runner/execution/provenance.hpp"

#include <exception>
#include <iostream>

namespace armfarm::cli {

int run_main(int argc, char** argv) {
  CLI::App app{"armfarm: parameter sweeps of learned motor control on simulated robot arms"};
  app.require_subcommand(1);
  // A command-line error is one line, like every other error (CLI11's default adds a second,
  // "Run with --help for more information."). Set before the subcommands are made: they copy it.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "armfarm: " + cap_message_line(e.what()) + " (--help lists the options)\n";
  });
  app.fallthrough(false);
  const Provenance build = make_provenance();
  app.set_version_flag("--version",
                       "armfarm " + build.armfarm_version + " (" + build.git_commit + (build.git_dirty ? ", dirty" : "") + ")",
                       "Print armfarm's version and git commit and exit (`armfarm version` says more)");

  std::vector<std::pair<CLI::App*, RunFunction>> runs;
  for (const auto& entry : all_subcommands()) {
    const std::size_t before = app.get_subcommands({}).size();
    RunFunction run = entry.setup(app);
    const auto subs = app.get_subcommands({});
    if (subs.size() > before) runs.emplace_back(subs.back(), std::move(run));
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  try {
    for (auto& [sub, run] : runs) {
      if (sub->parsed()) return run();
    }
  } catch (const std::exception& e) {
    // One line, capped and printed as text: a message may quote a huge input or a name from
    // someone else's database.
    std::cerr << "armfarm: " << cap_message_line(make_printable_text(e.what())) << "\n";
    return 2;
  }
  return 2;
}

}  // namespace armfarm::cli
