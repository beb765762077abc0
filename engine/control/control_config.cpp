#include "engine/control/control_config.hpp"

namespace armfarm {

const EnumNames& control_mode_names() {
  static const EnumNames names = {
      {"open_loop", static_cast<int>(ControlMode::open_loop), "feed-forward only"},
      {"feedback", static_cast<int>(ControlMode::feedback), "PD only"},
      {"composite", static_cast<int>(ControlMode::composite), "PD + feed-forward (appendix A)"},
  };
  return names;
}

const EnumNames& feed_forward_source_names() {
  static const EnumNames names = {
      {"learner", static_cast<int>(FeedForwardSource::learner), "LWPR at the desired q, q̇, q̈"},
      {"analytic", static_cast<int>(FeedForwardSource::analytic), "the nominal model's exact inverse dynamics, its joint damping and friction included"},
      {"none", static_cast<int>(FeedForwardSource::none), "no feed-forward"},
  };
  return names;
}

const EnumNames& gain_set_names() {
  static const EnumNames names = {
      {"mass_bandwidth", static_cast<int>(GainSet::mass_bandwidth),
       "kp = M_jj·bandwidth², kd = 2·damping_ratio·M_jj·bandwidth at the start posture, raised for the postures the job visits"},
      {"appendix_d", static_cast<int>(GainSet::appendix_d),
       "the thesis's paramfile PID lines (appendix D) for joints 1-6, joint 7 as joint 6; needs pd_substeps >= 10"},
  };
  return names;
}

const std::vector<ConfigKey<ControlConfig>>& control_config_keys() {
  using C = ControlConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"mode", "", {}, ListSize::any, "open_loop (feed-forward only), feedback (PD only) or composite (PD + feed-forward), appendix A",
       [](C& c) { return make_choice_field(c.mode, control_mode_names()); }},
      {"feed_forward", "", {}, ListSize::any,
       "learner (LWPR at the desired q, q̇, q̈), analytic (the nominal model's full inverse dynamics: rigid body plus its viscous damping and Coulomb friction, as the plant integrates them) or none",
       [](C& c) { return make_choice_field(c.feed_forward, feed_forward_source_names()); }},
      {"gain_set", "", {}, ListSize::any,
       "the gains where kp / kd are empty: mass_bandwidth (kp = M_jj·bandwidth², kd = 2·damping_ratio·M_jj·bandwidth) or appendix_d (the thesis's PID lines; with pd_substeps >= 10)",
       [](C& c) { return make_choice_field(c.gain_set, gain_set_names()); }},
      {"kp", "N·m/rad", closed(0.0, 1e6), ListSize::per_joint,
       "proportional gains; [] = by gain_set (mass_bandwidth: M_jj·bandwidth², M_jj the mass-matrix diagonal, armature included, at the start posture; raised for the postures the job visits, engine/README.md)",
       [](C& c) { return make_field(c.kp); }},
      {"kd", "N·m·s/rad", closed(0.0, 1e5), ListSize::per_joint, "derivative gains; [] = by gain_set (mass_bandwidth: 2·damping_ratio·M_jj·bandwidth)",
       [](C& c) { return make_field(c.kd); }},
      {"bandwidth", "rad/s", left_open(0.0, 1000.0), ListSize::any, "closed-loop bandwidth of the default gains",
       [](C& c) { return make_field(c.bandwidth); }},
      {"damping_ratio", "", closed(0.0, 10.0), ListSize::any, "damping ratio of the default gains",
       [](C& c) { return make_field(c.damping_ratio); }},
      {"gain_scale", "", closed(0.0, 100.0), ListSize::any, "multiplies kp and kd; 0.2 is the thesis's low-gain controller",
       [](C& c) { return make_field(c.gain_scale); }},
      {"keep_damping_ratio", "", {}, ListSize::any,
       "scale kd by √gain_scale (keeps the damping ratio) instead of gain_scale (ζ drops to √gain_scale·ζ, 0.45 at 0.2)",
       [](C& c) { return make_field(c.keep_damping_ratio); }},
      {"limit_torque", "", {}, ListSize::any, "clip commands to the model's effort limits (counted in torque_saturation_fraction)",
       [](C& c) { return make_field(c.limit_torque); }},
  };
  return keys;
}

}  // namespace armfarm
