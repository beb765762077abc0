// LWPR params JSON: library names, init_D shapes, "std" normalisation, unknown keys.
#include "runner/config/lwpr_params_json.hpp"

#include "engine/learning/learning_config.hpp"
#include "runner/config/ssgpr_params_json.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

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

// Both parameter files (`lwpr fit --params`, `fit --learner ssgpr --params`) are read as spec
// files are: a syntax error names the file, the line and the column (it named a byte offset).
TEST(LwprParamsJson, ASyntaxErrorInEitherParameterFileNamesItsLineAndColumn) {
  const std::string path = test_support::scratch_file("bad params \xc3\xa9.json");
  std::ofstream(path) << "{\"init_D\": 2,\n  \"update_D\": tru }\n";
  const auto message = [](const auto& load) {
    try {
      load();
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string lwpr = message([&] { load_lwpr_params(path, 2, {}); });
  const std::string ssgpr = message([&] { load_ssgpr_params(path); });
  EXPECT_EQ(lwpr.rfind(path + ": line 2, column ", 0), 0u) << lwpr;
  EXPECT_NE(lwpr.find("not valid JSON"), std::string::npos) << lwpr;
  EXPECT_EQ(ssgpr, lwpr);
  std::remove(path.c_str());
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

TEST(LwprParamsJson, ReadsThroughTheJobsTableKeepingTheLibraryDefaults) {
  const auto message = [](const char* text) {
    try {
      parse_lwpr_params(nlohmann::json::parse(text), "p.json", 2, {});
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message(R"({"max_fields": -1})"), "p.json: max_fields: expected an integer in [0, 1e+06], got -1");
  EXPECT_EQ(message(R"({"init_D": [[1, 0], [0]]})"), "p.json: init_D[1]: rows of different lengths");
  EXPECT_EQ(message(R"({"kernel": "triangle"})"), "p.json: kernel: must be one of \"gaussian\" or \"bisquare\", not \"triangle\"");
  // One table serves the file format and the job's learning.lwpr block: 20 library keys + 4 of ours.
  nlohmann::json all = nlohmann::json::object();
  for (const auto& key : lwpr_params_keys()) all[key.name] = nullptr;
  EXPECT_EQ(all.size(), 24u);
  // Keys left out keep the library's defaults (init_D 25 on raw data), not the job's 0.05.
  const lwpr::LwprParams p = parse_lwpr_params(nlohmann::json::parse(R"({"kernel": "BiSquare", "meta": 1})"), "p.json", 2, {});
  EXPECT_EQ(p.init_D(0, 0), 25.0);
  EXPECT_EQ(p.kernel, lwpr::Kernel::kBisquare);
  EXPECT_TRUE(p.meta);
  EXPECT_EQ(p.loo_start, lwpr::LooStart::kLibrary);  // and the library's start rule, not the job's early one
  const lwpr::LwprParams early = parse_lwpr_params(nlohmann::json::parse(R"({"loo_start": "early"})"), "p.json", 2, {});
  EXPECT_EQ(early.loo_start, lwpr::LooStart::kEarly);
  EXPECT_EQ(message(R"({"loo_start": "late"})"), "p.json: loo_start: must be one of \"library\" or \"early\", not \"late\"");
}

}  // namespace
}  // namespace armfarm
