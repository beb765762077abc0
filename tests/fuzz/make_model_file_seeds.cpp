// Writes the model_file fuzz seed corpus (tests/data/fuzz/model_file): small LWPR and SSGPR models
// as whole files (mode bytes 0, 2) and as payloads (mode bytes 1, 3). Built by hand, not by CMake:
//   g++ -std=c++17 -I. -I/usr/include/eigen3 tests/fuzz/make_model_file_seeds.cpp build/engine/libarmfarm_engine.a -o seeds
//   ./seeds tests/data/fuzz/model_file
#include "engine/lwpr/lwpr_model_file.hpp"
#include "engine/ssgpr/ssgpr_model_file.hpp"
#include "engine/random/random_stream.hpp"
#include <cmath>
#include <fstream>
#include <sstream>
using namespace armfarm;
static void emit(const std::string& dir, const std::string& name, char mode, const std::string& bytes) {
  std::ofstream(dir + "/" + name, std::ios::binary) << mode << bytes;
}
int main(int, char** argv) {
  const std::string dir = argv[1];
  {
    ssgpr::SsgprParams params;
    params.features = 4;
    params.lengthscales = Eigen::Vector2d(0.5, 1.0);
    params.output_scale = Eigen::VectorXd::Constant(1, 1.0);
    ssgpr::SsgprModel model(2, 1, params);
    RandomStream s(3, "fuzz.seed");
    for (int i = 0; i < 20; ++i) { Eigen::Vector2d x(s.uniform(-1, 1), s.uniform(-1, 1)); model.update(x, Eigen::VectorXd::Constant(1, std::sin(x(0)))); }
    std::ostringstream out(std::ios::binary);
    ssgpr::write_ssgpr_model(model, out);
    const std::string file = out.str();
    emit(dir, "ssgpr_file", 2, file);
    emit(dir, "ssgpr_payload", 3, file.substr(20, file.size() - 28));
  }
  {
    lwpr::LwprParams params;
    lwpr::LwprModel model(2, 1, params);
    RandomStream s(5, "fuzz.seed");
    for (int i = 0; i < 50; ++i) { Eigen::Vector2d x(s.uniform(-1, 1), s.uniform(-1, 1)); model.update(x, Eigen::VectorXd::Constant(1, std::sin(3 * x(0)))); }
    std::ostringstream out(std::ios::binary);
    lwpr::write_lwpr_model(model, out);
    const std::string file = out.str();
    emit(dir, "lwpr_file", 0, file);
    emit(dir, "lwpr_payload", 1, file.substr(20, file.size() - 28));
  }
}
