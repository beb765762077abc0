// LwprParams: the published defaults, expansion of init_D and norms, rejection of bad values.
#include "engine/lwpr/lwpr_params.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace armfarm::lwpr {
namespace {

TEST(LwprParams, DefaultsAreValidAndExpand) {
  const LwprParams p;
  EXPECT_NO_THROW(validate_lwpr_params(p, 3, 2));
  EXPECT_EQ(calc_init_metric(p, 3), 25.0 * Eigen::MatrixXd::Identity(3, 3));
  LwprParams diag;
  diag.init_D = Eigen::Vector2d(1.0, 4.0);
  EXPECT_EQ(calc_init_metric(diag, 2), Eigen::Vector2d(1.0, 4.0).asDiagonal().toDenseMatrix());
  EXPECT_EQ(calc_norm_vector(Eigen::VectorXd::Constant(1, 2.0), 3), Eigen::Vector3d(2.0, 2.0, 2.0));
}

TEST(LwprParams, RejectsBadValues) {
  auto rejects = [](auto change) {
    LwprParams p;
    change(p);
    EXPECT_THROW(validate_lwpr_params(p, 2, 1), std::invalid_argument);
  };
  rejects([](LwprParams& p) { p.init_D = Eigen::Matrix3d::Identity(); });
  rejects([](LwprParams& p) { p.init_D = (Eigen::Matrix2d() << 1, 2, 2, 1).finished(); });  // indefinite
  rejects([](LwprParams& p) { p.init_D = (Eigen::Matrix2d() << 1, 0.5, 0, 1).finished(); });  // asymmetric
  rejects([](LwprParams& p) { p.w_gen = 1.5; });
  rejects([](LwprParams& p) { p.init_lambda = 0.0; });
  rejects([](LwprParams& p) { p.init_alpha = std::numeric_limits<double>::quiet_NaN(); });
  rejects([](LwprParams& p) { p.norm_in = Eigen::Vector3d::Ones(); });
  rejects([](LwprParams& p) { p.norm_out = Eigen::VectorXd::Zero(1); });
  rejects([](LwprParams& p) { p.init_n_reg = 0; });
}

}  // namespace
}  // namespace armfarm::lwpr
