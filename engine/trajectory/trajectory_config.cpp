#include "engine/trajectory/trajectory_config.hpp"

#include <cmath>
#include <sstream>

namespace armfarm {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

}  // namespace

const EnumNames& differentiation_names() {
  static const EnumNames names = {
      {"backward_difference", static_cast<int>(Differentiation::backward_difference), "the thesis's backward differences"},
      {"smoothed", static_cast<int>(Differentiation::smoothed), "Savitzky–Golay derivatives"},
      {"analytic", static_cast<int>(Differentiation::analytic), "closed form for sine; central differences of the IK path otherwise"},
  };
  return names;
}

const EnumNames& reach_profile_names() {
  static const EnumNames names = {
      {"sigmoid", static_cast<int>(ReachProfile::sigmoid), "logistic profile of steepness sigmoid_steepness"},
      {"minimum_jerk", static_cast<int>(ReachProfile::minimum_jerk), "minimum-jerk profile (section 2.2.1)"},
  };
  return names;
}

const EnumNames& recorded_filter_names() {
  static const EnumNames names = {
      {"savitzky_golay", static_cast<int>(RecordedFilter::savitzky_golay), "Savitzky–Golay (window, polynomial_order)"},
      {"low_pass", static_cast<int>(RecordedFilter::low_pass), "zero-phase first-order low-pass (cutoff)"},
      {"none", static_cast<int>(RecordedFilter::none), "no smoothing"},
  };
  return names;
}

const EnumNames& trajectory_kind_names() {
  static const EnumNames names = {
      {"sine", static_cast<int>(TrajectoryKind::sine), "joint-space sinusoids (appendix D)"},
      {"figure_eight", static_cast<int>(TrajectoryKind::figure_eight), "task-space figure-eight (section 5.5)"},
      {"reaching", static_cast<int>(TrajectoryKind::reaching), "random reaches (section 5.5.2)"},
      {"recorded", static_cast<int>(TrajectoryKind::recorded), "a recorded motion from a CSV file (section 6.2.3)"},
  };
  return names;
}

const std::vector<ConfigKey<SineTrajectoryConfig>>& sine_trajectory_config_keys() {
  using C = SineTrajectoryConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"amplitude", "rad", closed(0.0, M_PI), ListSize::per_joint,
       "per joint; [] = 0.3 rad, less where 90 % of the room to the nearer position limit or 80 % of the velocity limit is less",
       [](C& c) { return make_field(c.amplitude); }},
      {"frequency", "Hz", left_open(0.0, 10.0), ListSize::per_joint, "per joint; [] = 0.25 Hz",
       [](C& c) { return make_field(c.frequency); }},
      {"phase", "rad", closed(-kTwoPi, kTwoPi), ListSize::per_joint, "per joint; [] = 0",
       [](C& c) { return make_field(c.phase); }},
      {"offset", "rad", closed(-kTwoPi, kTwoPi), ListSize::per_joint, "per joint; [] = the joints' start angles",
       [](C& c) { return make_field(c.offset); }},
      {"duration", "s", left_open(0.0, 86400.0), ListSize::any, "length of one pass",
       [](C& c) { return make_field(c.duration); }},
  };
  return keys;
}

FigureEightShape calc_figure_eight_shape(const FigureEightConfig& config, double reach) {
  const double ratio = reach / kReferenceReach;
  FigureEightShape shape;
  shape.centre = config.centre ? *config.centre : Eigen::Vector3d(0.45, 0.0, 0.6) * ratio;
  shape.a = config.a ? *config.a : 0.15 * ratio;
  shape.b = config.b ? *config.b : 0.10 * ratio;
  return shape;
}

ReachingBox calc_reaching_box(const ReachingConfig& config, double reach) {
  const double ratio = reach / kReferenceReach;
  return ReachingBox{config.box_min ? *config.box_min : Eigen::Vector3d(0.20, 0.20, 0.00) * ratio,
                     config.box_max ? *config.box_max : Eigen::Vector3d(0.70, 0.70, 0.50) * ratio};
}

const std::vector<ConfigKey<FigureEightConfig>>& figure_eight_config_keys() {
  using C = FigureEightConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"centre", "m", closed(-3.0, 3.0), ListSize::any,
       "centre [x, y, z] in the world frame; x stays constant; \"auto\" = (0.45, 0, 0.6) × the arm's reach / 1.018 m (the LWR III's), or the end effector's start position where the arm cannot follow the figure there",
       [](C& c) { return make_field(c.centre); }},
      {"a", "m", left_open(0.0, 2.0), ListSize::any, "half-width: y = centre.y + scale·a·sin(πs); \"auto\" = 0.15 × reach / 1.018 m",
       [](C& c) { return make_field(c.a); }},
      {"b", "m", left_open(0.0, 2.0), ListSize::any, "half-height: z = centre.z + scale·b·sin(2πs); \"auto\" = 0.10 × reach / 1.018 m",
       [](C& c) { return make_field(c.b); }},
      {"scale", "", left_open(0.0, 10.0), ListSize::any, "multiplies a and b (the thesis's trajScaling)",
       [](C& c) { return make_field(c.scale); }},
      {"points_per_loop", "", closed(4, 1e6), ListSize::any, "samples per loop, one per control tick",
       [](C& c) { return make_integer_field(c.points_per_loop); }},
      {"loops", "", closed(1, 1e4), ListSize::any, "loops per pass", [](C& c) { return make_integer_field(c.loops); }},
  };
  return keys;
}

