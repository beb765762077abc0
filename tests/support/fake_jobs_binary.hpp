// Where the tests find armfarm_fakejobs: the armfarm command line running the runner's fake job
// instead of the experiment (runner/execution/job_kind.hpp), a test-only binary built beside
// armfarm. Defined in the generated test_paths.cpp (tests/CMakeLists.txt), like test_paths.hpp's
// paths; declared here, not there, so that the objects of tests that never run it are unchanged.
#pragma once

namespace armfarm::test_paths {
const char* fake_jobs_binary();  ///< armfarm_fakejobs, built beside the tests
}  // namespace armfarm::test_paths

#define ARMFARM_FAKE_JOBS_BINARY (::armfarm::test_paths::fake_jobs_binary())
