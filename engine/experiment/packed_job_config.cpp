#include "engine/experiment/packed_job_config.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace armfarm {
namespace {

// The bytes of one field's value, as field_bytes writes them and read_field_bytes reads them:
// numbers as their object representation, lists and texts after their sizes.
class ByteWriter {
 public:
  explicit ByteWriter(std::string& out) : out_(out) {}
  template <typename T>
  void add(const T& value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out_.append(bytes, sizeof(T));
  }
  void add_doubles(const double* values, std::size_t count) {
    add(static_cast<std::uint64_t>(count));
    if (count != 0) out_.append(reinterpret_cast<const char*>(values), sizeof(double) * count);  // values may be null
  }
  void add_text(const std::string& text) {
    add(static_cast<std::uint64_t>(text.size()));
    out_ += text;
  }

 private:
  std::string& out_;
};

class ByteReader {
 public:
  ByteReader(const char* data, std::size_t size) : data_(data), end_(data + size) {}
  template <typename T>
  T take() {
    T value;
    take_bytes(&value, sizeof(T));
    return value;
  }
  std::size_t take_count() { return static_cast<std::size_t>(take<std::uint64_t>()); }
  void take_doubles(double* values, std::size_t count) { take_bytes(values, sizeof(double) * count); }
  std::string take_text() {
    const std::size_t size = take_count();
    check(size);
    std::string text(data_, size);
    data_ += size;
    return text;
  }
  /// A reader of the next `size` bytes, which it skips.
  ByteReader take_part(std::size_t size) {
    check(size);
    ByteReader part(data_, size);
    data_ += size;
    return part;
  }
  bool done() const { return data_ == end_; }

 private:
  void check(std::size_t size) const {
    if (static_cast<std::size_t>(end_ - data_) < size) throw std::logic_error("a packed job configuration is cut short");
  }
  void take_bytes(void* out, std::size_t size) {
    check(size);
    if (size == 0) return;  // an empty list's data() may be null, which memcpy may not be given
    std::memcpy(out, data_, size);
    data_ += size;
  }
  const char* data_;
  const char* end_;
};

void write_field_bytes(const FieldRef& field, std::string& out) {
  ByteWriter w(out);
  switch (field.kind) {
    case ValueKind::real: w.add(field.real()); return;
    case ValueKind::integer:
    case ValueKind::choice: w.add(field.get_integer(field.field)); return;
    case ValueKind::boolean: w.add(field.boolean()); return;
    case ValueKind::text: w.add_text(field.text()); return;
    case ValueKind::real_list:
    case ValueKind::real_or_list: w.add_doubles(field.vector().data(), static_cast<std::size_t>(field.vector().size())); return;
    case ValueKind::point: w.add_doubles(field.point().data(), 3); return;
    case ValueKind::integer_list:
      w.add(static_cast<std::uint64_t>(field.integers().size()));
      for (int value : field.integers()) w.add(value);
      return;
    case ValueKind::name_list:
      w.add(static_cast<std::uint64_t>(field.texts().size()));
      for (const std::string& name : field.texts()) w.add_text(name);
      return;
    case ValueKind::real_matrix:
      w.add(static_cast<std::int64_t>(field.matrix().rows()));
      w.add(static_cast<std::int64_t>(field.matrix().cols()));
      w.add_doubles(field.matrix().data(), static_cast<std::size_t>(field.matrix().size()));
      return;
    case ValueKind::integer_or_auto:
      w.add(field.optional_integer().has_value());
      w.add(field.optional_integer().value_or(0));
      return;
    case ValueKind::real_or_auto:
      w.add(field.optional_real().has_value());
      w.add(field.optional_real().value_or(0.0));
      return;
    case ValueKind::point_or_auto:
      w.add(field.optional_point().has_value());
      w.add_doubles(field.optional_point().value_or(Eigen::Vector3d::Zero()).data(), 3);
      return;
  }
}

Eigen::VectorXd read_vector(ByteReader& r) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(r.take_count()));
  r.take_doubles(v.data(), static_cast<std::size_t>(v.size()));
  return v;
}

Eigen::Vector3d read_point(ByteReader& r) {
  if (r.take_count() != 3) throw std::logic_error("a packed point has not 3 numbers");
  Eigen::Vector3d p;
  r.take_doubles(p.data(), 3);
  return p;
}

