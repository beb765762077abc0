#pragma once
// Why a sweep has new jobs: a job whose key the database lacks, while the sweep's stored jobs
// hold one with the same parameters and the same configuration apart from its input files, is
// new because an input file (model, mesh, recorded trajectory, include) changed.
#include "runner/spec/sweep_expansion.hpp"

#include <map>
#include <string>

namespace armfarm {

struct InputChangeReport {
  int changed = 0;                    ///< jobs new because an input changed
  std::map<std::string, int> inputs;  ///< per input name ("model", "include[0]", …): jobs where its hash differs
};

/// Compares `sweep` with what the database at `db_path` holds for a sweep of the same name. A
/// missing or unreadable database gives an empty report (the run reports its own errors).
InputChangeReport find_input_changes(const ExpandedSweep& sweep, const std::string& db_path);

/// "3 jobs are new because an input file changed (model: 3)", or "" when none are.
std::string make_input_change_text(const InputChangeReport& report);

}  // namespace armfarm
