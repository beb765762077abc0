// Where the tests find the source tree, their data and the armfarm binary under test.
// The paths live in one file generated into the build tree (tests/CMakeLists.txt) rather than in
// compile flags, so every test object is the same whichever checkout builds it and ccache shares it
// across worktrees. tests/CMakeLists.txt force-includes this header into every test binary.
#pragma once

namespace armfarm::test_paths {
const char* source_dir();     ///< the checkout's root folder
const char* test_data_dir();  ///< tests/data of that checkout
const char* binary();         ///< the armfarm executable built beside the tests
}  // namespace armfarm::test_paths

#define ARMFARM_SOURCE_DIR (::armfarm::test_paths::source_dir())
#define ARMFARM_TEST_DATA_DIR (::armfarm::test_paths::test_data_dir())
#define ARMFARM_BINARY (::armfarm::test_paths::binary())
