#pragma once
// The byte layer shared by the learners' model files (engine/lwpr/lwpr_model_file,
// engine/ssgpr/ssgpr_model_file): little-endian integers and IEEE-754 doubles, column-major
// matrices prefixed by their sizes, and the FNV-1a checksum of a payload. Each file format keeps
// its own magic, version and field order; only the encoding lives here.
#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>

namespace armfarm {

/// 64-bit FNV-1a of a byte string (the payload checksum).
std::uint64_t calc_model_file_checksum(const std::string& bytes);

class ModelFileWriter;

/// Writes a whole model file: the 8-byte `magic`, the header (format `version` u32, payload size
/// u64), `payload` and its checksum (u64). Throws std::runtime_error "<format> model file:
/// write failed" when the stream fails.
void write_model_file_frame(std::ostream& out, const char (&magic)[8], std::uint32_t version,
                            const ModelFileWriter& payload, const char* format);

/// A model file's frame, checked: its format version and its payload (checksum verified).
struct ModelFileFrame {
  std::uint32_t version = 0;
  std::string payload;
  std::size_t payload_offset = 0;  ///< byte of the file where the payload starts
};

/// Checks the frame that write_model_file_frame writes around `all` (a whole file): the magic,
/// a version in [1, newest_version], the payload size against the file size, and the checksum.
/// Throws std::runtime_error "<format> model file: ..." naming the byte or the sizes.
ModelFileFrame read_model_file_frame(const std::string& all, const char (&magic)[8], std::uint32_t newest_version,
                                     const char* format);

/// Appends encoded values to a byte string.
class ModelFileWriter {
 public:
  void put_u64(std::uint64_t v);
  void put_u32(std::uint32_t v);
  void put_f64(double v);
  void put_bool(bool v);  ///< as a u32, 0 or 1
  /// rows, cols (u32 each), then the entries column by column.
  void put_matrix(const Eigen::MatrixXd& m);
  /// Order n (u32), then the lower triangle of a square matrix column by column, diagonal included.
  void put_lower(const Eigen::MatrixXd& m);
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

/// Reads encoded values from `bytes` (kept by reference: it must outlive the reader), which start
/// at byte `base` of the file. Errors throw
/// std::runtime_error "<format> model file: byte N: what", N where the offending value starts.
class ModelFileReader {
 public:
  ModelFileReader(const std::string& bytes, std::size_t base, std::string format)
      : bytes_(bytes), base_(base), format_(std::move(format)) {}
  ModelFileReader(std::string&&, std::size_t, std::string) = delete;  // would dangle

  [[noreturn]] void fail(const std::string& what) const { fail_at(pos_, what); }
  [[noreturn]] void fail_at(std::size_t pos, const std::string& what) const;

  std::uint64_t get_u64();
  std::uint32_t get_u32();
  double get_f64();
  double get_finite(const char* name);  ///< refuses NaN and ±inf
  bool get_bool();                      ///< refuses values other than 0 and 1
  /// A rows × cols matrix; refuses other sizes, and a matrix larger than the bytes left before
  /// allocating it. `finite`: refuse NaN and ±inf entries.
  Eigen::MatrixXd get_matrix(Eigen::Index rows, Eigen::Index cols, const char* name, bool finite = false);
  Eigen::VectorXd get_vector(Eigen::Index size, const char* name, bool finite = false) {
    return get_matrix(size, 1, name, finite).col(0);
  }
  /// The lower triangle written by put_lower (upper part zero); entries must be finite.
  Eigen::MatrixXd get_lower(Eigen::Index n, const char* name);
  /// A u32 in [lo, hi].
  std::uint32_t get_dimension(const char* name, std::uint32_t lo, std::uint32_t hi);
  bool at_end() const { return pos_ == bytes_.size(); }

 private:
  void need(std::size_t n) const;
  void need_doubles(std::uint64_t count, const char* name) const;

  const std::string& bytes_;
  std::size_t base_;
  std::string format_;
  std::size_t pos_ = 0;
};

}  // namespace armfarm