void read_field_bytes(ByteReader& r, const FieldRef& field) {
  switch (field.kind) {
    case ValueKind::real: field.real() = r.take<double>(); return;
    case ValueKind::integer:
    case ValueKind::choice: field.set_integer(field.field, r.take<long long>()); return;
    case ValueKind::boolean: field.boolean() = r.take<bool>(); return;
    case ValueKind::text: field.text() = r.take_text(); return;
    case ValueKind::real_list:
    case ValueKind::real_or_list: field.vector() = read_vector(r); return;
    case ValueKind::point: field.point() = read_point(r); return;
    case ValueKind::integer_list: {
      std::vector<int> values(r.take_count());
      for (int& value : values) value = r.take<int>();
      field.integers() = std::move(values);
      return;
    }
    case ValueKind::name_list: {
      std::vector<std::string> names(r.take_count());
      for (std::string& name : names) name = r.take_text();
      field.texts() = std::move(names);
      return;
    }
    case ValueKind::real_matrix: {
      const auto rows = static_cast<Eigen::Index>(r.take<std::int64_t>());
      const auto cols = static_cast<Eigen::Index>(r.take<std::int64_t>());
      Eigen::MatrixXd m(rows, cols);
      if (r.take_count() != static_cast<std::size_t>(m.size())) throw std::logic_error("a packed matrix has the wrong size");
      r.take_doubles(m.data(), static_cast<std::size_t>(m.size()));
      field.matrix() = std::move(m);
      return;
    }
    case ValueKind::integer_or_auto: {
      const bool set = r.take<bool>();
      const int value = r.take<int>();
      field.optional_integer() = set ? std::optional<int>(value) : std::nullopt;
      return;
    }
    case ValueKind::real_or_auto: {
      const bool set = r.take<bool>();
      const double value = r.take<double>();
      field.optional_real() = set ? std::optional<double>(value) : std::nullopt;
      return;
    }
    case ValueKind::point_or_auto: {
      const bool set = r.take<bool>();
      const Eigen::Vector3d value = read_point(r);
      field.optional_point() = set ? std::optional<Eigen::Vector3d>(value) : std::nullopt;
      return;
    }
  }
}

// Each key's bytes in a default JobConfig, made once per process.
const std::vector<std::string>& default_field_bytes() {
  static const std::vector<std::string> bytes = [] {
    JobConfig defaults;
    std::vector<std::string> all;
    for (const JobConfigKey& key : job_config_keys()) {
      all.emplace_back();
      write_field_bytes(key.field(defaults), all.back());
    }
    return all;
  }();
  return bytes;
}

bool has_file_data(const JobConfig& config) {
  return config.trajectory.recorded.samples.size() != 0 || !config.trajectory.recorded.sample_lines.empty() ||
         !config.learning.initial_model_bytes.empty();
}

bool holds_file_data(const JobFileData& files, const JobConfig& config) {
  const RecordedTrajectoryConfig& recorded = config.trajectory.recorded;
  const Eigen::MatrixXd& samples = files.recorded_samples;
  return samples.rows() == recorded.samples.rows() && samples.cols() == recorded.samples.cols() &&
         (samples.size() == 0 ||  // empty matrices' data() are null, which memcmp may not be given
          std::memcmp(samples.data(), recorded.samples.data(), sizeof(double) * static_cast<std::size_t>(samples.size())) == 0) &&
         files.recorded_lines == recorded.sample_lines && files.initial_model_bytes == config.learning.initial_model_bytes;
}

}  // namespace

std::string pack_job_config_keys(const JobConfig& config) {
  // The key table hands out references to non-const fields; packing only reads them.
  JobConfig& fields = const_cast<JobConfig&>(config);
  const std::vector<JobConfigKey>& keys = job_config_keys();
  const std::vector<std::string>& defaults = default_field_bytes();
  std::string packed, bytes;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    bytes.clear();
    write_field_bytes(keys[i].field(fields), bytes);
    if (bytes == defaults[i]) continue;
    ByteWriter w(packed);
    w.add(static_cast<std::uint32_t>(i));
    w.add(static_cast<std::uint32_t>(bytes.size()));
    packed += bytes;
  }
  return packed;
}

JobConfig unpack_job_config_keys(const std::string& packed) {
  JobConfig config;
  const std::vector<JobConfigKey>& keys = job_config_keys();
  ByteReader r(packed.data(), packed.size());
  while (!r.done()) {
    const std::uint32_t index = r.take<std::uint32_t>();
    const std::uint32_t size = r.take<std::uint32_t>();
    ByteReader field = r.take_part(size);
    read_field_bytes(field, keys.at(index).field(config));
    if (!field.done()) throw std::logic_error("a packed value of " + keys.at(index).path + " is longer than its kind");
  }
  return config;
}

PackedValidJobConfig::PackedValidJobConfig(const ValidJobConfig& valid, const std::shared_ptr<const JobFileData>& shared_files)
    : values_(pack_job_config_keys(valid.get())) {
  values_.shrink_to_fit();
  const JobConfig& config = valid.get();
  if (!has_file_data(config)) return;
  if (shared_files && holds_file_data(*shared_files, config)) {
    files_ = shared_files;
    return;
  }
  files_ = std::make_shared<const JobFileData>(
      JobFileData{config.trajectory.recorded.samples, config.trajectory.recorded.sample_lines, config.learning.initial_model_bytes});
}

ValidJobConfig PackedValidJobConfig::unpack() const {
  JobConfig config = unpack_job_config_keys(values_);
  if (files_) {
    config.trajectory.recorded.samples = files_->recorded_samples;
    config.trajectory.recorded.sample_lines = files_->recorded_lines;
    config.learning.initial_model_bytes = files_->initial_model_bytes;
  }
  return ValidJobConfig(std::move(config));
}

std::size_t PackedValidJobConfig::calc_own_bytes() const { return sizeof(*this) + values_.capacity(); }

}  // namespace armfarm
