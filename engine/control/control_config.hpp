#pragma once
// The controller's configuration: mode, feed-forward source and PD gains, with the only copy
// of their defaults, and its key table (engine/config/config_key.hpp).
// Units: SI and radians; per-joint vectors have one entry per active joint or one for all.
#include "engine/config/config_key.hpp"

#include <Eigen/Core>

#include <vector>

namespace armfarm {

/// The thesis's three control modes (appendix A).
enum class ControlMode {
  open_loop,  ///< feed-forward only
  feedback,   ///< PD only
  composite,  ///< PD + feed-forward
};
const EnumNames& control_mode_names();

/// Where the feed-forward torque comes from.
enum class FeedForwardSource {
  learner,   ///< the learned inverse dynamics (LWPR) at the desired state
  analytic,  ///< the exact rigid-body inverse dynamics of the nominal model (section 3.1)
  none,
};
const EnumNames& feed_forward_source_names();

/// Which rule places the full-scale PD gains where control.kp / control.kd are empty.
enum class GainSet {
  mass_bandwidth,  ///< kp = M_jj·bandwidth², kd = 2·damping_ratio·M_jj·bandwidth (armfarm's default)
  appendix_d,      ///< the thesis's paramfile PID lines (appendix D), by joint number
};
const EnumNames& gain_set_names();

struct ControlConfig {
  ControlMode mode = ControlMode::composite;
  FeedForwardSource feed_forward = FeedForwardSource::learner;
  /// Where kp / kd are empty: mass_bandwidth (below) or appendix D's PID lines. Appendix D's
  /// gains need a PD period finer than 10 ms on this arm (pd_substeps, see pd_gains.hpp).
  GainSet gain_set = GainSet::mass_bandwidth;
  /// PD gains, N·m/rad and N·m·s/rad. Empty: by gain_set; for mass_bandwidth kp = M_jj·bandwidth²,
  /// kd = 2·damping_ratio·M_jj·bandwidth with M_jj the diagonal of the mass matrix (armature
  /// included) at the start posture, raised for the postures the job visits (the placement
  /// inertia and the gravity floor, pd_gains.hpp; engine/README.md). Set, they run as given.
  Eigen::VectorXd kp;
  Eigen::VectorXd kd;
  double bandwidth = 20.0;     ///< rad/s, for the default gains (stable under a 10 ms hold)
  double damping_ratio = 1.0;  ///< for the default gains
  /// Multiplies both gains; the thesis's low-gain controller is 0.2 (gains reduced by 80 %).
  double gain_scale = 1.0;
  /// With gain_scale s, kd is scaled by √s instead of s, which keeps the damping ratio
  /// ζ = kd / (2·√(kp·M_jj)) of the gains. Off (the thesis's "gains reduced by 80 %"), ζ becomes
  /// √s·ζ: 0.45 at s = 0.2 for the default ζ = 1 — an underdamped low-gain controller.
  bool keep_damping_ratio = false;
  bool limit_torque = true;    ///< clip the command to the model's effort limits
};

const std::vector<ConfigKey<ControlConfig>>& control_config_keys();

}  // namespace armfarm
