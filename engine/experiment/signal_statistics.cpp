#include "engine/experiment/signal_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace armfarm {

NmseAccumulator::NmseAccumulator(int dimensions)
    : squared_error_sum_(Eigen::VectorXd::Zero(dimensions)),
      mean_(Eigen::VectorXd::Zero(dimensions)),
      m2_(Eigen::VectorXd::Zero(dimensions)) {}

void NmseAccumulator::add(const Eigen::VectorXd& target, const Eigen::VectorXd& estimate) {
  ++count_;
  squared_error_sum_ += (estimate - target).cwiseAbs2();
  const Eigen::VectorXd delta = target - mean_;
  mean_ += delta / static_cast<double>(count_);
  m2_ += delta.cwiseProduct(target - mean_);
}

Eigen::VectorXd NmseAccumulator::calc_mse() const {
  if (count_ == 0) return Eigen::VectorXd::Constant(mean_.size(), std::numeric_limits<double>::quiet_NaN());
  return squared_error_sum_ / static_cast<double>(count_);
}

Eigen::VectorXd NmseAccumulator::calc_nmse() const {
  const Eigen::VectorXd mse = calc_mse();
  Eigen::VectorXd nmse(mse.size());
  for (int i = 0; i < mse.size(); ++i) {
    const double variance = count_ > 0 ? m2_[i] / static_cast<double>(count_) : 0.0;
    nmse[i] = variance > 0.0 ? mse[i] / variance : std::numeric_limits<double>::quiet_NaN();
  }
  return nmse;
}

Eigen::VectorXd NmseAccumulator::calc_target_variance() const {
  if (count_ == 0) return Eigen::VectorXd::Constant(mean_.size(), std::numeric_limits<double>::quiet_NaN());
  return m2_ / static_cast<double>(count_);
}

std::vector<NormalisedError> NmseAccumulator::calc_errors(const Eigen::VectorXd& std_floor, const std::string& unit) const {
  const Eigen::VectorXd mse = calc_mse();
  const Eigen::VectorXd variance = calc_target_variance();
  std::vector<NormalisedError> errors(static_cast<std::size_t>(mse.size()));
  for (int i = 0; i < mse.size(); ++i) {
    NormalisedError& error = errors[static_cast<std::size_t>(i)];
    if (count_ == 0) {
      error.rmse = std::numeric_limits<double>::quiet_NaN();
      error.target_std = std::numeric_limits<double>::quiet_NaN();
      error.reason = "no samples";
      continue;
    }
    error.rmse = std::sqrt(mse[i]);
    error.target_std = std::sqrt(std::max(0.0, variance[i]));
    if (error.target_std >= std_floor[i] && variance[i] > 0.0) {
      error.nmse = mse[i] / variance[i];
    } else {
      char text[160];
      std::snprintf(text, sizeof text, "target std %.3g %s is below the nMSE floor %.3g %s", error.target_std,
                    unit.c_str(), std_floor[i], unit.c_str());
      error.reason = text;
    }
  }
  return errors;
}

FeedForwardShareAccumulator::FeedForwardShareAccumulator(int joints)
    : ratio_count_(Eigen::VectorXd::Zero(joints)),
      ratio_mean_(Eigen::VectorXd::Zero(joints)),
      ratio_m2_(Eigen::VectorXd::Zero(joints)),
      ff_abs_sum_(Eigen::VectorXd::Zero(joints)),
      fb_abs_sum_(Eigen::VectorXd::Zero(joints)) {}

void FeedForwardShareAccumulator::add(const Eigen::VectorXd& feed_forward, const Eigen::VectorXd& feedback) {
  ++count_;
  for (int j = 0; j < feed_forward.size(); ++j) {
    const double ff = std::fabs(feed_forward[j]);
    const double fb = std::fabs(feedback[j]);
    ff_abs_sum_[j] += ff;
    fb_abs_sum_[j] += fb;
    if (ff + fb <= 0.0) continue;
    const double ratio = ff / (ff + fb);
    ratio_count_[j] += 1.0;
    const double delta = ratio - ratio_mean_[j];
    ratio_mean_[j] += delta / ratio_count_[j];
    ratio_m2_[j] += delta * (ratio - ratio_mean_[j]);
  }
}

Eigen::VectorXd FeedForwardShareAccumulator::calc_ratio_mean() const {
  Eigen::VectorXd mean = ratio_mean_;
  for (int j = 0; j < mean.size(); ++j) {
    if (ratio_count_[j] == 0.0) mean[j] = std::numeric_limits<double>::quiet_NaN();
  }
  return mean;
}

Eigen::VectorXd FeedForwardShareAccumulator::calc_ratio_variance() const {
  Eigen::VectorXd variance(ratio_m2_.size());
  for (int j = 0; j < variance.size(); ++j) {
    variance[j] = ratio_count_[j] > 0.0 ? ratio_m2_[j] / ratio_count_[j] : std::numeric_limits<double>::quiet_NaN();
  }
  return variance;
}

Eigen::VectorXd FeedForwardShareAccumulator::calc_feed_forward_abs_mean() const {
  return count_ > 0 ? Eigen::VectorXd(ff_abs_sum_ / static_cast<double>(count_))
                    : Eigen::VectorXd::Constant(ff_abs_sum_.size(), std::numeric_limits<double>::quiet_NaN());
}

Eigen::VectorXd FeedForwardShareAccumulator::calc_feedback_abs_mean() const {
  return count_ > 0 ? Eigen::VectorXd(fb_abs_sum_ / static_cast<double>(count_))
                    : Eigen::VectorXd::Constant(fb_abs_sum_.size(), std::numeric_limits<double>::quiet_NaN());
}

}  // namespace armfarm
