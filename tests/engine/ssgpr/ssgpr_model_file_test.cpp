// SSGPR model files: bit-identical round trip, refused damaged, truncated and future files.
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include "engine/random/random_stream.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <string>

namespace armfarm::ssgpr {
namespace {

SsgprModel make_trained_model() {
  SsgprParams params;
  params.features = 30;
  params.lengthscales = Eigen::Vector3d(0.5, 1.0, 2.0);
  params.output_scale = Eigen::Vector2d(1.0, 3.0);
  params.forgetting = 0.999;
  params.resolve_interval = 64;
  params.seed = 17;
  SsgprModel model(3, 2, params);
  RandomStream stream(11, "test.file");
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d x(stream.uniform(-1.0, 1.0), stream.uniform(-1.0, 1.0), stream.uniform(-1.0, 1.0));
    model.update(x, Eigen::Vector2d(std::sin(3.0 * x(0)) * x(1), 3.0 * x(2) * x(2)));
  }
  return model;
}

std::string save(const SsgprModel& model) {
  std::ostringstream out(std::ios::binary);
  write_ssgpr_model(model, out);
  return out.str();
}

SsgprModel load(const std::string& bytes) {
  std::istringstream in(bytes, std::ios::binary);
  return load_ssgpr_model(in);
}

std::string error_of(const std::string& bytes) {
  try {
    load(bytes);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

// A file whose payload was edited and whose checksum was recomputed (so the content checks,
// not the hash, must refuse it).
std::string with_payload_byte(std::string bytes, std::size_t offset, char value) {
  bytes[offset] = value;
  const std::size_t start = 20, end = bytes.size() - 8;
  std::uint64_t hash = 14695981039346656037ull;
  for (std::size_t i = start; i < end; ++i) {
    hash ^= static_cast<unsigned char>(bytes[i]);
    hash *= 1099511628211ull;
  }
  for (int i = 0; i < 8; ++i) bytes[end + i] = static_cast<char>((hash >> (8 * i)) & 0xffu);
  return bytes;
}

TEST(SsgprModelFile, RoundTripGivesBitIdenticalPredictions) {
  const SsgprModel original = make_trained_model();
  const SsgprModel copy = load(save(original));
  EXPECT_EQ(copy.n_updates(), original.n_updates());
  EXPECT_EQ(copy.size(), original.size());
  auto wa = original.make_workspace();
  auto wb = copy.make_workspace();
  RandomStream stream(12, "test.file.points");
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d x(stream.uniform(-1.5, 1.5), stream.uniform(-1.5, 1.5), stream.uniform(-1.5, 1.5));
    SsgprPredictionDetail da, db;
    const Prediction a = original.predict(x, *wa, da);
    const Prediction b = copy.predict(x, *wb, db);
    EXPECT_EQ(a.value, b.value);
    EXPECT_EQ(a.confidence, b.confidence);
    EXPECT_EQ(a.output_trusted, b.output_trusted);
    EXPECT_EQ(da.mean, db.mean);
    EXPECT_EQ(da.predictive_variance, db.predictive_variance);
  }
  EXPECT_EQ(save(copy), save(original));
}

TEST(SsgprModelFile, LoadedModelKeepsLearningLikeTheOriginal) {
  SsgprModel original = make_trained_model();
  SsgprModel copy = load(save(original));
  for (int i = 0; i < 70; ++i) {  // crosses a re-solve (every 64 updates)
    const Eigen::Vector3d x(0.01 * i, -0.4, 0.6);
    original.update(x, Eigen::Vector2d(1.0, 2.0));
    copy.update(x, Eigen::Vector2d(1.0, 2.0));
  }
  EXPECT_EQ(save(copy), save(original));
}

TEST(SsgprModelFile, RefusesDamagedTruncatedAndFutureFiles) {
  const std::string good = save(make_trained_model());
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_NE(error_of(flipped).find("checksum mismatch"), std::string::npos) << error_of(flipped);
  EXPECT_NE(error_of(good.substr(0, good.size() - 3)).find("truncated"), std::string::npos);
  EXPECT_NE(error_of(good + "x").find("truncated or corrupt"), std::string::npos);
  EXPECT_NE(error_of("hello world, not a model").find("bad magic"), std::string::npos);
  EXPECT_NE(error_of("").find("bad magic"), std::string::npos);
  std::string future = good;
  future[8] = 2;  // version, little-endian
  EXPECT_NE(error_of(future).find("newer"), std::string::npos) << error_of(future);
  std::string zero = good;
  zero[8] = 0;
  EXPECT_NE(error_of(zero).find("version 0"), std::string::npos) << error_of(zero);
  // Content checks behind a valid checksum: n_in = 0 (file byte 20, the payload's first), features = 0 (byte 36).
  const std::string no_inputs = error_of(with_payload_byte(good, 20, 0));
  EXPECT_NE(no_inputs.find("byte 20: n_in is 0"), std::string::npos) << no_inputs;
  const std::string no_features = error_of(with_payload_byte(good, 36, 0));
  EXPECT_NE(no_features.find("byte 36: features is 0"), std::string::npos) << no_features;
  // features 30 → 4126: the stored Ω no longer has the announced shape.
  const std::string more_features = error_of(with_payload_byte(good, 37, 0x10));
  EXPECT_NE(more_features.find("frequencies is 30x3, expected 4126x3"), std::string::npos) << more_features;
  // A NaN in the last double of W (the 8 bytes before the checksum; 0xff.. is a NaN pattern).
  std::string nan = good;
  for (int i = 0; i < 8; ++i) nan = with_payload_byte(nan, good.size() - 16 + i, static_cast<char>(0xff));
  const std::string nan_error = error_of(nan);
  EXPECT_NE(nan_error.find("byte " + std::to_string(good.size() - 16) + ": weights is not finite"), std::string::npos) << nan_error;
  EXPECT_EQ(error_of(good), "");
}

}  // namespace
}  // namespace armfarm::ssgpr
