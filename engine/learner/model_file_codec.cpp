#include "engine/learner/model_file_codec.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace armfarm {

std::uint64_t calc_model_file_checksum(const std::string& bytes) {
  std::uint64_t hash = 14695981039346656037ull;
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

void write_model_file_frame(std::ostream& out, const char (&magic)[8], std::uint32_t version,
                            const ModelFileWriter& payload, const char* format) {
  ModelFileWriter header;
  header.put_u32(version);
  header.put_u64(payload.bytes().size());
  ModelFileWriter trailer;
  trailer.put_u64(calc_model_file_checksum(payload.bytes()));
  out.write(magic, sizeof magic);
  out.write(header.bytes().data(), static_cast<std::streamsize>(header.bytes().size()));
  out.write(payload.bytes().data(), static_cast<std::streamsize>(payload.bytes().size()));
  out.write(trailer.bytes().data(), static_cast<std::streamsize>(trailer.bytes().size()));
  if (!out) throw std::runtime_error(std::string(format) + " model file: write failed");
}

ModelFileFrame read_model_file_frame(const std::string& all, const char (&magic)[8], std::uint32_t newest_version,
                                     const char* format) {
  const std::string name(format);
  if (all.size() < sizeof magic || std::memcmp(all.data(), magic, sizeof magic) != 0) {
    throw std::runtime_error(name + " model file: byte 0: not an armfarm " + name + " model (bad magic)");
  }
  constexpr std::size_t kHeaderBytes = 12;  // version u32 + payload size u64
  const std::string header = all.substr(sizeof magic, kHeaderBytes);  // the reader keeps a reference
  ModelFileReader head(header, sizeof magic, name);
  ModelFileFrame frame;
  frame.version = head.get_u32();
  if (frame.version > newest_version) {
    throw std::runtime_error(name + " model file: format version " + std::to_string(frame.version) +
                             " is newer than this armfarm reads (" + std::to_string(newest_version) + "); upgrade armfarm");
  }
  if (frame.version == 0) head.fail("format version 0 is invalid");
  const std::uint64_t length = head.get_u64();
  const std::size_t start = sizeof magic + kHeaderBytes;
  // Compared without adding to `length`, so a huge size in a damaged header cannot wrap around.
  if (all.size() < start + 8 || length != all.size() - start - 8) {
    const std::string expected = length > all.size() ? "more than the file holds" : std::to_string(start + length + 8);
    throw std::runtime_error(name + " model file: size " + std::to_string(all.size()) + " bytes, expected " + expected +
                             " (truncated or corrupt)");
  }
  frame.payload = all.substr(start, length);
  frame.payload_offset = start;
  const std::string trailer = all.substr(start + length);
  ModelFileReader tail(trailer, start + length, name);
  if (tail.get_u64() != calc_model_file_checksum(frame.payload)) {
    throw std::runtime_error(name + " model file: byte " + std::to_string(start + length) +
                             ": checksum mismatch (corrupt file)");
  }
  return frame;
}

void ModelFileWriter::put_u64(std::uint64_t v) {
  for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

void ModelFileWriter::put_u32(std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

void ModelFileWriter::put_f64(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  put_u64(bits);
}

void ModelFileWriter::put_bool(bool v) { put_u32(v ? 1 : 0); }

void ModelFileWriter::put_matrix(const Eigen::MatrixXd& m) {
  put_u32(static_cast<std::uint32_t>(m.rows()));
  put_u32(static_cast<std::uint32_t>(m.cols()));
  for (Eigen::Index c = 0; c < m.cols(); ++c) {
    for (Eigen::Index r = 0; r < m.rows(); ++r) put_f64(m(r, c));
  }
}

void ModelFileWriter::put_lower(const Eigen::MatrixXd& m) {
  put_u32(static_cast<std::uint32_t>(m.rows()));
  for (Eigen::Index c = 0; c < m.cols(); ++c) {
    for (Eigen::Index r = c; r < m.rows(); ++r) put_f64(m(r, c));
  }
}

void ModelFileReader::fail_at(std::size_t pos, const std::string& what) const {
  throw std::runtime_error(format_ + " model file: byte " + std::to_string(base_ + pos) + ": " + what);
}

std::uint64_t ModelFileReader::get_u64() {
  need(8);
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes_[pos_ + i])) << (8 * i);
  pos_ += 8;
  return v;
}

std::uint32_t ModelFileReader::get_u32() {
  need(4);
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes_[pos_ + i])) << (8 * i);
  pos_ += 4;
  return v;
}

double ModelFileReader::get_f64() {
  const std::uint64_t bits = get_u64();
  double v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

double ModelFileReader::get_finite(const char* name) {
  const std::size_t at = pos_;
  const double v = get_f64();
  if (!std::isfinite(v)) fail_at(at, std::string(name) + " is not finite");
  return v;
}

bool ModelFileReader::get_bool() {
  const std::size_t at = pos_;
  const std::uint32_t v = get_u32();
  if (v > 1) fail_at(at, "flag is " + std::to_string(v) + ", expected 0 or 1");
  return v == 1;
}

Eigen::MatrixXd ModelFileReader::get_matrix(Eigen::Index rows, Eigen::Index cols, const char* name, bool finite) {
  const std::size_t at = pos_;
  const std::uint32_t r = get_u32(), c = get_u32();
  if (r != rows || c != cols) {
    fail_at(at, std::string(name) + " is " + std::to_string(r) + "x" + std::to_string(c) + ", expected " +
                    std::to_string(rows) + "x" + std::to_string(cols));
  }
  need_doubles(static_cast<std::uint64_t>(rows) * static_cast<std::uint64_t>(cols), name);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = finite ? get_finite(name) : get_f64();
  }
  return m;
}

Eigen::MatrixXd ModelFileReader::get_lower(Eigen::Index n, const char* name) {
  const std::size_t at = pos_;
  const std::uint32_t r = get_u32();
  if (r != n) fail_at(at, std::string(name) + " has order " + std::to_string(r) + ", expected " + std::to_string(n));
  need_doubles(static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(n + 1) / 2, name);
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = j; i < n; ++i) m(i, j) = get_finite(name);
  }
  return m;
}

std::uint32_t ModelFileReader::get_dimension(const char* name, std::uint32_t lo, std::uint32_t hi) {
  const std::size_t at = pos_;
  const std::uint32_t v = get_u32();
  if (v < lo || v > hi) fail_at(at, std::string(name) + " is " + std::to_string(v) + ", out of range");
  return v;
}

void ModelFileReader::need(std::size_t n) const {
  if (bytes_.size() - pos_ < n) fail("unexpected end of data");
}

void ModelFileReader::need_doubles(std::uint64_t count, const char* name) const {
  if (count > (bytes_.size() - pos_) / 8) fail(std::string(name) + " needs more bytes than the file has left");
}

}  // namespace armfarm
