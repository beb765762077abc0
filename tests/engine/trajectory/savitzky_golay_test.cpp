// Savitzky–Golay filters reproduce polynomials up to their order exactly (value and
// derivatives), also at the ends; the zero-phase low pass smooths without lag. The trajectories
// built with them: build_trajectory_test.cpp.
#include "engine/trajectory/savitzky_golay.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace armfarm {
namespace {

TEST(SavitzkyGolay, IsExactOnACubic) {
  const double dt = 0.01;
  Eigen::MatrixXd signal(60, 1), velocity(60, 1), acceleration(60, 1);
  for (int i = 0; i < 60; ++i) {
    const double t = i * dt;
    signal(i, 0) = 0.3 - 2.0 * t + 1.5 * t * t + 4.0 * t * t * t;
    velocity(i, 0) = -2.0 + 3.0 * t + 12.0 * t * t;
    acceleration(i, 0) = 3.0 + 24.0 * t;
  }
  EXPECT_LT((calc_savitzky_golay(signal, 11, 3, 0, dt) - signal).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT((calc_savitzky_golay(signal, 11, 3, 1, dt) - velocity).cwiseAbs().maxCoeff(), 1e-7);
  EXPECT_LT((calc_savitzky_golay(signal, 11, 3, 2, dt) - acceleration).cwiseAbs().maxCoeff(), 1e-4);
}

TEST(SavitzkyGolay, SmoothsNoiseAndLowPassHasNoLag) {
  const double dt = 0.01;
  Eigen::MatrixXd clean(400, 1), noisy(400, 1);
  for (int i = 0; i < 400; ++i) {
    clean(i, 0) = std::sin(2.0 * M_PI * 0.5 * i * dt);
    noisy(i, 0) = clean(i, 0) + ((i * 7919) % 13 - 6) * 1e-3;  // deterministic ±6 mrad noise
  }
  const double raw = (noisy - clean).norm();
  EXPECT_LT((calc_savitzky_golay(noisy, 21, 3, 0, dt) - clean).norm(), 0.5 * raw);
  const Eigen::MatrixXd low = calc_zero_phase_low_pass(clean, 5.0, dt);
  // A causal filter would lag by about 1/(2π·5 Hz) = 32 ms; forward-backward does not shift.
  int peak_clean = 0, peak_low = 0;
  clean.col(0).segment(50, 200).maxCoeff(&peak_clean);
  low.col(0).segment(50, 200).maxCoeff(&peak_low);
  EXPECT_LE(std::abs(peak_clean - peak_low), 1);
}

}  // namespace
}  // namespace armfarm
