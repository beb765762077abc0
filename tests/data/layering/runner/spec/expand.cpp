// Fixture for LayeringTest.
#include "runner/execution/job_executor.hpp"
#include "runner/config/config_schema.hpp"
