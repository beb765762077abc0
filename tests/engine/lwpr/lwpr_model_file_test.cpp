// LWPR model files: bit-identical round trip, clear errors for corrupt, truncated and future files.
#include "engine/lwpr/lwpr_model_file.hpp"

#include "engine/learner/model_file_codec.hpp"

#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <string>

namespace armfarm::lwpr {
namespace {

LwprModel make_trained_model(bool diag_only, LooStart loo_start = LooStart::kLibrary) {
  LwprParams params;
  params.loo_start = loo_start;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 20.0);
  params.diag_only = diag_only;
  params.meta = true;
  params.norm_in = Eigen::Vector3d(1.0, 2.0, 0.5);
  LwprModel model(3, 2, params);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
    model.update(x, Eigen::Vector2d(std::sin(3.0 * x(0)) * x(1), x(2) * x(2)));
  }
  return model;
}

std::string save(const LwprModel& model) {
  std::ostringstream out(std::ios::binary);
  write_lwpr_model(model, out);
  return out.str();
}

LwprModel load(const std::string& bytes) {
  std::istringstream in(bytes, std::ios::binary);
  return load_lwpr_model(in);
}

std::string error_of(const std::string& bytes) {
  try {
    load(bytes);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(LwprModelFile, RoundTripGivesBitIdenticalPredictions) {
  for (bool diag_only : {true, false}) {
    const LwprModel original = make_trained_model(diag_only);
    ASSERT_GT(original.size(), 4u);
    const LwprModel copy = load(save(original));
    EXPECT_EQ(copy.size(), original.size());
    EXPECT_EQ(copy.n_updates(), original.n_updates());
    auto wa = original.make_workspace();
    auto wb = copy.make_workspace();
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector3d x(uniform(rng), uniform(rng), uniform(rng));
      const Prediction a = original.predict(x, *wa);
      const Prediction b = copy.predict(x, *wb);
      EXPECT_EQ(a.value, b.value);
      EXPECT_EQ(a.confidence, b.confidence);
      EXPECT_EQ(a.trustworthy, b.trustworthy);
    }
    EXPECT_EQ(save(copy), save(original));  // and the saved bytes themselves
  }
}

TEST(LwprModelFile, LoadedModelKeepsLearningLikeTheOriginal) {
  LwprModel original = make_trained_model(true);
  LwprModel copy = load(save(original));
  const Eigen::Vector3d x(0.2, -0.4, 0.6);
  original.update(x, Eigen::Vector2d(1.0, 2.0));
  copy.update(x, Eigen::Vector2d(1.0, 2.0));
  EXPECT_EQ(save(copy), save(original));
}

TEST(LwprModelFile, RejectsCorruptTruncatedAndFutureFiles) {
  const std::string good = save(make_trained_model(true));
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  EXPECT_NE(error_of(flipped).find("checksum"), std::string::npos) << error_of(flipped);
  EXPECT_NE(error_of(good.substr(0, good.size() - 3)).find("truncated"), std::string::npos);
  EXPECT_NE(error_of("hello world, not a model").find("bad magic"), std::string::npos);
  std::string future = good;
  future[8] = static_cast<char>(kLwprModelFormatVersion + 1);  // version field, little-endian
  EXPECT_NE(error_of(future).find("newer"), std::string::npos) << error_of(future);
  EXPECT_NE(error_of("").find("bad magic"), std::string::npos);
  std::string huge = good;
  for (int i = 12; i < 20; ++i) huge[i] = '\xff';  // payload size field: 2^64 - 1
  EXPECT_NE(error_of(huge).find("more than the file holds"), std::string::npos) << error_of(huge);
}

void put_le(std::string& to, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) to.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

TEST(LwprModelFile, StartRuleRoundTripsAndVersionOneFilesLoadWithTheEarlyRule) {
  for (LooStart rule : {LooStart::kLibrary, LooStart::kEarly}) {
    EXPECT_EQ(load(save(make_trained_model(true, rule))).params().loo_start, rule);
  }
  // A version-1 file is a version-2 file without the start rule's u32. Two untrained models that
  // differ only in the rule locate it: their payloads differ in that one value.
  LwprParams a, b;
  b.loo_start = LooStart::kEarly;
  const std::string file_a = save(LwprModel(3, 2, a)), file_b = save(LwprModel(3, 2, b));
  ASSERT_EQ(file_a.size(), file_b.size());
  constexpr std::size_t kHeader = 20, kChecksum = 8;  // magic, version u32, payload size u64 | FNV-1a u64
  std::size_t at = kHeader;
  while (at < file_a.size() - kChecksum && file_a[at] == file_b[at]) ++at;
  ASSERT_LT(at, file_a.size() - kChecksum);
  // The library rule learns differently from the early one; written as version 1 it loads early.
  const LwprModel trained = make_trained_model(true, LooStart::kLibrary);
  const std::string v2 = save(trained);
  std::string payload = v2.substr(kHeader, v2.size() - kHeader - kChecksum);
  payload.erase(at - kHeader, 4);
  std::string v1(v2.substr(0, 8));
  put_le(v1, 1, 4);
  put_le(v1, payload.size(), 8);
  v1 += payload;
  put_le(v1, calc_model_file_checksum(payload), 8);
  const LwprModel old = load(v1);
  EXPECT_EQ(old.params().loo_start, LooStart::kEarly);
  EXPECT_EQ(old.size(), trained.size());
  EXPECT_EQ(old.n_updates(), trained.n_updates());
}

}  // namespace
}  // namespace armfarm::lwpr
