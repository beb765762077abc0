// Canonical JSON and job keys: stable under key order and number formatting, sensitive to values.
#include "runner/spec/canonical_json.hpp"

#include <gtest/gtest.h>
#include <xxhash.h>

namespace armfarm {
namespace {

TEST(CanonicalJson, SortsKeysAndWritesNumbersOneWay) {
  const auto a = nlohmann::json::parse(R"({"b": 1.0, "a": {"y": [1e0, 2.50], "x": -0.0}})");
  EXPECT_EQ(calc_canonical_json(a), R"({"a":{"x":0,"y":[1,2.5]},"b":1})");
}

TEST(CanonicalJson, KeyIsStableUnderOrderAndFormattingButNotValues) {
  const auto a = nlohmann::json::parse(R"({"seed": 1, "control": {"kp": [100, 5e1], "gain_scale": 1}})");
  const auto b = nlohmann::json::parse(R"({"control": {"gain_scale": 1.0, "kp": [1e2, 50.0]}, "seed": 1.0})");
  const auto c = nlohmann::json::parse(R"({"control": {"gain_scale": 1.0000000000000002, "kp": [1e2, 50.0]}, "seed": 1})");
  EXPECT_EQ(calc_job_key(a), calc_job_key(b));
  EXPECT_NE(calc_job_key(a), calc_job_key(c));
  EXPECT_EQ(calc_job_key(a).size(), 32u);
}

TEST(CanonicalJson, TextHashIsXxh3OfTheBytesHighHalfFirst) {
  const std::string text = "armfarm";
  const XXH128_hash_t hash = XXH3_128bits(text.data(), text.size());
  char expected[33];
  std::snprintf(expected, sizeof expected, "%016llx%016llx", static_cast<unsigned long long>(hash.high64),
                static_cast<unsigned long long>(hash.low64));
  EXPECT_EQ(calc_text_hash(text), expected);
  EXPECT_NE(calc_text_hash("armfarm "), calc_text_hash(text));
}

}  // namespace
}  // namespace armfarm
