#pragma once
// Running statistics of a job's signals, accumulated tick by tick without storing the run.
#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace armfarm {

/// The error of one dimension of an NmseAccumulator: the RMSE always (when anything was
/// added), the nMSE only where the target's standard deviation reaches the floor.
struct NormalisedError {
  std::optional<double> nmse;  ///< empty = undefined, see `reason`
  double rmse = 0.0;           ///< target units
  double target_std = 0.0;     ///< target units
  std::string reason;          ///< why the nMSE is undefined; empty when defined
};

/// Per-dimension normalised mean squared error: mean((estimate − target)²) / var(target), the
/// thesis's nMSE. The target variance is accumulated with Welford's update (stable for long runs).
class NmseAccumulator {
 public:
  explicit NmseAccumulator(int dimensions = 0);
  void add(const Eigen::VectorXd& target, const Eigen::VectorXd& estimate);
  long count() const { return count_; }
  /// nMSE per dimension; NaN where the target never varied or nothing was added.
  Eigen::VectorXd calc_nmse() const;
  Eigen::VectorXd calc_mse() const;
  /// Population variance of the target per dimension (NaN when nothing was added).
  Eigen::VectorXd calc_target_variance() const;
  /// Per dimension: the nMSE where std(target) >= `std_floor[i]` (target units, > 0), else
  /// undefined with a reason naming the std, the floor and `unit`.
  std::vector<NormalisedError> calc_errors(const Eigen::VectorXd& std_floor, const std::string& unit) const;

 private:
  long count_ = 0;
  Eigen::VectorXd squared_error_sum_, mean_, m2_;
};

/// The thesis's feed-forward share statistics (tables 6.1–6.7) per joint: r = |ff|/(|ff|+|fb|)
/// averaged and its variance, and the mean absolute feed-forward and feedback torques (N·m).
/// Ticks with |ff| + |fb| = 0 do not count towards r.
class FeedForwardShareAccumulator {
 public:
  explicit FeedForwardShareAccumulator(int joints = 0);
  void add(const Eigen::VectorXd& feed_forward, const Eigen::VectorXd& feedback);
  long count() const { return count_; }
  Eigen::VectorXd calc_ratio_mean() const;
  Eigen::VectorXd calc_ratio_variance() const;
  Eigen::VectorXd calc_feed_forward_abs_mean() const;
  Eigen::VectorXd calc_feedback_abs_mean() const;

 private:
  long count_ = 0;
  Eigen::VectorXd ratio_count_, ratio_mean_, ratio_m2_, ff_abs_sum_, fb_abs_sum_;
};

}  // namespace armfarm
