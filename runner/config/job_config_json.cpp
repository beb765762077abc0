#include "runner/config/job_config_json.hpp"

#include "engine/experiment/series_recorder.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/io/csv_reader.hpp"
#include "runner/lwpr_params_json.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace armfarm {
namespace {

using nlohmann::json;

template <typename Enum>
Enum parse_choice(const json& value, const std::string& path, const std::vector<std::pair<const char*, Enum>>& choices) {
  const std::string text = value.is_string() ? value.get<std::string>() : value.dump();
  std::string names;
  for (const auto& [name, choice] : choices) {
    if (text == name) return choice;
    names += (names.empty() ? "" : ", ") + std::string("\"") + name + "\"";
  }
  throw ConfigError(path, "must be one of " + names + ", not " + value.dump());
}

Eigen::VectorXd parse_vector(const json& value, const std::string& path) {
  if (value.is_number()) return Eigen::VectorXd::Constant(1, value.get<double>());
  if (!value.is_array()) throw ConfigError(path, "expected a number or a list of numbers, got " + value.dump());
  Eigen::VectorXd result(static_cast<Eigen::Index>(value.size()));
  for (std::size_t i = 0; i < value.size(); ++i) {
    if (!value[i].is_number()) throw ConfigError(path + "[" + std::to_string(i) + "]", "expected a number, got " + value[i].dump());
    result[static_cast<Eigen::Index>(i)] = value[i].get<double>();
  }
  return result;
}

Eigen::Vector3d parse_point(const json& value, const std::string& path) {
  const Eigen::VectorXd v = parse_vector(value, path);
  if (v.size() != 3) throw ConfigError(path, "expected 3 numbers [x, y, z], got " + value.dump());
  return v;
}

double parse_number(const json& object, const char* key, const std::string& path) {
  const json& value = object.at(key);
  if (!value.is_number()) throw ConfigError(path + "." + key, "expected a number, got " + value.dump());
  return value.get<double>();
}

int parse_int(const json& object, const char* key, const std::string& path) {
  const json& value = object.at(key);
  if (!value.is_number_integer()) throw ConfigError(path + "." + key, "expected an integer, got " + value.dump());
  return value.get<int>();
}

bool parse_bool(const json& object, const char* key, const std::string& path) {
  const json& value = object.at(key);
  if (!value.is_boolean()) throw ConfigError(path + "." + key, "expected true or false, got " + value.dump());
  return value.get<bool>();
}

void require_positive(double value, const std::string& path) {
  if (!(value > 0.0)) throw ConfigError(path, "must be positive, got " + std::to_string(value));
}

void require_per_joint(const Eigen::VectorXd& values, int n, const std::string& path) {
  if (values.size() > 1 && values.size() != n) {
    throw ConfigError(path, "has " + std::to_string(values.size()) + " values; give 1 or one per active joint (" +
                                std::to_string(n) + ")");
  }
}

TrajectoryConfig parse_trajectory(const json& t, int n) {
  TrajectoryConfig config;
  config.kind = parse_choice<TrajectoryKind>(t.at("kind"), "trajectory.kind",
                                             {{"sine", TrajectoryKind::sine},
                                              {"figure_eight", TrajectoryKind::figure_eight},
                                              {"reaching", TrajectoryKind::reaching},
                                              {"recorded", TrajectoryKind::recorded}});
  config.differentiation = parse_choice<Differentiation>(t.at("differentiation"), "trajectory.differentiation",
                                                         {{"backward_difference", Differentiation::backward_difference},
                                                          {"smoothed", Differentiation::smoothed},
                                                          {"analytic", Differentiation::analytic}});
  const json& sine = t.at("sine");
  const std::string sp = "trajectory.sine";
  config.sine.amplitude = parse_vector(sine.at("amplitude"), sp + ".amplitude");
  config.sine.frequency = parse_vector(sine.at("frequency"), sp + ".frequency");
  config.sine.phase = parse_vector(sine.at("phase"), sp + ".phase");
  config.sine.offset = parse_vector(sine.at("offset"), sp + ".offset");
  for (const char* key : {"amplitude", "frequency", "phase", "offset"}) {
    require_per_joint(parse_vector(sine.at(key), sp + "." + key), n, sp + "." + key);
  }
  config.sine.duration = parse_number(sine, "duration", sp);
  require_positive(config.sine.duration, sp + ".duration");

  const json& eight = t.at("figure_eight");
  const std::string ep = "trajectory.figure_eight";
  config.figure_eight.centre = parse_point(eight.at("centre"), ep + ".centre");
  config.figure_eight.a = parse_number(eight, "a", ep);
  config.figure_eight.b = parse_number(eight, "b", ep);
  config.figure_eight.scale = parse_number(eight, "scale", ep);
  config.figure_eight.points_per_loop = parse_int(eight, "points_per_loop", ep);
  config.figure_eight.loops = parse_int(eight, "loops", ep);
  if (config.figure_eight.points_per_loop < 4) throw ConfigError(ep + ".points_per_loop", "must be at least 4");
  if (config.figure_eight.loops < 1) throw ConfigError(ep + ".loops", "must be at least 1");

  const json& reach = t.at("reaching");
  const std::string rp = "trajectory.reaching";
  config.reaching.box_min = parse_point(reach.at("box_min"), rp + ".box_min");
  config.reaching.box_max = parse_point(reach.at("box_max"), rp + ".box_max");
  config.reaching.profile = parse_choice<ReachProfile>(reach.at("profile"), rp + ".profile",
                                                       {{"sigmoid", ReachProfile::sigmoid}, {"minimum_jerk", ReachProfile::minimum_jerk}});
  config.reaching.sigmoid_steepness = parse_number(reach, "sigmoid_steepness", rp);
  config.reaching.points_per_reach = parse_int(reach, "points_per_reach", rp);
  config.reaching.reaches = parse_int(reach, "reaches", rp);
  if (config.reaching.points_per_reach < 2) throw ConfigError(rp + ".points_per_reach", "must be at least 2");
  if (config.reaching.reaches < 1) throw ConfigError(rp + ".reaches", "must be at least 1");
  for (int axis = 0; axis < 3; ++axis) {
    if (!(config.reaching.box_min[axis] < config.reaching.box_max[axis])) {
      throw ConfigError(rp + ".box_max[" + std::to_string(axis) + "]", "must exceed box_min[" + std::to_string(axis) + "]");
    }
  }

  const json& recorded = t.at("recorded");
  const std::string cp = "trajectory.recorded";
  config.recorded.file = recorded.at("file").get<std::string>();
  config.recorded.task_space = parse_bool(recorded, "task_space", cp);
  config.recorded.sample_rate = parse_number(recorded, "sample_rate", cp);
  config.recorded.filter = recorded.at("filter").get<std::string>();
  if (config.recorded.filter != "savitzky_golay" && config.recorded.filter != "low_pass" && config.recorded.filter != "none") {
    throw ConfigError(cp + ".filter", "must be one of \"savitzky_golay\", \"low_pass\", \"none\", not \"" + config.recorded.filter + "\"");
  }
  config.recorded.window = parse_int(recorded, "window", cp);
  config.recorded.polynomial_order = parse_int(recorded, "polynomial_order", cp);
  config.recorded.cutoff = parse_number(recorded, "cutoff", cp);
  config.recorded.loops = parse_int(recorded, "loops", cp);
  if (config.kind == TrajectoryKind::recorded) {
    if (config.recorded.file.empty()) throw ConfigError(cp + ".file", "is required when trajectory.kind is \"recorded\"");
    try {
      config.recorded.samples = io::load_csv(config.recorded.file).values;
    } catch (const std::exception& error) {
      throw ConfigError(cp + ".file", error.what());
    }
  }
  require_positive(config.recorded.sample_rate, cp + ".sample_rate");
  return config;
}

}  // namespace

