// LwprModel::calc_memory_bytes (the learner_memory_bytes metric) against a count by hand of the
// numbers one new receptive field with a diagonal metric stores.
#include "engine/lwpr/lwpr_model.hpp"

#include <gtest/gtest.h>

namespace armfarm::lwpr {
namespace {

TEST(LwprMemory, OneNewFieldPerOutputAddsItsNumbers) {
  const int n = 3, outputs = 2;
  LwprParams params;
  params.diag_only = true;
  LwprModel model(n, outputs, params);
  const std::size_t empty = model.calc_memory_bytes();
  model.update(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector2d(1.0, -1.0));
  ASSERT_EQ(model.size(), 2u);
  const std::size_t R = static_cast<std::size_t>(model.fields(0).at(0).n_reg());
  ASSERT_EQ(model.fields(1).at(0).n_reg(), model.fields(0).at(0).n_reg());
  // Per field: c, M, D, log α, IDBD trace, x₀ (n each); Σw, n_data, ss2, sys, Σe_cv², PRESS H and
  // R, β (R each); sxy, sxs, directions, loadings (n×R each); λ, β₀, Σe², PRESS E, trust (5);
  // in the scan: centre and metric diagonal padded to 8 doubles, and one trust byte.
  const std::size_t per_field = 8 * (6 * n + 8 * R + 4 * n * R + 5) + 8 * (2 * 8) + 1;
  EXPECT_EQ(model.calc_memory_bytes() - empty, outputs * per_field);
}

}  // namespace
}  // namespace armfarm::lwpr
