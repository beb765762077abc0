#pragma once
// Sweep specs with stages (sweeps/README.md, "Two-stage experiments"): a list of sweeps that run
// one after the other, a later stage's jobs starting from the models an earlier stage stored:
//
//   {"name": "reach_then_recorded", "base": {...shared...},
//    "stages": [{"name": "train", "base": {"learning": {"store_model": true}}, "sweep": {...}},
//               {"name": "test",  "base": {"learning": {"mode": "frozen",
//                                   "initial_model": {"stage": "train", "params": {...}}}}, "sweep": {...}}]}
//
// Each stage is an ordinary sweep named "<name>.<stage>" whose base is the top-level base with
// the stage's base merged over it (objects merge key by key, the stage's values win), with the
// top-level include and description. A {"stage": S, "params": P} reference becomes the stored-model
// reference {"sweep": "<name>.S", "params": P} (runner/execution/stored_models.hpp); S must be an
// earlier stage.
#include "runner/spec/config_schema.hpp"
#include "runner/spec/sweep_spec.hpp"

#include <string>
#include <vector>

namespace armfarm {

/// The stages of the spec file at `path` in run order; a spec without "stages" is one stage, the
/// spec itself (load_sweep_spec). Every stage's spec is parsed and checked now (its stored-model
/// references resolve only when it expands). Each stage keeps the whole file as its text.
/// Throws SpecError naming the file and the stage.
std::vector<SweepSpec> load_sweep_stages(const std::string& path, const JobConfigSchema& schema);

/// The same for a spec given as text (`file` names it in messages, `folder` resolves its paths).
std::vector<SweepSpec> parse_sweep_stages(const std::string& text, const std::string& file, const std::string& folder,
                                          const JobConfigSchema& schema);

}  // namespace armfarm
