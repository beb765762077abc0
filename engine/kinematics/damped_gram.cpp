#include "engine/kinematics/damped_gram.hpp"

#include <cmath>
#include <limits>
#include <utility>

namespace armfarm {
namespace {

/// The lower triangle of J Jᵀ + λ² I into m: each sum over J's columns in order, first term first.
void form_lower_gram(const Eigen::Matrix3Xd& jacobian, double lambda_squared, double (&m)[3][3]) {
  const Eigen::Index n = jacobian.cols();
  const double* j = jacobian.data();  // column-major: J(r, k) = j[3k + r]
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c <= r; ++c) {
      double sum = n > 0 ? j[r] * j[c] : 0.0;
      for (Eigen::Index k = 1; k < n; ++k) sum += j[3 * k + r] * j[3 * k + c];
      m[r][c] = sum;
    }
    m[r][r] += lambda_squared;
  }
}

/// Moves the largest remaining |diagonal| (the first of equals) to position k of the lower
/// triangle, as ldlt_inplace<Lower> does; returns its former index.
int pivot_largest_diagonal(int k, double (&m)[3][3]) {
  int big = k;
  double biggest = std::abs(m[k][k]);
  for (int i = k + 1; i < 3; ++i) {
    if (std::abs(m[i][i]) > biggest) {
      biggest = std::abs(m[i][i]);
      big = i;
    }
  }
  if (big == k) return big;
  for (int c = 0; c < k; ++c) std::swap(m[k][c], m[big][c]);
  for (int r = big + 1; r < 3; ++r) std::swap(m[r][k], m[r][big]);
  std::swap(m[k][k], m[big][big]);
  for (int i = k + 1; i < big; ++i) std::swap(m[i][k], m[big][i]);
  return big;
}

}  // namespace

void DampedGram::factor(const Eigen::Matrix3Xd& jacobian, double lambda_squared) {
  form_lower_gram(jacobian, lambda_squared, m_);
  for (int k = 0; k < 3; ++k) {
    transpositions_[k] = pivot_largest_diagonal(k, m_);
    if (k > 0) {
      // Row k of L times D, taken off the pivot and (at k = 1) off the entry below it.
      double scaled[2] = {m_[0][0] * m_[k][0], k > 1 ? m_[1][1] * m_[k][1] : 0.0};
      const double dot = k > 1 ? m_[k][0] * scaled[0] + m_[k][1] * scaled[1] : m_[k][0] * scaled[0];
      m_[k][k] -= dot;
      if (k == 1) m_[2][1] -= m_[2][0] * scaled[0];
    }
    const double pivot = m_[k][k];
    const bool valid = std::abs(pivot) > 0.0;
    if (k == 0 && !valid) {
      // A zero diagonal: Eigen keeps the matrix as it is, with no permutation.
      for (int i = 0; i < 3; ++i) transpositions_[i] = i;
      return;
    }
    if (valid) {
      for (int r = k + 1; r < 3; ++r) m_[r][k] /= pivot;
    }
  }
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
