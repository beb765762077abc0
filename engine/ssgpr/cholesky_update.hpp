#pragma once
// Rank-one update of a Cholesky factor: given lower-triangular L with A = L Lᵀ, overwrite L
// with the factor of A + v vᵀ in O(n²), by one Givens rotation per column (each rotation
// zeroes one entry of v against the diagonal; orthogonal, hence backward stable).
#include <Eigen/Core>

namespace armfarm::ssgpr {

/// L (n×n, lower triangular, positive diagonal; the strict upper part is not read or written)
/// becomes the Cholesky factor of L Lᵀ + v vᵀ. `v` (n) is used as scratch and destroyed.
void update_cholesky_rank_one(Eigen::MatrixXd& L, Eigen::Ref<Eigen::VectorXd> v);

}  // namespace armfarm::ssgpr
