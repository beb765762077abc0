// `armfarm version`: the build's provenance (version, git commit, compiler, Simbody).
#include "runner/build_info.hpp"
#include "runner/cli/subcommand.hpp"

#include <iostream>

namespace armfarm::cli {

RunFunction setup_version(CLI::App& parent) {
  parent.add_subcommand("version", "Print armfarm's version, git commit, compiler and Simbody version");
  return [] {
    std::cout << "armfarm " << build_info::version << " (" << build_info::git_commit
              << (build_info::git_dirty ? ", dirty" : "") << ")\n"
              << "compiler " << build_info::compiler << ", Simbody " << build_info::simbody_version << "\n";
    return 0;
  };
}

}  // namespace armfarm::cli
