// `armfarm version`: the build's provenance (version, git commit, compiler, Simbody).
#include "runner/cli/subcommand.hpp"
#include "runner/execution/provenance.hpp"

#include <iostream>

namespace armfarm::cli {

RunFunction setup_version(CLI::App& parent) {
  parent.add_subcommand("version", "Print armfarm's version, git commit, compiler and Simbody version");
  return [] {
    const Provenance build = make_provenance();
    std::cout << "armfarm " << build.armfarm_version << " (" << build.git_commit << (build.git_dirty ? ", dirty" : "")
              << ")\n"
              << "compiler " << build.compiler << ", Simbody " << build.simbody_version << "\n";
    return 0;
  };
}

}  // namespace armfarm::cli
