// LWPR params JSON: library names, init_D shapes, "std" normalisation, unknown keys.
#include "runner/lwpr_params_json.hpp"

#include <gtest/gtest.h>

namespace armfarm {
namespace {

TEST(LwprParamsJson, ParsesLibraryNames) {
  const auto json = nlohmann::json::parse(R"({"init_D": [[25, 0], [0, 50]], "init_alpha": 250, "w_gen": 0.2,
      "diag_only": 0, "meta": true, "kernel": "bisquare", "norm_in": "std", "norm_out": [2.0], "max_fields": 7})");
  const LwprDataScales scales{Eigen::Vector2d(0.5, 3.0), Eigen::VectorXd::Ones(1)};
  const lwpr::LwprParams p = parse_lwpr_params(json, "p.json", 2, scales);
  EXPECT_EQ(p.init_D(1, 1), 50.0);
  EXPECT_EQ(p.init_alpha, 250.0);
  EXPECT_FALSE(p.diag_only);
  EXPECT_TRUE(p.meta);
  EXPECT_EQ(p.kernel, lwpr::Kernel::kBisquare);
  EXPECT_EQ(p.norm_in, Eigen::Vector2d(0.5, 3.0));
  EXPECT_EQ(p.norm_out(0), 2.0);
  EXPECT_EQ(p.max_fields, 7u);
  EXPECT_NO_THROW(lwpr::validate_lwpr_params(p, 2, 1));
}

TEST(LwprParamsJson, UnknownKeyIsAnErrorWithASuggestion) {
  try {
    parse_lwpr_params(nlohmann::json::parse(R"({"w_gem": 0.2})"), "p.json", 2, {});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "p.json: w_gem: unknown parameter (did you mean 'w_gen'?)");
  }
  EXPECT_THROW(parse_lwpr_params(nlohmann::json::parse(R"({"init_alpha": "big"})"), "p.json", 2, {}), std::runtime_error);
  EXPECT_THROW(parse_lwpr_params(nlohmann::json::parse(R"({"norm_in": "max"})"), "p.json", 2, {}), std::runtime_error);
}

}  // namespace
}  // namespace armfarm
