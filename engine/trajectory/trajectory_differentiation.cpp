#include "engine/trajectory/trajectory_differentiation.hpp"

#include "engine/trajectory/savitzky_golay.hpp"

namespace armfarm {
namespace {

Eigen::MatrixXd calc_backward_difference(const Eigen::MatrixXd& signal, double dt) {
  Eigen::MatrixXd derivative = Eigen::MatrixXd::Zero(signal.rows(), signal.cols());
  for (Eigen::Index i = 1; i < signal.rows(); ++i) derivative.row(i) = (signal.row(i) - signal.row(i - 1)) / dt;
  return derivative;
}

Eigen::MatrixXd calc_central_difference(const Eigen::MatrixXd& signal, double dt, bool periodic) {
  const Eigen::Index rows = signal.rows();
  Eigen::MatrixXd derivative(rows, signal.cols());
  for (Eigen::Index i = 0; i < rows; ++i) {
    if (periodic) {
      derivative.row(i) = (signal.row((i + 1) % rows) - signal.row((i + rows - 1) % rows)) / (2.0 * dt);
    } else if (i == 0) {
      derivative.row(i) = (-3.0 * signal.row(0) + 4.0 * signal.row(1) - signal.row(2)) / (2.0 * dt);
    } else if (i == rows - 1) {
      derivative.row(i) = (3.0 * signal.row(i) - 4.0 * signal.row(i - 1) + signal.row(i - 2)) / (2.0 * dt);
    } else {
      derivative.row(i) = (signal.row(i + 1) - signal.row(i - 1)) / (2.0 * dt);
    }
  }
  return derivative;
}

}  // namespace

void fill_derivatives(JointTrajectory& trajectory, Differentiation method, bool periodic, int window, int order) {
  const double dt = trajectory.dt;
  switch (method) {
    case Differentiation::backward_difference:
      trajectory.qd = calc_backward_difference(trajectory.q, dt);
      trajectory.qdd = calc_backward_difference(trajectory.qd, dt);
      break;
    case Differentiation::smoothed:
      trajectory.qd = calc_savitzky_golay(trajectory.q, window, order, 1, dt);
      trajectory.qdd = calc_savitzky_golay(trajectory.q, window, order, 2, dt);
      break;
    case Differentiation::analytic:
      trajectory.qd = calc_central_difference(trajectory.q, dt, periodic);
      trajectory.qdd = calc_central_difference(trajectory.qd, dt, periodic);
      break;
  }
}

}  // namespace armfarm
