// Series BLOBs: exact round trip, the documented layout (zstd frame of column-major f64le), and
// clear errors for damaged data.
#include "results/series_codec.hpp"
#include "results/store_error.hpp"

#include <gtest/gtest.h>
#include <zstd.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

namespace armfarm {
namespace {

TEST(SeriesCodec, RoundTripIsBitExactIncludingSpecialValues) {
  Eigen::MatrixXd rows(5, 3);
  for (int i = 0; i < 5; ++i) rows.row(i) << 0.01 * i, std::sin(i), -1e-300 * i;
  rows(2, 1) = std::numeric_limits<double>::quiet_NaN();
  rows(3, 2) = -std::numeric_limits<double>::infinity();
  const Eigen::MatrixXd back = calc_series_matrix(calc_series_blob(rows), 5, 3, "test");
  ASSERT_EQ(back.rows(), 5);
  ASSERT_EQ(back.cols(), 3);
  EXPECT_EQ(std::memcmp(back.data(), rows.data(), sizeof(double) * 15), 0);
}

TEST(SeriesCodec, BlobIsAZstdFrameOfColumnMajorLittleEndianDoubles) {
  Eigen::MatrixXd rows(2, 2);
  rows << 1.0, 2.0, 3.0, 4.0;  // row-major literal: column 0 is (1, 3)
  const std::vector<unsigned char> blob = calc_series_blob(rows);
  std::vector<double> raw(4);
  ASSERT_EQ(ZSTD_decompress(raw.data(), 32, blob.data(), blob.size()), 32u);
  EXPECT_EQ(raw, (std::vector<double>{1.0, 3.0, 2.0, 4.0}));
}

TEST(SeriesCodec, SmoothSignalsCompress) {
  Eigen::MatrixXd rows(10000, 2);
  for (int i = 0; i < 10000; ++i) rows.row(i) << 0.001 * i, 0.0;
  EXPECT_LT(calc_series_blob(rows).size(), 10000u * 2 * 8 / 4);
}

TEST(SeriesCodec, DamagedOrMismatchedBlobsAreErrors) {
  Eigen::MatrixXd rows = Eigen::MatrixXd::Ones(4, 2);
  std::vector<unsigned char> blob = calc_series_blob(rows);
  EXPECT_THROW(calc_series_matrix(blob, 4, 3, "test"), StoreError);  // wrong size
  EXPECT_THROW(calc_series_matrix({1, 2, 3, 4, 5}, 4, 2, "test"), StoreError);  // not zstd
  try {
    calc_series_matrix({1, 2, 3}, 1, 1, "db.sqlite: series POS");
    FAIL();
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("db.sqlite: series POS"), std::string::npos);
  }
}

TEST(SeriesCodec, AFlippedBitInTheSamplesIsFoundByTheFrameChecksum) {
  // Random bits do not compress: zstd stores them as a raw block, where a flipped bit decodes
  // without any format error; only the frame's content checksum can tell the numbers changed.
  Eigen::MatrixXd rows(64, 2);
  std::mt19937_64 bits(7);
  for (Eigen::Index i = 0; i < rows.size(); ++i) {
    const std::uint64_t word = bits() & 0x3fffffffffffffffULL;  // finite doubles
    std::memcpy(rows.data() + i, &word, sizeof word);
  }
  const std::vector<unsigned char> blob = calc_series_blob(rows);
  ASSERT_GT(blob.size(), 5u);
  EXPECT_NE(blob[4] & 0x04, 0) << "frame header descriptor: Content_Checksum_flag (RFC 8878, 3.1.1.1.1)";
  std::vector<unsigned char> flipped = blob;
  flipped[flipped.size() / 2] ^= 0x10;
  EXPECT_THROW(calc_series_matrix(flipped, 64, 2, "test"), StoreError);

  // The control: the same samples in a frame without checksum, the same bit flipped, decode
  // "fine" to other numbers.
  std::vector<unsigned char> plain(ZSTD_compressBound(1024));
  plain.resize(ZSTD_compress(plain.data(), plain.size(), rows.data(), 1024, 3));
  plain[plain.size() / 2] ^= 0x10;
  const Eigen::MatrixXd wrong = calc_series_matrix(plain, 64, 2, "test");
  EXPECT_NE(std::memcmp(wrong.data(), rows.data(), 1024), 0);

  const Eigen::MatrixXd back = calc_series_matrix(blob, 64, 2, "test");
  EXPECT_EQ(std::memcmp(back.data(), rows.data(), 1024), 0);
}

TEST(SeriesCodec, AnOlderFrameWithoutChecksumStillDecodes) {
  Eigen::MatrixXd rows = Eigen::MatrixXd::Constant(3, 2, 0.25);
  std::vector<unsigned char> blob(ZSTD_compressBound(48));
  blob.resize(ZSTD_compress(blob.data(), blob.size(), rows.data(), 48, 3));  // no checksum by default
  EXPECT_EQ(calc_series_matrix(blob, 3, 2, "test"), rows);
}

}  // namespace
}  // namespace armfarm
