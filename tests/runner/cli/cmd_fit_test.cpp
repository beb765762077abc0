// `armfarm fit --learner ssgpr|lwpr`: learns a generated CSV, prints the JSON keys, saves a model
// file that loads and predicts like the reported fit; bad parameters exit 2 with one line.
#include "engine/lwpr/lwpr_model_file.hpp"
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_armfarm;

namespace {

class FitCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("armfarm_fit_test-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
            std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    write_data("train.csv", 400, 0.0);
    write_data("test.csv", 200, 0.37);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  // x1 in [-3, 3] (a deterministic sweep), x2 ten times larger: y1 = sin(2 x1) + x2/10, y2 = x1 x2 / 10.
  void write_data(const std::string& name, int rows, double shift) {
    std::ofstream out(dir_ / name);
    out << "x1,x2,y1,y2\n";
    for (int i = 0; i < rows; ++i) {
      const double a = -3.0 + 6.0 * std::fmod(i * 0.618034 + shift, 1.0), b = 10.0 * std::sin(1.7 * i + shift);
      out << a << "," << b << "," << std::sin(2 * a) + b / 10 << "," << a * b / 10 << "\n";
    }
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

TEST_F(FitCommand, SsgprFitsReportsAndSavesALoadableModel) {
  std::ofstream(path("params.json")) << R"({"features": 80, "fit_samples": 200, "fit_iterations": 40})";
  const CommandResult r = run_armfarm("fit --learner ssgpr --train " + path("train.csv") + " --test " + path("test.csv") +
                                      " --inputs 2 --params " + path("params.json") + " --epochs 2 --shuffle 1 --json --save " +
                                      path("model.ssgpr"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto json = nlohmann::json::parse(r.output);
  EXPECT_EQ(json["learner"], "ssgpr");
  ASSERT_EQ(json["nmse"].size(), 2u);
  EXPECT_LT(json["nmse_mean"].get<double>(), 0.05);
  EXPECT_EQ(json["features"].get<int>(), 80);
  EXPECT_GT(json["fit_seconds"].get<double>(), 0.0);
  EXPECT_EQ(json["lengthscales"].size(), 2u);
  EXPECT_EQ(json["untrusted_predictions"].get<int>(), 0);
  std::ifstream in(path("model.ssgpr"), std::ios::binary);
  const armfarm::ssgpr::SsgprModel model = armfarm::ssgpr::load_ssgpr_model(in);
  EXPECT_EQ(model.n_updates(), 800u);  // 2 epochs × 400 rows
  EXPECT_EQ(model.params().features, 80);
  EXPECT_EQ(model.params().noise_variance, json["noise_variance"].get<double>());
  EXPECT_EQ(static_cast<double>(model.calc_memory_bytes()), json["memory_bytes"].get<double>());
}

TEST_F(FitCommand, LwprIsTheDefaultAndTheAliasAgrees) {
  const std::string args = " --train " + path("train.csv") + " --test " + path("test.csv") + " --inputs 2 --shuffle 3 --json";
  const CommandResult fit = run_armfarm("fit" + args), alias = run_armfarm("lwpr fit" + args);
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  ASSERT_EQ(alias.exit_code, 0) << alias.output;
  const auto a = nlohmann::json::parse(fit.output), b = nlohmann::json::parse(alias.output);
  EXPECT_EQ(a["learner"], "lwpr");
  EXPECT_EQ(a["nmse"], b["nmse"]);
  EXPECT_EQ(a["n_rf"], b["n_rf"]);
  EXPECT_GT(a["memory_bytes"].get<double>(), 0.0);
}

TEST_F(FitCommand, BadInputExitsTwoWithOneLine) {
  std::ofstream(path("bad.json")) << R"({"features": 0})";
  CommandResult r = run_armfarm("fit --learner ssgpr --train " + path("train.csv") + " --test " + path("test.csv") +
                                " --inputs 2 --params " + path("bad.json"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("bad.json: features: 0 is outside the allowed range [1, 2000]"), std::string::npos) << r.output;
  std::ofstream(path("unknown.json")) << R"({"feature": 10})";
  r = run_armfarm("fit --learner ssgpr --train " + path("train.csv") + " --test " + path("test.csv") + " --inputs 2 --params " +
                  path("unknown.json"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown.json: feature: unknown parameter"), std::string::npos) << r.output;
  std::ofstream(path("big_fit.json")) << R"({"fit_samples": 1000})";
  r = run_armfarm("fit --learner ssgpr --train " + path("train.csv") + " --test " + path("test.csv") + " --inputs 2 --params " +
                  path("big_fit.json") + " --save " + path("never.ssgpr"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("fewer than fit_samples = 1000"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(path("never.ssgpr")));
  r = run_armfarm("fit --learner gp --train " + path("train.csv") + " --test " + path("test.csv") + " --inputs 2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace
