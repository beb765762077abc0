// Fixture for LayeringTest: the configuration reader may use the spec layer, not the execution.
#include "runner/spec/input_files.hpp"
#include "runner/execution/job_kind.hpp"
