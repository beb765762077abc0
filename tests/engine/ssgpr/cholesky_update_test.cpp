// Rank-one Cholesky update against a fresh factorisation of A + vvᵀ.
#include "engine/ssgpr/cholesky_update.hpp"

#include "engine/random/random_stream.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace armfarm::ssgpr {
namespace {

Eigen::MatrixXd make_random(int rows, int cols, RandomStream& stream) {
  Eigen::MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j) {
    for (int i = 0; i < rows; ++i) m(i, j) = stream.normal();
  }
  return m;
}

TEST(CholeskyUpdate, MatchesRefactorisationAfterManyUpdates) {
  RandomStream stream(3, "test.cholesky");
  const int n = 40;
  const Eigen::MatrixXd G = make_random(n, n, stream);
  Eigen::MatrixXd A = G * G.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
  Eigen::MatrixXd L = A.llt().matrixL();
  for (int k = 0; k < 50; ++k) {
    Eigen::VectorXd v = make_random(n, 1, stream);
    if (k % 7 == 0) v.head(n / 2).setZero();  // leading zeros take the skip path
    A += v * v.transpose();
    update_cholesky_rank_one(L, v);
  }
  const Eigen::MatrixXd expected = A.llt().matrixL();
  const Eigen::MatrixXd got = L.triangularView<Eigen::Lower>();
  EXPECT_LT((got - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
  EXPECT_GT(got.diagonal().minCoeff(), 0.0);
}

TEST(CholeskyUpdate, TinyCaseByHand) {
  // A = diag(16, 1), v = (3, 0): A + vvᵀ = diag(25, 1), factor diag(5, 1).
  Eigen::MatrixXd L = Eigen::Vector2d(4.0, 1.0).asDiagonal();
  Eigen::VectorXd v = Eigen::Vector2d(3.0, 0.0);
  update_cholesky_rank_one(L, v);
  EXPECT_DOUBLE_EQ(L(0, 0), 5.0);
  EXPECT_DOUBLE_EQ(L(1, 0), 0.0);
  EXPECT_DOUBLE_EQ(L(1, 1), 1.0);
}

}  // namespace
}  // namespace armfarm::ssgpr
