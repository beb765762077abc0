#include "runner/execution/provenance.hpp"

// The only file that includes the generated build_info.hpp (runner/CMakeLists.txt), which a
// re-configure after a commit rewrites: this small file recompiles then, not the CLI's units or
// main.cpp, which print the build's provenance from make_provenance().
#include "runner/build_info.hpp"

#include <unistd.h>

namespace armfarm {

Provenance make_provenance() {
  Provenance provenance;
  provenance.armfarm_version = build_info::version;
  provenance.git_commit = build_info::git_commit;
  provenance.git_dirty = build_info::git_dirty;
  provenance.compiler = build_info::compiler;
  provenance.simbody_version = build_info::simbody_version;
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) == 0) provenance.host = host;
  return provenance;
}

}  // namespace armfarm
