// Fixture for LayeringTest.
#include "runner/execution/job_executor.hpp"
#include "runner/spec/config_schema.hpp"
#include "runner/config/job_config_json.hpp"
