#include "engine/kinematics/damped_gram.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace armfarm {
void DampedGram::factor(const Eigen::Matrix3Xd& jacobian, double lambda_squared) {
  // The lower triangle of J Jᵀ in one pass over J's columns, each sum in column order, first term first.
  const Eigen::Index n = jacobian.cols();
  const double* j = jacobian.data();  // column-major: J(r, k) = j[3k + r]
  double g00 = 0.0, g10 = 0.0, g11 = 0.0, g20 = 0.0, g21 = 0.0, g22 = 0.0;
  if (n > 0) {
    g00 = j[0] * j[0], g10 = j[1] * j[0], g11 = j[1] * j[1], g20 = j[2] * j[0], g21 = j[2] * j[1], g22 = j[2] * j[2];
  }
  for (Eigen::Index k = 1; k < n; ++k) {
    const double x = j[3 * k], y = j[3 * k + 1], z = j[3 * k + 2];
    g00 += x * x;
    g10 += y * x;
    g11 += y * y;
    g20 += z * x;
    g21 += z * y;
    g22 += z * z;
  }
  g00 += lambda_squared;
  g11 += lambda_squared;
  g22 += lambda_squared;
  // ldlt_inplace<Lower>, k = 0: the largest |diagonal| (the first of equals) to the front.
  transpositions_[0] = 0, transpositions_[1] = 1, transpositions_[2] = 2;
  double biggest = std::abs(g00);
  if (std::abs(g11) > biggest) transpositions_[0] = 1, biggest = std::abs(g11);
  if (std::abs(g22) > biggest) transpositions_[0] = 2;
  if (transpositions_[0] == 1) {
    std::swap(g20, g21);
    std::swap(g00, g11);
  } else if (transpositions_[0] == 2) {
    std::swap(g00, g22);
    std::swap(g10, g21);
  }
  if (!(std::abs(g00) > 0.0)) {
    // A zero diagonal: Eigen keeps the matrix as it is, with no permutation.
    transpositions_[0] = 0;
    store(g00, g10, g11, g20, g21, g22);
    return;
  }
  g10 /= g00;
  g20 /= g00;
  // k = 1: pivot, then row 1 of L times D off the pivot and off the entry below it.
  if (std::abs(g22) > std::abs(g11)) {
    transpositions_[1] = 2;
    std::swap(g10, g20);
    std::swap(g11, g22);
  }
  const double t0 = g00 * g10;
  g11 -= g10 * t0;
  g21 -= g20 * t0;
  if (std::abs(g11) > 0.0) g21 /= g11;
  // k = 2: row 2 of L times D off the last pivot.
  const double u0 = g00 * g20, u1 = g11 * g21;
  g22 -= g20 * u0 + g21 * u1;
  store(g00, g10, g11, g20, g21, g22);
}

Eigen::Vector3d DampedGram::solve(const Eigen::Vector3d& b) const {
  double x[3] = {b[0], b[1], b[2]};
  for (int k = 0; k < 3; ++k) {
    if (transpositions_[k] != k) std::swap(x[k], x[transpositions_[k]]);
  }
  x[1] -= m_[1][0] * x[0];  // L⁻¹, unit diagonal
  x[2] -= m_[2][0] * x[0] + m_[2][1] * x[1];
  for (int i = 0; i < 3; ++i) {  // D's pseudo-inverse
    if (std::abs(m_[i][i]) > std::numeric_limits<double>::min()) {
      x[i] /= m_[i][i];
    } else {
      x[i] = 0.0;
    }
  }
  x[1] -= m_[2][1] * x[2];  // L⁻ᵀ
  x[0] -= m_[1][0] * x[1] + m_[2][0] * x[2];
  for (int k = 2; k >= 0; --k) {
    if (transpositions_[k] != k) std::swap(x[k], x[transpositions_[k]]);
  }
  return Eigen::Vector3d(x[0], x[1], x[2]);
}

}  // namespace armfarm
