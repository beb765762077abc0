#include "engine/trajectory/savitzky_golay.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace armfarm {

Eigen::MatrixXd calc_savitzky_golay(const Eigen::MatrixXd& signal, int window, int order, int derivative, double dt) {
  const int rows = static_cast<int>(signal.rows());
  const int half = window / 2;
  Eigen::MatrixXd result(signal.rows(), signal.cols());
  // Fit in local time τ = (i − centre)·dt over window positions; the row of the fit operator
  // evaluated at the sample's own τ gives its weights.
  for (int i = 0; i < rows; ++i) {
    const int first = std::clamp(i - half, 0, rows - window);
    Eigen::MatrixXd vandermonde(window, order + 1);
    for (int r = 0; r < window; ++r) {
      const double tau = (first + r - i) * 1.0;  // in samples; scaled by dt below
      double power = 1.0;
      for (int c = 0; c <= order; ++c, power *= tau) vandermonde(r, c) = power;
    }
    // Coefficients a = (VᵀV)⁻¹Vᵀ y; the derivative at τ = 0 is derivative!·a_derivative.
    const Eigen::MatrixXd fit = (vandermonde.transpose() * vandermonde).ldlt().solve(vandermonde.transpose());
    double factorial = 1.0;
    for (int k = 2; k <= derivative; ++k) factorial *= k;
    const Eigen::RowVectorXd weights = fit.row(derivative) * (factorial / std::pow(dt, derivative));
    result.row(i) = weights * signal.middleRows(first, window);
  }
  return result;
}

Eigen::MatrixXd calc_zero_phase_low_pass(const Eigen::MatrixXd& signal, double cutoff_hz, double dt) {
  const double time_constant = 1.0 / (2.0 * M_PI * cutoff_hz);
  const double alpha = dt / (time_constant + dt);
  Eigen::MatrixXd forward = signal;
  for (Eigen::Index i = 1; i < signal.rows(); ++i) forward.row(i) = forward.row(i - 1) + alpha * (signal.row(i) - forward.row(i - 1));
  Eigen::MatrixXd backward = forward;
  for (Eigen::Index i = signal.rows() - 2; i >= 0; --i) {
    backward.row(i) = backward.row(i + 1) + alpha * (forward.row(i) - backward.row(i + 1));
  }
  return backward;
}

}  // namespace armfarm
