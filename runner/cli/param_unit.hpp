#pragma once
// The unit of a swept parameter for axis labels (PlotRequest::param_unit), from the job
// configuration's key table (engine/experiment/job_config.hpp), the one home of units.
#include <string>

namespace armfarm::cli {

/// The SI unit of the configuration key at dotted `path` ("control.kp[2]" reads "control.kp");
/// "" for a dimensionless key, a flag, a name or a path the key table lacks.
std::string find_param_unit(const std::string& path);

}  // namespace armfarm::cli
