#pragma once
// parse_sweep_spec with a choice of whether its messages give the line and column of the value
// they name. A staged spec (sweep_stages.cpp) checks each stage as a merged document of its
// own, whose positions would point into text the user never wrote: it asks for none, so that
// nothing has to cut them out of the messages afterwards.
#include "runner/spec/sweep_spec.hpp"

#include <string>

namespace armfarm {

/// Whether a spec's messages end with " (line L, column C)" of the value they name.
enum class SpecPositions { given, omitted };

/// parse_sweep_spec (sweep_spec.hpp), its messages with or without the value's position.
SweepSpec parse_sweep_spec(const std::string& text, const std::string& file, const std::string& folder,
                           const JobConfigSchema& schema, SpecPositions positions);

}  // namespace armfarm
