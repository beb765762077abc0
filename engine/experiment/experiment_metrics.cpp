#include "engine/experiment/experiment_metrics.hpp"

#include <cmath>
#include <utility>

namespace armfarm {

MetricWriter::MetricWriter(std::vector<Metric>& metrics, std::vector<int> joint_numbers, std::string prefix,
                           std::optional<int> checkpoint)
    : metrics_(metrics), joint_numbers_(std::move(joint_numbers)), prefix_(std::move(prefix)), checkpoint_(checkpoint) {}

void MetricWriter::add(const std::string& name, double value) {
  metrics_.push_back({prefix_ + name, std::nullopt, value, checkpoint_});
}

void MetricWriter::add_joints(const std::string& name, const Eigen::VectorXd& values) {
  for (std::size_t j = 0; j < joint_numbers_.size(); ++j) {
    metrics_.push_back({prefix_ + name, joint_numbers_[j], values[static_cast<Eigen::Index>(j)], checkpoint_});
  }
}

void MetricWriter::add_joints_and_mean(const std::string& name, const Eigen::VectorXd& values) {
  add_joints(name, values);
  add(name, calc_mean_of_finite(values));
}

double calc_mean_of_finite(const Eigen::VectorXd& values) {
  double sum = 0.0;
  int count = 0;
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    if (std::isfinite(values[i])) sum += values[i], ++count;
  }
  return count ? sum / count : std::nan("");
}

}  // namespace armfarm
