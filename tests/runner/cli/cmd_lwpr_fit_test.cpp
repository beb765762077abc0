// `armfarm lwpr fit`: learns a generated CSV, prints the JSON keys, saves a loadable model,
// rejects unknown parameters and bad CSVs with exit code 2.
#include "engine/lwpr/lwpr_model_file.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include "support/command_line.hpp"

using armfarm::test_support::CommandResult;
using armfarm::test_support::run_armfarm;

namespace {

class LwprFitCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test and process: ctest runs the tests of this file in parallel.
    dir_ = std::filesystem::temp_directory_path() / ("armfarm_lwpr_fit_test" + std::string("-") + ::testing::UnitTest::GetInstance()->current_test_info()->name() + "-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    write_data("train.csv", 400, 1);
    write_data("test.csv", 200, 2);
  }
  void write_data(const std::string& name, int rows, int seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::ofstream out(dir_ / name);
    out << "x1,x2,y1,y2\n";
    for (int i = 0; i < rows; ++i) {
      const double a = uniform(rng), b = uniform(rng);
      out << a << "," << b << "," << std::sin(2 * a) + b << "," << a * b << "\n";
    }
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

TEST_F(LwprFitCommand, FitsAndReportsJson) {
  std::ofstream(path("params.json")) << R"({"init_D": 4, "w_gen": 0.2, "norm_in": "std"})";
  const CommandResult r = run_armfarm("lwpr fit --train " + path("train.csv") + " --test " + path("test.csv") +
                                      " --inputs 2 --params " + path("params.json") +
                                      " --epochs 5 --shuffle 1 --json --save " + path("model.lwpr"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto json = nlohmann::json::parse(r.output);
  ASSERT_EQ(json["nmse"].size(), 2u);
  EXPECT_LT(json["nmse_mean"].get<double>(), 0.1);
  EXPECT_GT(json["n_rf"].get<int>(), 2);
  EXPECT_GT(json["us_per_update"].get<double>(), 0.0);
  EXPECT_GT(json["us_per_predict"].get<double>(), 0.0);
  // Thread CPU time of the same loops: positive, and a single thread cannot use more CPU than
  // wall time (a small allowance for the two clocks' resolutions).
  EXPECT_GT(json["cpu_us_per_update"].get<double>(), 0.0);
  EXPECT_LE(json["cpu_us_per_update"].get<double>(), json["us_per_update"].get<double>() * 1.05 + 0.5);
  std::ifstream in(path("model.lwpr"), std::ios::binary);
  const armfarm::lwpr::LwprModel model = armfarm::lwpr::load_lwpr_model(in);
  EXPECT_EQ(static_cast<int>(model.size()), json["n_rf"].get<int>());
  EXPECT_EQ(model.output_dim(), 2);
}

TEST_F(LwprFitCommand, BadInputExitsTwoWithOneLine) {
  std::ofstream(path("bad_params.json")) << R"({"w_gem": 0.2})";
  CommandResult r = run_armfarm("lwpr fit --train " + path("train.csv") + " --test " + path("test.csv") +
                                " --inputs 2 --params " + path("bad_params.json"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("w_gem: unknown parameter (did you mean 'w_gen'?)"), std::string::npos) << r.output;
  std::ofstream(path("broken.csv")) << "x1,x2,y1\n1,2,3\n4,5\n";
  r = run_armfarm("lwpr fit --train " + path("broken.csv") + " --test " + path("test.csv") + " --inputs 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("broken.csv:3:"), std::string::npos) << r.output;
  r = run_armfarm("lwpr fit --train " + path("train.csv") + " --test " + path("test.csv") + " --inputs 4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace
