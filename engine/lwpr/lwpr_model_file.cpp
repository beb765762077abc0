// Versioned little-endian binary serialisation of LwprModel.
#include "engine/lwpr/lwpr_model_file.hpp"

#include "engine/learner/model_file_codec.hpp"

#include <istream>
#include <iterator>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm::lwpr {
namespace {

constexpr char kMagic[8] = {'A', 'F', 'L', 'W', 'P', 'R', '\r', '\n'};
constexpr std::uint32_t kMaxDimension = 1u << 16;


void put_params(ModelFileWriter& w, const LwprParams& p) {
  w.put_matrix(p.init_D);
  w.put_f64(p.init_alpha);
  w.put_f64(p.penalty);
  w.put_bool(p.diag_only);
  w.put_bool(p.update_D);
  w.put_bool(p.meta);
  w.put_f64(p.meta_rate);
  w.put_f64(p.w_gen);
  w.put_f64(p.w_prune);
  w.put_f64(p.init_lambda);
  w.put_f64(p.final_lambda);
  w.put_f64(p.tau_lambda);
  w.put_f64(p.init_S2);
  w.put_f64(p.add_threshold);
  w.put_u32(p.kernel == Kernel::kGaussian ? 0 : 1);
  w.put_matrix(p.norm_in);
  w.put_matrix(p.norm_out);
  w.put_bool(p.blend);
  w.put_bool(p.add_proj);
  w.put_u32(static_cast<std::uint32_t>(p.init_n_reg));
  w.put_u64(p.max_fields);
  w.put_f64(p.cutoff);
  w.put_f64(p.trust_n_data);
  w.put_u32(p.loo_start == LooStart::kLibrary ? 0 : 1);  // since format version 2
}

LwprParams get_params(ModelFileReader& r, int n_in, int n_out, std::uint32_t version) {
  LwprParams p;
  const std::uint32_t rows = r.get_u32(), cols = r.get_u32();
  if (!((rows == 1 && cols == 1) || (rows == static_cast<std::uint32_t>(n_in) && (cols == 1 || cols == rows)))) {
    r.fail("init_D has a bad shape");
  }
  p.init_D.resize(rows, cols);
  for (std::uint32_t j = 0; j < cols; ++j) {
    for (std::uint32_t i = 0; i < rows; ++i) p.init_D(i, j) = r.get_f64();
  }
  p.init_alpha = r.get_f64();
  p.penalty = r.get_f64();
  p.diag_only = r.get_bool();
  p.update_D = r.get_bool();
  p.meta = r.get_bool();
  p.meta_rate = r.get_f64();
  p.w_gen = r.get_f64();
  p.w_prune = r.get_f64();
  p.init_lambda = r.get_f64();
  p.final_lambda = r.get_f64();
  p.tau_lambda = r.get_f64();
  p.init_S2 = r.get_f64();
  p.add_threshold = r.get_f64();
  const std::uint32_t kernel = r.get_dimension("kernel", 0, 1);
  p.kernel = kernel == 0 ? Kernel::kGaussian : Kernel::kBisquare;
  const std::uint32_t nin_rows = r.get_u32();
  if (r.get_u32() != 1 || (nin_rows != 1 && nin_rows != static_cast<std::uint32_t>(n_in))) r.fail("norm_in has a bad shape");
  p.norm_in.resize(nin_rows);
  for (std::uint32_t i = 0; i < nin_rows; ++i) p.norm_in(i) = r.get_f64();
  const std::uint32_t nout_rows = r.get_u32();
  if (r.get_u32() != 1 || (nout_rows != 1 && nout_rows != static_cast<std::uint32_t>(n_out))) {
    r.fail("norm_out has a bad shape");
  }
  p.norm_out.resize(nout_rows);
  for (std::uint32_t i = 0; i < nout_rows; ++i) p.norm_out(i) = r.get_f64();
  p.blend = r.get_bool();
  p.add_proj = r.get_bool();
  p.init_n_reg = static_cast<int>(r.get_dimension("init_n_reg", 1, kMaxDimension));
  p.max_fields = r.get_u64();
  p.cutoff = r.get_f64();
  p.trust_n_data = r.get_f64();
  // Version 1 files were written before the start rule was a parameter: they learnt with the early rule.
  p.loo_start = version >= 2 && r.get_dimension("loo_start", 0, 1) == 0 ? LooStart::kLibrary : LooStart::kEarly;
  return p;
}

void put_field(ModelFileWriter& w, const ReceptiveField& rf) {
  w.put_u32(static_cast<std::uint32_t>(rf.n_reg()));
  w.put_matrix(rf.center);
  w.put_matrix(rf.metric_factor);
  w.put_matrix(rf.metric);
  w.put_matrix(rf.log_alpha);
  w.put_matrix(rf.meta_trace);
  w.put_f64(rf.lambda);
  w.put_matrix(rf.mean_x);
  w.put_f64(rf.beta0);
  w.put_matrix(rf.sum_w);
  w.put_matrix(rf.n_data);
  w.put_matrix(rf.sxy);
  w.put_matrix(rf.sxs);
  w.put_matrix(rf.ss2);
  w.put_matrix(rf.sys);
  w.put_matrix(rf.sum_e_cv2);
  w.put_f64(rf.sum_e2);
  w.put_f64(rf.press_E);
  w.put_matrix(rf.press_H);
  w.put_matrix(rf.press_R);
  w.put_bool(rf.trustworthy);
  // Cached derived quantities are stored too, so predictions after loading are bit-identical.
  w.put_matrix(rf.directions);
  w.put_matrix(rf.loadings);
  w.put_matrix(rf.beta);
}

ReceptiveField get_field(ModelFileReader& r, int n, bool diagonal) {
  ReceptiveField rf;
  const int R = static_cast<int>(r.get_dimension("number of projections", 1, static_cast<std::uint32_t>(n)));
  const Eigen::Index mc = diagonal ? 1 : n;
  rf.center = r.get_vector(n, "center");
  rf.metric_factor = r.get_matrix(n, mc, "M");
  rf.metric = r.get_matrix(n, mc, "D");
  rf.log_alpha = r.get_matrix(n, mc, "log_alpha");
  rf.meta_trace = r.get_matrix(n, mc, "meta_trace");
  rf.lambda = r.get_f64();
  rf.mean_x = r.get_vector(n, "mean_x");
  rf.beta0 = r.get_f64();
  rf.sum_w = r.get_vector(R, "sum_w");
  rf.n_data = r.get_vector(R, "n_data");
  rf.sxy = r.get_matrix(n, R, "sxy");
  rf.sxs = r.get_matrix(n, R, "sxs");
  rf.ss2 = r.get_vector(R, "ss2");
  rf.sys = r.get_vector(R, "sys");
  rf.sum_e_cv2 = r.get_vector(R, "sum_e_cv2");
  rf.sum_e2 = r.get_f64();
  rf.press_E = r.get_f64();
  rf.press_H = r.get_vector(R, "press_H");
  rf.press_R = r.get_vector(R, "press_R");
  rf.trustworthy = r.get_bool();
  rf.directions = r.get_matrix(n, R, "directions");
  rf.loadings = r.get_matrix(n, R, "loadings");
  rf.beta = r.get_vector(R, "beta");
  if (!rf.metric.allFinite() || !rf.metric_factor.allFinite() || !rf.center.allFinite()) {
    r.fail("receptive field has a non-finite metric or centre");
  }
  return rf;
}

}  // namespace

