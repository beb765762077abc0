#pragma once
// The provenance recorded with every sweep run: this build (runner/build_info.hpp) and host.
#include "results/results_store.hpp"

namespace armfarm {

/// Version, git commit and dirty flag, compiler, Simbody version of this build; the host name.
Provenance make_provenance();

}  // namespace armfarm
