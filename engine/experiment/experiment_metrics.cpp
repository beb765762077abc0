#include "engine/experiment/experiment_metrics.hpp"

#include <cmath>
#include <utility>

namespace armfarm {

MetricWriter::MetricWriter(std::vector<Metric>& metrics, std::vector<int> joint_numbers, std::string prefix,
                           std::optional<int> checkpoint)
    : metrics_(metrics), joint_numbers_(std::move(joint_numbers)), prefix_(std::move(prefix)), checkpoint_(checkpoint) {}

Metric MetricWriter::make_metric(const std::string& name, std::optional<int> joint, double value, std::string reason) const {
  Metric metric{prefix_ + name, joint, std::nullopt, std::nullopt, std::move(reason)};
  if (checkpoint_) metric.checkpoint = MetricCheckpoint{*checkpoint_};
  if (std::isfinite(value)) {
    metric.value = value;
  } else if (metric.reason.empty()) {
    metric.reason = std::isnan(value) ? "undefined (nothing to average)" : "infinite";
  }
  return metric;
}

void MetricWriter::add(const std::string& name, double value, std::string reason) {
  metrics_.push_back(make_metric(name, std::nullopt, value, std::move(reason)));
}

void MetricWriter::add_joints(const std::string& name, const Eigen::VectorXd& values, const std::string& reason_if_undefined) {
  for (std::size_t j = 0; j < joint_numbers_.size(); ++j) {
    const double value = values[static_cast<Eigen::Index>(j)];
    metrics_.push_back(make_metric(name, joint_numbers_[j], value, std::isfinite(value) ? std::string() : reason_if_undefined));
  }
}

void MetricWriter::add_error_metrics(const std::string& nmse_name, const std::string& rmse_name, const NmseAccumulator& errors,
                                     const Eigen::VectorXd& std_floor, const std::string& unit) {
  const std::vector<NormalisedError> per_joint = errors.calc_errors(std_floor, unit);
  const int n = static_cast<int>(joint_numbers_.size());
  double sum = 0.0;
  int defined = 0;
  std::string left_out;
  for (int j = 0; j < n; ++j) {
    const NormalisedError& error = per_joint[static_cast<std::size_t>(j)];
    Metric nmse = make_metric(nmse_name, joint_numbers_[static_cast<std::size_t>(j)], 0.0, error.reason);
    nmse.value = error.nmse;
    metrics_.push_back(std::move(nmse));
    metrics_.push_back(make_metric(rmse_name, joint_numbers_[static_cast<std::size_t>(j)], error.rmse, {}));
    if (error.nmse) {
      sum += *error.nmse;
      ++defined;
    } else {
      left_out += (left_out.empty() ? "" : ", ") + std::to_string(joint_numbers_[static_cast<std::size_t>(j)]);
    }
  }
  std::string note = "mean over " + std::to_string(defined) + " of " + std::to_string(n) + " joints";
  if (!left_out.empty()) note += "; left out (nMSE undefined): joint " + left_out;
  add(nmse_name, defined ? sum / defined : std::nan(""), note);
  add(rmse_name, std::sqrt(errors.calc_mse().mean()));
}

}  // namespace armfarm