const std::vector<ConfigKey<ReachingConfig>>& reaching_config_keys() {
  using C = ReachingConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"box_min", "m", closed(-3.0, 3.0), ListSize::any,
       "lower corner of the box targets are drawn from (section 5.5.2); \"auto\" = (0.2, 0.2, 0) × the arm's reach / 1.018 m",
       [](C& c) { return make_field(c.box_min); }},
      {"box_max", "m", closed(-3.0, 3.0), ListSize::any, "upper corner; each element above box_min's; \"auto\" = (0.7, 0.7, 0.5) × reach / 1.018 m",
       [](C& c) { return make_field(c.box_max); }},
      {"profile", "", {}, ListSize::any, "minimum_jerk (section 2.2.1) or sigmoid",
       [](C& c) { return make_choice_field(c.profile, reach_profile_names()); }},
      {"sigmoid_steepness", "", left_open(0.0, 100.0), ListSize::any, "k of the sigmoid 1/(1+exp(−k(s−½)))",
       [](C& c) { return make_field(c.sigmoid_steepness); }},
      {"points_per_reach", "", closed(2, 1e5), ListSize::any, "samples per reach, one per control tick",
       [](C& c) { return make_integer_field(c.points_per_reach); }},
      {"reaches", "", closed(1, 1e5), ListSize::any,
       "reaches per pass; a reach whose joint path would exceed 80 % of a velocity limit gets a new target",
       [](C& c) { return make_integer_field(c.reaches); }},
  };
  return keys;
}

const std::vector<ConfigKey<RecordedTrajectoryConfig>>& recorded_trajectory_config_keys() {
  using C = RecordedTrajectoryConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"file", "", {}, ListSize::any, "CSV (a relative path resolves against the file that wrote it): header row, then x, y, z (m) or one angle per active joint (rad) per row",
       [](C& c) { return make_field(c.file); }},
      {"task_space", "", {}, ListSize::any, "the columns are x, y, z rather than joint angles",
       [](C& c) { return make_field(c.task_space); }},
      {"sample_rate", "Hz", left_open(0.0, 1e5), ListSize::any, "rate of the file's rows", [](C& c) { return make_field(c.sample_rate); }},
      {"filter", "", {}, ListSize::any, "smoothing before differentiation: savitzky_golay, low_pass (zero-phase) or none",
       [](C& c) { return make_choice_field(c.filter, recorded_filter_names()); }},
      {"window", "", closed(3, 1001), ListSize::any, "Savitzky–Golay window, odd, in control ticks",
       [](C& c) { return make_integer_field(c.window); }},
      {"polynomial_order", "", closed(2, 10), ListSize::any, "Savitzky–Golay order, below the window",
       [](C& c) { return make_integer_field(c.polynomial_order); }},
      {"cutoff", "Hz", left_open(0.0, 1e4), ListSize::any, "low-pass cutoff", [](C& c) { return make_field(c.cutoff); }},
      {"loops", "", closed(1, 1e4), ListSize::any, "replays of the recording per pass", [](C& c) { return make_integer_field(c.loops); }},
  };
  return keys;
}

const std::vector<ConfigKey<TrajectoryConfig>>& trajectory_config_keys() {
  using C = TrajectoryConfig;
  static const std::vector<ConfigKey<C>> keys = {
      {"kind", "", {}, ListSize::any, "sine, figure_eight, reaching or recorded",
       [](C& c) { return make_choice_field(c.kind, trajectory_kind_names()); }},
      {"differentiation", "", {}, ListSize::any,
       "desired q̇, q̈: analytic (closed form for sine; central differences of the IK path otherwise), smoothed (Savitzky–Golay) "
       "or backward_difference (the thesis's)",
       [](C& c) { return make_choice_field(c.differentiation, differentiation_names()); }},
      {"ik_noise", "rad", closed(0.0, 0.1), ListSize::any,
       "task-space kinds: std of seeded white noise on every IK joint angle (the thesis's IK zig-zag); q̇, q̈ differentiated from the noisy angles",
       [](C& c) { return make_field(c.ik_noise); }},
  };
  return keys;
}

int calc_recorded_ticks(const RecordedTrajectoryConfig& recorded, double dt) {
  if (recorded.samples.rows() < 2 || !(recorded.sample_rate > 0.0) || !(dt > 0.0)) return 0;
  const double duration = static_cast<double>(recorded.samples.rows() - 1) / recorded.sample_rate;
  return static_cast<int>(std::floor(duration / dt + 1e-9)) + 1;
}

std::string check_recorded_length(const RecordedTrajectoryConfig& recorded, double dt) {
  if (recorded.filter != RecordedFilter::savitzky_golay) return "";
  const int ticks = calc_recorded_ticks(recorded, dt);
  if (ticks == 0 || ticks >= recorded.window) return "";  // too few rows or bad rates: reported on their own
  std::ostringstream text;
  text << (recorded.file.empty() ? std::string("the samples") : recorded.file) << " is too short for its filter: "
       << recorded.samples.rows() << " rows at " << recorded.sample_rate << " Hz are " << ticks << " control ticks of " << dt
       << " s, fewer than the Savitzky–Golay window of " << recorded.window
       << " (trajectory.recorded.window; record more rows, narrow the window, or set trajectory.recorded.filter to none)";
  return text.str();
}

}  // namespace armfarm
