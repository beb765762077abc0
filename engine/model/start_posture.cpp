#include "engine/model/start_posture.hpp"

#include <algorithm>

namespace armfarm {

double calc_default_start_position(const Joint& joint) {
  if (!joint.has_position_limits || joint.type == JointType::fixed) return 0.0;
  const double margin = kStartPostureMargin * (joint.upper - joint.lower);
  return std::clamp(0.0, joint.lower + margin, joint.upper - margin);
}

}  // namespace armfarm