nlohmann::json make_job_config_defaults() {
  const JobConfig d;
  const LearningConfig& l = d.learning;
  const lwpr::LwprParams& p = l.lwpr;
  const TrajectoryConfig& t = d.trajectory;
  auto point = [](const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); };
  json defaults = {
      {"model", "models/dlr_lwr3.urdf"},
      {"active_joints", json::array()},
      {"seed", 0},
      {"dt", d.dt},
      {"integrator", "runge_kutta_merson"},
      {"integrator_accuracy", d.integrator_accuracy},
      {"control",
       {{"mode", "composite"},
        {"feed_forward", "learner"},
        {"kp", json::array()},
        {"kd", json::array()},
        {"bandwidth", d.control.bandwidth},
        {"damping_ratio", d.control.damping_ratio},
        {"gain_scale", d.control.gain_scale},
        {"limit_torque", d.control.limit_torque}}},
      {"trajectory",
       {{"kind", "sine"},
        {"differentiation", "analytic"},
        {"sine",
         {{"amplitude", json::array()}, {"frequency", json::array()}, {"phase", json::array()}, {"offset", json::array()},
          {"duration", t.sine.duration}}},
        {"figure_eight",
         {{"centre", point(t.figure_eight.centre)},
          {"a", t.figure_eight.a},
          {"b", t.figure_eight.b},
          {"scale", t.figure_eight.scale},
          {"points_per_loop", t.figure_eight.points_per_loop},
          {"loops", t.figure_eight.loops}}},
        {"reaching",
         {{"box_min", point(t.reaching.box_min)},
          {"box_max", point(t.reaching.box_max)},
          {"profile", "minimum_jerk"},
          {"sigmoid_steepness", t.reaching.sigmoid_steepness},
          {"points_per_reach", t.reaching.points_per_reach},
          {"reaches", t.reaching.reaches}}},
        {"recorded",
         {{"file", ""},
          {"task_space", t.recorded.task_space},
          {"sample_rate", t.recorded.sample_rate},
          {"filter", t.recorded.filter},
          {"window", t.recorded.window},
          {"polynomial_order", t.recorded.polynomial_order},
          {"cutoff", t.recorded.cutoff},
          {"loops", t.recorded.loops}}}}},
      {"learning",
       {{"mode", "online"},
        {"normalize_inputs", l.normalize_inputs},
        {"train_fraction", l.train_fraction},
        {"epochs", l.epochs},
        {"collect_repeats", l.collect_repeats},
        {"collect_gain_scale", l.collect_gain_scale},
        {"learn_during_evaluation", l.learn_during_evaluation},
        {"learner", "lwpr"},
        {"collect_start_spread", l.collect_start_spread},
        {"collect_noise_q", l.collect_noise_q},
        {"collect_noise_qd", l.collect_noise_qd},
        {"heldout", l.heldout},
        {"heldout_checkpoints", json::array()},
        {"heldout_segments", l.heldout_segments},
        {"heldout_amplitude_scale", l.heldout_amplitude_scale},
        {"heldout_phase_step", l.heldout_phase_step},
        {"heldout_recorded_fraction", l.heldout_recorded_fraction},
        {"lwpr",
         {{"init_D", nullptr},
          {"init_alpha", p.init_alpha},
          {"penalty", p.penalty},
          {"diag_only", p.diag_only},
          {"update_D", p.update_D},
          {"meta", p.meta},
          {"meta_rate", p.meta_rate},
          {"w_gen", p.w_gen},
          {"w_prune", p.w_prune},
          {"init_lambda", p.init_lambda},
          {"final_lambda", p.final_lambda},
          {"tau_lambda", p.tau_lambda},
          {"init_S2", p.init_S2},
          {"add_threshold", p.add_threshold},
          {"kernel", "gaussian"},
          {"norm_in", nullptr},
          {"norm_out", nullptr},
          {"blend", p.blend},
          {"add_proj", p.add_proj},
          {"init_n_reg", p.init_n_reg},
          {"max_fields", static_cast<int>(p.max_fields)},
          {"cutoff", p.cutoff},
          {"trust_n_data", p.trust_n_data}}}}},
      {"mismatch",
       {{"payload", {{"mass", 0.0}, {"offset", json::array({0.0, 0.0, 0.0})}, {"radius_of_gyration", 0.0}}},
        {"viscous", json::array()},
        {"coulomb", json::array()},
        {"start_time", 0.0}}},
      {"recording", {{"series", json::array({"TRIAL"})}, {"every", d.recording.every}}},
      {"divergence",
       {{"max_tracking_error", d.divergence.max_tracking_error},
        {"max_error_duration", d.divergence.max_error_duration},
        {"velocity_limit_factor", d.divergence.velocity_limit_factor}}},
  };
  return defaults;
}