void write_lwpr_model(const LwprModel& model, std::ostream& out) {
  ModelFileWriter payload;
  payload.put_u32(static_cast<std::uint32_t>(model.input_dim()));
  payload.put_u32(static_cast<std::uint32_t>(model.output_dim()));
  payload.put_u64(model.n_updates());
  put_params(payload, model.params());
  for (int o = 0; o < model.output_dim(); ++o) {
    const std::vector<ReceptiveField> fields = model.fields(o);
    payload.put_u64(fields.size());
    for (const ReceptiveField& rf : fields) put_field(payload, rf);
  }
  write_model_file_frame(out, kMagic, kLwprModelFormatVersion, payload, "LWPR");
}

LwprModel load_lwpr_model(std::istream& in) {
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const ModelFileFrame frame = read_model_file_frame(all, kMagic, kLwprModelFormatVersion, "LWPR");
  const std::string& payload = frame.payload;
  ModelFileReader r(payload, frame.payload_offset, "LWPR");
  const int n_in = static_cast<int>(r.get_dimension("n_in", 1, kMaxDimension));
  const int n_out = static_cast<int>(r.get_dimension("n_out", 1, kMaxDimension));
  const std::uint64_t n_updates = r.get_u64();
  const LwprParams params = get_params(r, n_in, n_out, frame.version);
  std::vector<std::vector<ReceptiveField>> fields(n_out);
  for (int o = 0; o < n_out; ++o) {
    const std::uint64_t count = r.get_u64();
    if (count > payload.size()) r.fail("field count " + std::to_string(count) + " is impossible");
    for (std::uint64_t k = 0; k < count; ++k) fields[o].push_back(get_field(r, n_in, params.diag_only));
  }
  if (!r.at_end()) r.fail("trailing bytes after the last field");
  try {
    return LwprModel(n_in, n_out, params, std::move(fields), n_updates);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("LWPR model file: ") + e.what());
  }
}

}  // namespace armfarm::lwpr
