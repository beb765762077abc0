// Versioned little-endian binary serialisation of SsgprModel.
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include "engine/learner/model_file_codec.hpp"

#include <cmath>
#include <istream>
#include <iterator>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>

namespace armfarm::ssgpr {
namespace {

constexpr char kMagic[8] = {'A', 'F', 'S', 'S', 'G', 'P', '\r', '\n'};
constexpr std::uint32_t kMaxDimension = 1u << 16;


void put_vector(ModelFileWriter& w, const Eigen::VectorXd& v) { w.put_matrix(v); }

Eigen::VectorXd get_vector(ModelFileReader& r, int dim, const char* name) {
  const std::uint32_t rows = r.get_u32();
  if (r.get_u32() != 1 || (rows != 1 && rows != static_cast<std::uint32_t>(dim))) r.fail(std::string(name) + " has a bad shape");
  Eigen::VectorXd v(rows);
  for (std::uint32_t i = 0; i < rows; ++i) v(i) = r.get_finite(name);
  return v;
}

}  // namespace

void write_ssgpr_model(const SsgprModel& model, std::ostream& out) {
  const SsgprParams& p = model.params();
  const SsgprState& s = model.state();
  ModelFileWriter payload;
  payload.put_u32(static_cast<std::uint32_t>(model.input_dim()));
  payload.put_u32(static_cast<std::uint32_t>(model.output_dim()));
  payload.put_u64(s.n_updates);
  payload.put_u32(static_cast<std::uint32_t>(p.features));
  put_vector(payload, p.lengthscales);
  payload.put_f64(p.signal_variance);
  payload.put_f64(p.noise_variance);
  put_vector(payload, p.output_scale);
  payload.put_f64(p.forgetting);
  payload.put_u64(p.seed);
  payload.put_u64(p.trust_min_samples);
  payload.put_f64(p.trust_variance_fraction);
  payload.put_u64(p.resolve_interval);
  payload.put_matrix(s.frequencies);
  payload.put_lower(s.factor);
  payload.put_matrix(s.rhs);
  payload.put_matrix(s.weights);
  write_model_file_frame(out, kMagic, kSsgprModelFormatVersion, payload, "SSGPR");
}

SsgprModel load_ssgpr_model(std::istream& in) {
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const ModelFileFrame frame = read_model_file_frame(all, kMagic, kSsgprModelFormatVersion, "SSGPR");
  const std::string& payload = frame.payload;
  ModelFileReader r(payload, frame.payload_offset, "SSGPR");
  const int n_in = static_cast<int>(r.get_dimension("n_in", 1, kMaxDimension));
  const int n_out = static_cast<int>(r.get_dimension("n_out", 1, kMaxDimension));
  SsgprState s;
  s.n_updates = r.get_u64();
  SsgprParams p;
  p.features = static_cast<int>(r.get_dimension("features", 1, 1u << 15));
  const Eigen::Index F = 2 * static_cast<Eigen::Index>(p.features);
  p.lengthscales = get_vector(r, n_in, "lengthscales");
  p.signal_variance = r.get_finite("signal_variance");
  p.noise_variance = r.get_finite("noise_variance");
  p.output_scale = get_vector(r, n_out, "output_scale");
  p.forgetting = r.get_finite("forgetting");
  p.seed = r.get_u64();
  p.trust_min_samples = r.get_u64();
  p.trust_variance_fraction = r.get_finite("trust_variance_fraction");
  p.resolve_interval = r.get_u64();
  try {
    validate_ssgpr_params(p, n_in, n_out);
  } catch (const std::invalid_argument& e) {
    r.fail(e.what());
  }
  s.frequencies = r.get_matrix(p.features, n_in, "frequencies", true);
  s.factor = r.get_lower(F, "Cholesky factor");
  s.rhs = r.get_matrix(F, n_out, "right-hand side", true);
  s.weights = r.get_matrix(F, n_out, "weights", true);
  if (!r.at_end()) r.fail("trailing bytes after the weights");
  try {
    return SsgprModel(n_in, n_out, p, std::move(s));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("SSGPR model file: ") + e.what());
  }
}

}  // namespace armfarm::ssgpr
