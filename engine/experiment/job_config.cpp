#include "engine/experiment/job_config.hpp"

namespace armfarm {

lwpr::LwprParams make_job_lwpr_defaults() {
  lwpr::LwprParams params;
  params.init_D = Eigen::MatrixXd::Constant(1, 1, 0.05);
  params.trust_n_data = 5.0;
  return params;
}

}  // namespace armfarm