JobConfig parse_job_config(const nlohmann::json& c, int movable_joints) {
  JobConfig config;
  const json& active = c.at("active_joints");
  for (std::size_t i = 0; i < active.size(); ++i) {
    const std::string path = "active_joints[" + std::to_string(i) + "]";
    // The schema's empty default list normalizes its numbers to reals: accept integral values.
    if (!active[i].is_number() || std::floor(active[i].get<double>()) != active[i].get<double>()) {
      throw ConfigError(path, "expected a joint number, got " + active[i].dump());
    }
    const int joint = static_cast<int>(active[i].get<double>());
    if (joint < 1 || joint > movable_joints) {
      throw ConfigError(path, "joint " + std::to_string(joint) + " does not exist; the arm has joints 1.." + std::to_string(movable_joints));
    }
    for (std::size_t k = 0; k < i; ++k) {
      if (static_cast<int>(active[k].get<double>()) == joint) throw ConfigError(path, "joint " + std::to_string(joint) + " is listed twice");
    }
    config.active_joints.push_back(joint);
  }
  const int n = config.active_joints.empty() ? movable_joints : static_cast<int>(config.active_joints.size());
  const json& seed = c.at("seed");
  if (!seed.is_number_integer() || seed.get<std::int64_t>() < 0) throw ConfigError("seed", "expected a non-negative integer");
  config.seed = seed.get<std::uint64_t>();
  config.dt = parse_number(c, "dt", "");
  if (!(config.dt > 0.0 && config.dt <= 0.1)) throw ConfigError("dt", "must be in (0, 0.1] s");
  config.integrator = parse_choice<IntegratorKind>(c.at("integrator"), "integrator",
                                                   {{"runge_kutta_merson", IntegratorKind::runge_kutta_merson},
                                                    {"runge_kutta_3", IntegratorKind::runge_kutta_3},
                                                    {"runge_kutta_feldberg", IntegratorKind::runge_kutta_feldberg},
                                                    {"explicit_euler", IntegratorKind::explicit_euler},
                                                    {"semi_explicit_euler2", IntegratorKind::semi_explicit_euler2},
                                                    {"verlet", IntegratorKind::verlet},
                                                    {"cpodes", IntegratorKind::cpodes}});
  config.integrator_accuracy = parse_number(c, "integrator_accuracy", "");
  if (!(config.integrator_accuracy > 0.0 && config.integrator_accuracy < 1.0)) throw ConfigError("integrator_accuracy", "must be in (0, 1)");

  const json& control = c.at("control");
  config.control.mode = parse_choice<ControlMode>(
      control.at("mode"), "control.mode",
      {{"open_loop", ControlMode::open_loop}, {"feedback", ControlMode::feedback}, {"composite", ControlMode::composite}});
  config.control.feed_forward = parse_choice<FeedForwardSource>(
      control.at("feed_forward"), "control.feed_forward",
      {{"learner", FeedForwardSource::learner}, {"analytic", FeedForwardSource::analytic}, {"none", FeedForwardSource::none}});
  config.control.kp = parse_vector(control.at("kp"), "control.kp");
  config.control.kd = parse_vector(control.at("kd"), "control.kd");
  require_per_joint(config.control.kp, n, "control.kp");
  require_per_joint(config.control.kd, n, "control.kd");
  for (int j = 0; j < config.control.kp.size(); ++j) {
    if (config.control.kp[j] < 0.0) throw ConfigError("control.kp[" + std::to_string(j) + "]", "must not be negative");
  }
  for (int j = 0; j < config.control.kd.size(); ++j) {
    if (config.control.kd[j] < 0.0) throw ConfigError("control.kd[" + std::to_string(j) + "]", "must not be negative");
  }
  config.control.bandwidth = parse_number(control, "bandwidth", "control");
  require_positive(config.control.bandwidth, "control.bandwidth");
  config.control.damping_ratio = parse_number(control, "damping_ratio", "control");
  if (config.control.damping_ratio < 0.0) throw ConfigError("control.damping_ratio", "must not be negative");
  config.control.gain_scale = parse_number(control, "gain_scale", "control");
  if (config.control.gain_scale < 0.0) throw ConfigError("control.gain_scale", "must not be negative");
  config.control.limit_torque = parse_bool(control, "limit_torque", "control");

  config.trajectory = parse_trajectory(c.at("trajectory"), n);

  const json& learning = c.at("learning");
  config.learning.mode = parse_choice<LearningMode>(
      learning.at("mode"), "learning.mode",
      {{"none", LearningMode::none}, {"online", LearningMode::online}, {"batch", LearningMode::batch}});
  config.learning.normalize_inputs = parse_bool(learning, "normalize_inputs", "learning");
  config.learning.train_fraction = parse_number(learning, "train_fraction", "learning");
  if (!(config.learning.train_fraction > 0.0 && config.learning.train_fraction <= 1.0)) {
    throw ConfigError("learning.train_fraction", "must be in (0, 1]");
  }
  config.learning.epochs = parse_int(learning, "epochs", "learning");
  if (config.learning.epochs < 1) throw ConfigError("learning.epochs", "must be at least 1");
  config.learning.collect_repeats = parse_int(learning, "collect_repeats", "learning");
  if (config.learning.collect_repeats < 1) throw ConfigError("learning.collect_repeats", "must be at least 1");
  config.learning.collect_gain_scale = parse_number(learning, "collect_gain_scale", "learning");
  if (config.learning.collect_gain_scale < 0.0) throw ConfigError("learning.collect_gain_scale", "must not be negative");
  config.learning.learn_during_evaluation = parse_bool(learning, "learn_during_evaluation", "learning");
  config.learning.learner = parse_choice<LearnerKind>(learning.at("learner"), "learning.learner", {{"lwpr", LearnerKind::lwpr}});
  config.learning.collect_start_spread = parse_number(learning, "collect_start_spread", "learning");
  if (config.learning.collect_start_spread < 0.0) throw ConfigError("learning.collect_start_spread", "must not be negative");
  config.learning.collect_noise_q = parse_number(learning, "collect_noise_q", "learning");
  if (config.learning.collect_noise_q < 0.0) throw ConfigError("learning.collect_noise_q", "must not be negative");
  config.learning.collect_noise_qd = parse_number(learning, "collect_noise_qd", "learning");
  if (config.learning.collect_noise_qd < 0.0) throw ConfigError("learning.collect_noise_qd", "must not be negative");
  config.learning.heldout = parse_bool(learning, "heldout", "learning");
  const json& checkpoints = learning.at("heldout_checkpoints");
  if (!checkpoints.is_array()) throw ConfigError("learning.heldout_checkpoints", "expected a list of integers, got " + checkpoints.dump());
  for (std::size_t i = 0; i < checkpoints.size(); ++i) {
    const std::string path = "learning.heldout_checkpoints[" + std::to_string(i) + "]";
    if (!checkpoints[i].is_number_integer()) throw ConfigError(path, "expected an integer, got " + checkpoints[i].dump());
    const int checkpoint = checkpoints[i].get<int>();
    if (checkpoint < 0 || (i > 0 && checkpoint <= config.learning.heldout_checkpoints.back())) {
      throw ConfigError(path, "checkpoints must be non-negative and increasing");
    }
    config.learning.heldout_checkpoints.push_back(checkpoint);
  }
  config.learning.heldout_segments = parse_int(learning, "heldout_segments", "learning");
  if (config.learning.heldout_segments < 0) throw ConfigError("learning.heldout_segments", "must not be negative");
  config.learning.heldout_amplitude_scale = parse_number(learning, "heldout_amplitude_scale", "learning");
  require_positive(config.learning.heldout_amplitude_scale, "learning.heldout_amplitude_scale");
  config.learning.heldout_phase_step = parse_number(learning, "heldout_phase_step", "learning");
  config.learning.heldout_recorded_fraction = parse_number(learning, "heldout_recorded_fraction", "learning");
  if (!(config.learning.heldout_recorded_fraction > 0.0 && config.learning.heldout_recorded_fraction < 1.0)) {
    throw ConfigError("learning.heldout_recorded_fraction", "must be in (0, 1)");
  }
  json lwpr = json::object();
  for (const auto& [key, value] : learning.at("lwpr").items()) {
    if (!value.is_null()) lwpr[key] = value;
  }
  if (!lwpr.contains("init_D")) lwpr["init_D"] = make_job_lwpr_defaults().init_D(0, 0);
  try {
    config.learning.lwpr = parse_lwpr_params(lwpr, "learning.lwpr", 3 * n, LwprDataScales{});
    lwpr::validate_lwpr_params(config.learning.lwpr, 3 * n, n);
  } catch (const std::exception& error) {
    // parse_lwpr_params says "learning.lwpr: key: what"; keep the path, drop the separator.
    std::string message = error.what();
    const std::string prefix = "learning.lwpr: ";
    if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
    const auto colon = message.find(": ");
    if (colon != std::string::npos && message.find(' ') > colon) {
      throw ConfigError("learning.lwpr." + message.substr(0, colon), message.substr(colon + 2));
    }
    throw ConfigError("learning.lwpr", message);
  }
  if (config.control.mode != ControlMode::feedback && config.control.feed_forward == FeedForwardSource::learner &&
      config.learning.mode == LearningMode::none) {
    throw ConfigError("learning.mode", "is \"none\" but control.feed_forward is \"learner\" (use \"analytic\" or \"none\")");
  }

  const json& mismatch = c.at("mismatch");
  const json& payload = mismatch.at("payload");
  config.mismatch.payload.mass = parse_number(payload, "mass", "mismatch.payload");
  if (config.mismatch.payload.mass < 0.0) throw ConfigError("mismatch.payload.mass", "must not be negative");
  config.mismatch.payload.offset = parse_point(payload.at("offset"), "mismatch.payload.offset");
  config.mismatch.payload.radius_of_gyration = parse_number(payload, "radius_of_gyration", "mismatch.payload");
  config.mismatch.viscous = parse_vector(mismatch.at("viscous"), "mismatch.viscous");
  config.mismatch.coulomb = parse_vector(mismatch.at("coulomb"), "mismatch.coulomb");
  require_per_joint(config.mismatch.viscous, n, "mismatch.viscous");
  require_per_joint(config.mismatch.coulomb, n, "mismatch.coulomb");
  config.mismatch.start_time = parse_number(mismatch, "start_time", "mismatch");

  const json& recording = c.at("recording");
  for (std::size_t i = 0; i < recording.at("series").size(); ++i) {
    const json& name = recording.at("series")[i];
    if (!name.is_string()) throw ConfigError("recording.series[" + std::to_string(i) + "]", "expected a series name");
    const auto& known = recordable_series_names();
    if (std::find(known.begin(), known.end(), name.get<std::string>()) == known.end()) {
      std::string names;
      for (const std::string& k : known) names += (names.empty() ? "" : ", ") + k;
      throw ConfigError("recording.series[" + std::to_string(i) + "]", "unknown series " + name.dump() + " (known: " + names + ")");
    }
    config.recording.series.push_back(name.get<std::string>());
  }
  config.recording.every = parse_int(recording, "every", "recording");
  if (config.recording.every < 1) throw ConfigError("recording.every", "must be at least 1");

  const json& divergence = c.at("divergence");
  config.divergence.max_tracking_error = parse_number(divergence, "max_tracking_error", "divergence");
  config.divergence.max_error_duration = parse_number(divergence, "max_error_duration", "divergence");
  config.divergence.velocity_limit_factor = parse_number(divergence, "velocity_limit_factor", "divergence");
  require_positive(config.divergence.max_tracking_error, "divergence.max_tracking_error");
  require_positive(config.divergence.velocity_limit_factor, "divergence.velocity_limit_factor");
  return config;
}

}  // namespace armfarm
