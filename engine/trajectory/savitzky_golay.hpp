#pragma once
// Savitzky–Golay smoothing and differentiation of uniformly sampled signals: a polynomial of
// the given order fitted by least squares to each window of samples, evaluated (or
// differentiated) at the sample. Near the ends the window is shifted inside the signal.
#include <Eigen/Core>

namespace armfarm {

/// Returns the `derivative`-th derivative (0 = smoothed value) of each column of `signal`
/// (rows = samples, spacing dt seconds). Preconditions: window odd, window > order ≥ derivative,
/// signal.rows() ≥ window.
Eigen::MatrixXd calc_savitzky_golay(const Eigen::MatrixXd& signal, int window, int order, int derivative, double dt);

/// First-order low-pass (exponential smoothing) with cutoff `cutoff_hz`, run forwards and then
/// backwards so that it adds no lag.
Eigen::MatrixXd calc_zero_phase_low_pass(const Eigen::MatrixXd& signal, double cutoff_hz, double dt);

}  // namespace armfarm
