#include "engine/experiment/series_recorder.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace armfarm {

namespace {

constexpr const char* kHeldoutPrefix = "heldout_";

bool is_heldout_name(const std::string& name) { return name.rfind(kHeldoutPrefix, 0) == 0; }

}  // namespace

const std::vector<std::string>& recordable_series_names() {
  static const std::vector<std::string> names = [] {
    const std::vector<std::string> per_tick = {"POS", "POS_D", "PHI", "PHI_D", "VEL", "VEL_D", "ACC", "ACC_D", "TOR", "F", "FF", "RF"};
    std::vector<std::string> all = per_tick;
    all.push_back("TRIAL");
    for (const std::string& name : per_tick) all.push_back(kHeldoutPrefix + name);
    return all;
  }();
  return names;
}

std::vector<std::string> select_pass_series(const std::vector<std::string>& requested) {
  std::vector<std::string> names;
  for (const std::string& name : requested) {
    if (!is_heldout_name(name)) names.push_back(name);
  }
  return names;
}

std::vector<std::string> select_heldout_series(const std::vector<std::string>& requested) {
  std::vector<std::string> names;
  for (const std::string& name : requested) {
    if (is_heldout_name(name)) names.push_back(name.substr(std::char_traits<char>::length(kHeldoutPrefix)));
  }
  return names;
}

std::string make_heldout_series_name(const std::string& name, long checkpoint) {
  return kHeldoutPrefix + name + "_c" + std::to_string(checkpoint);
}

SeriesRecorder::SeriesRecorder(const std::vector<std::string>& requested, const std::vector<int>& joint_numbers)
    : joint_numbers_(joint_numbers) {
  const auto& known = recordable_series_names();
  for (const std::string& name : requested) {
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      throw std::invalid_argument("recording.series: unknown series \"" + name + "\"");
    }
    buffers_[name];
  }
}

void SeriesRecorder::add(const std::string& name, double time, const Eigen::VectorXd& values) {
  const auto found = buffers_.find(name);
  if (found == buffers_.end()) return;
  Buffer& buffer = found->second;
  if (buffer.columns.empty()) {
    buffer.columns.push_back("t");
    if (name == "POS" || name == "POS_D") {
      buffer.columns.insert(buffer.columns.end(), {"x", "y", "z"});
    } else if (name == "RF") {
      buffer.columns.push_back("n_receptive_fields");
    } else {
      for (int joint : joint_numbers_) buffer.columns.push_back("j" + std::to_string(joint));
    }
  }
  buffer.values.push_back(time);
  buffer.values.insert(buffer.values.end(), values.data(), values.data() + values.size());
}

void SeriesRecorder::add_row(const std::string& name, const std::vector<std::string>& columns, const Eigen::VectorXd& values) {
  const auto found = buffers_.find(name);
  if (found == buffers_.end()) return;
  Buffer& buffer = found->second;
  if (buffer.columns.empty()) buffer.columns = columns;
  buffer.values.insert(buffer.values.end(), values.data(), values.data() + values.size());
}

std::vector<Series> SeriesRecorder::take_series() {
  std::vector<Series> result;
  for (auto& [name, buffer] : buffers_) {
    Series series;
    series.name = name;
    series.columns = buffer.columns;
    const auto width = static_cast<Eigen::Index>(buffer.columns.size());
    const Eigen::Index rows = width == 0 ? 0 : static_cast<Eigen::Index>(buffer.values.size()) / width;
    series.rows = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
        buffer.values.data(), rows, width);
    result.push_back(std::move(series));
  }
  buffers_.clear();
  return result;
}

}  // namespace armfarm
