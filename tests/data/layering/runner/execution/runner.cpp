// Fixture for LayeringTest: execution may use the spec and configuration layers, not the CLI above it.
#include "runner/spec/sweep_expansion.hpp"
#include "runner/config/job_config_json.hpp"
#include "runner/cli/subcommand.hpp"
