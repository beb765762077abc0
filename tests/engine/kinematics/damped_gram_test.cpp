// DampedGram against the Eigen expressions it replaces in the inverse kinematics (an independent
// implementation of the same arithmetic): G = J Jᵀ + λ² I formed by Eigen's product and solved by
// Eigen::LDLT<Matrix3d> must give the same solution bit for bit (== compares a zero of either
// sign as equal, the one difference DampedGram allows), on random Jacobians of every width up to
// kMaxColumns, on rank-deficient ones with and without damping, and with ties in the pivots.
#include "engine/kinematics/damped_gram.hpp"
#include "engine/random/random_stream.hpp"

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace armfarm {
namespace {

Eigen::Vector3d solve_with_eigen(const Eigen::Matrix3Xd& jacobian, double lambda_squared, const Eigen::Vector3d& b) {
  Eigen::Matrix3d gram;
  gram.noalias() = jacobian * jacobian.transpose();
  gram.diagonal().array() += lambda_squared;
  Eigen::LDLT<Eigen::Matrix3d> factor;
  factor.compute(gram);
  return factor.solve(b);
}

/// Counts the right-hand sides whose DampedGram solution differs from Eigen's in any component.
int count_mismatches(const Eigen::Matrix3Xd& jacobian, double lambda_squared, RandomStream& random, const std::string& what) {
  DampedGram gram;
  gram.factor(jacobian, lambda_squared);
  int mismatches = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::Vector3d b(random.normal(0.0, 1.0), random.normal(0.0, 1.0), random.normal(0.0, 1.0));
    const Eigen::Vector3d expected = solve_with_eigen(jacobian, lambda_squared, b);
    const Eigen::Vector3d got = gram.solve(b);
    bool same = true;
    for (int i = 0; i < 3; ++i) same = same && (got[i] == expected[i] || (std::isnan(got[i]) && std::isnan(expected[i])));
    if (!same) {
      ++mismatches;
      ADD_FAILURE() << what << ": DampedGram " << got.transpose() << " against Eigen's " << expected.transpose();
    }
  }
  return mismatches;
}

Eigen::Matrix3Xd random_jacobian(int columns, RandomStream& random) {
  Eigen::Matrix3Xd jacobian(3, columns);
  for (int c = 0; c < columns; ++c)
    for (int r = 0; r < 3; ++r) jacobian(r, c) = random.normal(0.0, 0.5);
  return jacobian;
}

TEST(DampedGram, SolvesRandomSystemsAsEigensProductAndLdltBitForBit) {
  RandomStream random(28, "test.damped_gram.random");
  int systems = 0;
  for (int columns = 1; columns <= DampedGram::kMaxColumns; ++columns) {
    for (const double lambda_squared : {0.0, 1e-6, 1e-2, 1.0}) {
      for (int trial = 0; trial < 200; ++trial) {
        const Eigen::Matrix3Xd jacobian = random_jacobian(columns, random);
        EXPECT_EQ(count_mismatches(jacobian, lambda_squared, random, std::to_string(columns) + " columns"), 0);
        ++systems;
      }
    }
  }
  EXPECT_EQ(systems, 13 * 4 * 200);
}

TEST(DampedGram, SolvesSingularAndTiedSystemsAsEigen) {
  RandomStream random(29, "test.damped_gram.singular");
  for (const double lambda_squared : {0.0, 1e-6}) {
    // A zero Jacobian (every pivot zero without damping), a zero row, rank one, two equal rows
    // (ties in the diagonal), and a Jacobian whose columns are the unit axes (an exact diagonal).
    Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, 7);
    EXPECT_EQ(count_mismatches(zero, lambda_squared, random, "zero"), 0);
    for (int trial = 0; trial < 100; ++trial) {
      Eigen::Matrix3Xd row_missing = random_jacobian(7, random);
      row_missing.row(trial % 3).setZero();
      EXPECT_EQ(count_mismatches(row_missing, lambda_squared, random, "a zero row"), 0);
      const Eigen::Vector3d direction(random.normal(0.0, 1.0), random.normal(0.0, 1.0), random.normal(0.0, 1.0));
      const Eigen::Matrix3Xd rank_one = direction * random_jacobian(7, random).row(0);
      EXPECT_EQ(count_mismatches(rank_one, lambda_squared, random, "rank one"), 0);
      Eigen::Matrix3Xd equal_rows = random_jacobian(5, random);
      equal_rows.row(2) = equal_rows.row(trial % 2);
      EXPECT_EQ(count_mismatches(equal_rows, lambda_squared, random, "equal rows"), 0);
    }
    Eigen::Matrix3Xd axes = Eigen::Matrix3Xd::Zero(3, 3);
    axes.diagonal() << 1.0, 2.0, 2.0;
    EXPECT_EQ(count_mismatches(axes, lambda_squared, random, "axes"), 0);
  }
}

}  // namespace
}  // namespace armfarm
