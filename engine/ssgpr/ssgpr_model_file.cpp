// Versioned little-endian binary serialisation of SsgprModel.
#include "engine/ssgpr/ssgpr_model_file.hpp"

#include <cmath>
#include <cstring>
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
constexpr std::size_t kHeaderBytes = 12;  // version + payload length

std::uint64_t calc_fnv1a(const std::string& bytes) {
  std::uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

class Writer {
 public:
  void put_u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
  }
  void put_u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
  }
  void put_f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    put_u64(bits);
  }
  void put_matrix(const Eigen::MatrixXd& m) {
    put_u32(static_cast<std::uint32_t>(m.rows()));
    put_u32(static_cast<std::uint32_t>(m.cols()));
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
      for (Eigen::Index r = 0; r < m.rows(); ++r) put_f64(m(r, c));
    }
  }
  /// Lower triangle of a square matrix, column by column (diagonal included).
  void put_lower(const Eigen::MatrixXd& m) {
    put_u32(static_cast<std::uint32_t>(m.rows()));
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
      for (Eigen::Index r = c; r < m.rows(); ++r) put_f64(m(r, c));
    }
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class Reader {
 public:
  Reader(const std::string& bytes, std::size_t base) : bytes_(bytes), base_(base) {}
  /// Fails naming the byte where the value being read starts (or the current position).
  [[noreturn]] void fail(const std::string& what) const { fail_at(pos_, what); }
  [[noreturn]] void fail_at(std::size_t pos, const std::string& what) const {
    throw std::runtime_error("SSGPR model file: byte " + std::to_string(base_ + pos) + ": " + what);
  }
  std::uint64_t get_u64() {
    need(8);
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes_[pos_ + i])) << (8 * i);
    pos_ += 8;
    return v;
  }
  std::uint32_t get_u32() {
    need(4);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes_[pos_ + i])) << (8 * i);
    pos_ += 4;
    return v;
  }
  double get_f64() {
    const std::uint64_t bits = get_u64();
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  double get_finite(const char* name) {
    const std::size_t at = pos_;
    const double v = get_f64();
    if (!std::isfinite(v)) fail_at(at, std::string(name) + " is not finite");
    return v;
  }
  Eigen::MatrixXd get_matrix(Eigen::Index rows, Eigen::Index cols, const char* name) {
    const std::uint32_t r = get_u32(), c = get_u32();
    if (r != rows || c != cols) {
      fail(std::string(name) + " is " + std::to_string(r) + "x" + std::to_string(c) + ", expected " +
           std::to_string(rows) + "x" + std::to_string(cols));
    }
    need_doubles(static_cast<std::uint64_t>(rows) * static_cast<std::uint64_t>(cols), name);
    Eigen::MatrixXd m(rows, cols);
    for (Eigen::Index j = 0; j < cols; ++j) {
      for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = get_finite(name);
    }
    return m;
  }
  Eigen::MatrixXd get_lower(Eigen::Index n, const char* name) {
    const std::uint32_t r = get_u32();
    if (r != n) fail(std::string(name) + " has order " + std::to_string(r) + ", expected " + std::to_string(n));
    need_doubles(static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n + 1) / 2, name);
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index i = j; i < n; ++i) m(i, j) = get_finite(name);
    }
    return m;
  }
  std::uint32_t get_dimension(const char* name, std::uint32_t lo, std::uint32_t hi) {
    const std::size_t at = pos_;
    const std::uint32_t v = get_u32();
    if (v < lo || v > hi) fail_at(at, std::string(name) + " is " + std::to_string(v) + ", out of range");
    return v;
  }
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  void need(std::size_t n) const {
    if (bytes_.size() - pos_ < n) fail("unexpected end of data");
  }
  /// Refuses a matrix larger than the bytes left, before allocating it.
  void need_doubles(std::uint64_t count, const char* name) const {
    if (count > (bytes_.size() - pos_) / 8) fail(std::string(name) + " needs more bytes than the file has left");
  }
  const std::string& bytes_;
  std::size_t base_;
  std::size_t pos_ = 0;
};

void put_vector(Writer& w, const Eigen::VectorXd& v) { w.put_matrix(v); }

Eigen::VectorXd get_vector(Reader& r, int dim, const char* name) {
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
  Writer payload;
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
  Writer header;
  header.put_u32(kSsgprModelFormatVersion);
  header.put_u64(payload.bytes().size());
  Writer trailer;
  trailer.put_u64(calc_fnv1a(payload.bytes()));
  out.write(kMagic, sizeof kMagic);
  out.write(header.bytes().data(), static_cast<std::streamsize>(header.bytes().size()));
  out.write(payload.bytes().data(), static_cast<std::streamsize>(payload.bytes().size()));
  out.write(trailer.bytes().data(), static_cast<std::streamsize>(trailer.bytes().size()));
  if (!out) throw std::runtime_error("SSGPR model file: write failed");
}

SsgprModel load_ssgpr_model(std::istream& in) {
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (all.size() < sizeof kMagic || std::memcmp(all.data(), kMagic, sizeof kMagic) != 0) {
    throw std::runtime_error("SSGPR model file: byte 0: not an armfarm SSGPR model (bad magic)");
  }
  const std::string header = all.substr(sizeof kMagic, kHeaderBytes);
  Reader head(header, sizeof kMagic);
  const std::uint32_t version = head.get_u32();
  if (version > kSsgprModelFormatVersion) {
    throw std::runtime_error("SSGPR model file: format version " + std::to_string(version) +
                             " is newer than this armfarm reads (" + std::to_string(kSsgprModelFormatVersion) +
                             "); upgrade armfarm");
  }
  if (version == 0) head.fail("format version 0 is invalid");
  const std::uint64_t length = head.get_u64();
  const std::size_t start = sizeof kMagic + kHeaderBytes;
  if (length > all.size() || all.size() != start + length + 8) {
    throw std::runtime_error("SSGPR model file: size " + std::to_string(all.size()) + " bytes, expected " +
                             std::to_string(start + length + 8) + " (truncated or corrupt)");
  }
  const std::string payload = all.substr(start, length);
  const std::string trailer = all.substr(start + length);
  Reader tail(trailer, start + length);
  if (tail.get_u64() != calc_fnv1a(payload)) {
    throw std::runtime_error("SSGPR model file: byte " + std::to_string(start + length) +
                             ": checksum mismatch (corrupt file)");
  }
  Reader r(payload, start);
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
  s.frequencies = r.get_matrix(p.features, n_in, "frequencies");
  s.factor = r.get_lower(F, "Cholesky factor");
  s.rhs = r.get_matrix(F, n_out, "right-hand side");
  s.weights = r.get_matrix(F, n_out, "weights");
  if (!r.at_end()) r.fail("trailing bytes after the weights");
  try {
    return SsgprModel(n_in, n_out, p, std::move(s));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("SSGPR model file: ") + e.what());
  }
}

}  // namespace armfarm::ssgpr
