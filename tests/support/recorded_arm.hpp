// A scratch arm with a recorded trajectory, for the tests of jobs that read input files.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>

namespace armfarm::test_support {

/// Writes `folder`/arm.urdf (a copy of models/planar2.urdf) and `folder`/motion.csv, a joint-space
/// recording of 1 s at 100 Hz (columns q1,q2: a slow swing of both joints).
inline void write_recorded_planar_arm(const std::filesystem::path& folder) {
  std::filesystem::copy_file(std::filesystem::path(ARMFARM_SOURCE_DIR) / "models" / "planar2.urdf", folder / "arm.urdf");
  std::ofstream csv(folder / "motion.csv");
  csv << "q1,q2\n";
  for (int row = 0; row < 100; ++row) csv << 0.2 * std::sin(0.05 * row) << "," << 0.1 * std::sin(0.03 * row) << "\n";
}

}  // namespace armfarm::test_support
