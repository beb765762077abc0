#pragma once
// The 3 × 3 system of the inverse kinematics' damped least squares, G = J Jᵀ + λ² I for a 3 × n
// position Jacobian J, formed and factored in scalar code with the arithmetic of the Eigen 3.4
// expressions it replaces, in their order:
//   - G's lower triangle as `gram.noalias() = J * J.transpose()` sums it: J(r,0)·J(c,0) + J(r,1)·J(c,1)
//     + … in column order (Eigen's lazy product for 3 + 3 + n < 20, n ≤ 13), then λ² on the diagonal;
//   - the factorization and solve of Eigen::LDLT<Eigen::Matrix3d> (lower, diagonal pivoting by the
//     largest |diagonal|, first on ties; L unit lower; a zero pivot handled as Eigen does).
// The solutions are Eigen's bit for bit (DampedGram.* in engine_tests, against Eigen itself on
// random and singular systems), except that a sum whose terms are all zeros may be a zero of the
// other sign: Eigen's own sign there depends on the destination's address (its vectorized rows
// start from +0). Such a zero can change only the sign of a zero in the solution.
// In the 30-reach 7-DOF job (callgrind, 374 000 IK iterations) the Eigen expressions took 374M
// instructions (product 179M, LDLT compute 163M, solves 32M), these 135M (factor 77M, solves 57M).
#include <Eigen/Core>

namespace armfarm {

class DampedGram {
 public:
  /// The largest n (columns of J) for which the sums have the order above: beyond it Eigen's
  /// product takes its blocked path, and callers use Eigen (inverse_kinematics.cpp).
  static constexpr int kMaxColumns = 13;

  /// Forms and factors G = J Jᵀ + λ² I (J 3 × n, n ≤ kMaxColumns; lambda_squared in m²).
  void factor(const Eigen::Matrix3Xd& jacobian, double lambda_squared);
  /// G⁻¹ b, as LDLT::solve computes it (b in m, the result in 1/m).
  Eigen::Vector3d solve(const Eigen::Vector3d& b) const;

 private:
  void store(double g00, double g10, double g11, double g20, double g21, double g22) {
    m_[0][0] = g00, m_[1][0] = g10, m_[1][1] = g11, m_[2][0] = g20, m_[2][1] = g21, m_[2][2] = g22;
  }

  double m_[3][3] = {};       ///< lower triangle: L below the diagonal, D on it (Eigen's in-place layout)
  int transpositions_[3] = {0, 1, 2};
};

}  // namespace armfarm
