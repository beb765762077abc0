// The synthetic recordings of sweeps/thesis/data (stand-ins for the thesis's tracker recordings,
// section 6.2.3) read through the recorded-trajectory CSV path: shape, sample count, the stated
// noise level, every point inside the thesis's reaching box; and the generator reproduces them.
#include "runner/io/csv_reader.hpp"

#include "support/text_file.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace armfarm::io {
namespace {

const std::string kDataDir = std::string(ARMFARM_SOURCE_DIR) + "/sweeps/thesis/data/";

struct Recording {
  const char* file;
  Eigen::Index samples;  ///< rows at 100 Hz (sweeps/thesis/data/README.md)
};

const Recording kRecordings[] = {{"picking_synthetic.csv", 1133}, {"sphere_synthetic.csv", 1651}};

constexpr double kNoiseSigma = 0.0005;  // m per axis, as the README and the generator state


TEST(SyntheticRecordings, LoadAsTaskSpaceSamplesInsideTheReachingBox) {
  for (const Recording& recording : kRecordings) {
    SCOPED_TRACE(recording.file);
    const CsvTable table = load_csv(kDataDir + recording.file);
    EXPECT_EQ(table.header, (std::vector<std::string>{"x", "y", "z"}));
    ASSERT_EQ(table.values.cols(), 3);
    EXPECT_EQ(table.values.rows(), recording.samples);
    // Section 6.2.2: 20 cm < x < 70 cm, 20 cm < y < 70 cm, 0 cm < z < 50 cm.
    const Eigen::Vector3d low(0.20, 0.20, 0.00), high(0.70, 0.70, 0.50);
    for (Eigen::Index k = 0; k < table.values.rows(); ++k) {
      for (int axis = 0; axis < 3; ++axis) {
        ASSERT_GE(table.values(k, axis), low[axis]) << "sample " << k << " axis " << axis;
        ASSERT_LE(table.values(k, axis), high[axis]) << "sample " << k << " axis " << axis;
      }
    }
  }
}

TEST(SyntheticRecordings, NoiseIsTheStatedLevel) {
  // The second difference of white noise of σ has variance 6σ²; at 100 Hz the smooth motion's
  // own second difference (a·dt², below 0.3 mm) adds well under 1 % to that.
  for (const Recording& recording : kRecordings) {
    SCOPED_TRACE(recording.file);
    const Eigen::MatrixXd x = load_csv(kDataDir + recording.file).values;
    const Eigen::Index n = x.rows();
    const Eigen::MatrixXd second = x.bottomRows(n - 2) - 2.0 * x.middleRows(1, n - 2) + x.topRows(n - 2);
    // Pooled over the axes (about 3400 values: the estimate's spread is about 2 %), and per axis
    // (about 1100 values) more loosely.
    const double pooled = std::sqrt(second.squaredNorm() / (6.0 * 3.0 * static_cast<double>(n - 2)));
    EXPECT_NEAR(pooled, kNoiseSigma, 0.06 * kNoiseSigma);
    for (int axis = 0; axis < 3; ++axis) {
      const double sigma = std::sqrt(second.col(axis).squaredNorm() / (6.0 * static_cast<double>(n - 2)));
      EXPECT_NEAR(sigma, kNoiseSigma, 0.15 * kNoiseSigma) << "axis " << axis;
    }
    // And the motion itself is much larger than the noise: the recording moves.
    const Eigen::RowVector3d range = x.colwise().maxCoeff() - x.colwise().minCoeff();
    EXPECT_GT(range.maxCoeff(), 0.15);
  }
}

TEST(SyntheticRecordings, GeneratorReproducesTheCommittedFiles) {
  if (std::system("command -v python3 > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3 not found: cannot rerun sweeps/thesis/tools/make_recordings.py";
  }
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("armfarm-recordings-test-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  const std::string command = "python3 " + std::string(ARMFARM_SOURCE_DIR) + "/sweeps/thesis/tools/make_recordings.py " +
                              dir.string() + " > /dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  for (const Recording& recording : kRecordings) {
    SCOPED_TRACE(recording.file);
    const std::string fresh = test_support::read_text_file((dir / recording.file).string());
    ASSERT_FALSE(fresh.empty());
    EXPECT_TRUE(fresh == test_support::read_text_file(kDataDir + recording.file)) << "the committed file differs from the generator's output";
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace armfarm::io
