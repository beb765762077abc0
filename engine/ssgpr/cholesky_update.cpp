// Rank-one Cholesky update by Givens rotations, column by column (Eigen is column-major, so
// each rotation streams one contiguous column of L and the tail of v).
#include "engine/ssgpr/cholesky_update.hpp"

#include <cmath>

namespace armfarm::ssgpr {

void update_cholesky_rank_one(Eigen::MatrixXd& L, Eigen::Ref<Eigen::VectorXd> v) {
  const Eigen::Index n = L.rows();
  for (Eigen::Index k = 0; k < n; ++k) {
    const double lkk = L(k, k);
    const double vk = v(k);
    if (vk == 0.0) continue;  // nothing to rotate in; the column is unchanged
    const double r = std::hypot(lkk, vk);
    const double c = lkk / r;
    const double s = vk / r;
    L(k, k) = r;
    const Eigen::Index tail = n - k - 1;
    if (tail == 0) break;
    double* col = L.col(k).data() + k + 1;
    double* vt = v.data() + k + 1;
    for (Eigen::Index i = 0; i < tail; ++i) {
      const double l = col[i];
      const double x = vt[i];
      col[i] = c * l + s * x;
      vt[i] = c * x - s * l;
    }
  }
}

}  // namespace armfarm::ssgpr
