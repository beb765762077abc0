// The experiment job's JSON configuration: defaults parse into the engine's defaults, values
// land in the right fields, and bad values name their JSON path.
#include "runner/config/job_config_json.hpp"
#include "runner/config/config_value_json.hpp"
#include "runner/execution/job_executor.hpp"
#include "runner/spec/spec_error.hpp"
#include "runner/spec/sweep_expansion.hpp"
#include "runner/spec/input_files.hpp"
#include "engine/model/model_loading.hpp"
#include "support/scratch_file.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <unistd.h>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <limits>

namespace armfarm {
namespace {

std::string error_of(const nlohmann::json& config) {
  try {
    parse_job_config(config, 7);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(JobConfigJson, DefaultsParseToTheEngineDefaults) {
  const JobConfig parsed = parse_job_config(make_job_config_defaults(), 7);
  const JobConfig engine;
  EXPECT_EQ(parsed.simulation.dt, engine.simulation.dt);
  EXPECT_EQ(parsed.control.gain_scale, engine.control.gain_scale);
  EXPECT_EQ(parsed.control.bandwidth, engine.control.bandwidth);
  EXPECT_EQ(parsed.learning.lwpr.init_D(0, 0), make_job_lwpr_defaults().init_D(0, 0));
  EXPECT_EQ(parsed.learning.lwpr.trust_n_data, 5.0);
  EXPECT_EQ(parsed.trajectory.figure_eight.points_per_loop, 750);
  EXPECT_EQ(parsed.divergence.velocity_limit_factor, engine.divergence.velocity_limit_factor);
  EXPECT_TRUE(parsed.active_joints.empty());
}

TEST(JobConfigJson, ValuesLandInTheirFields) {
  nlohmann::json config = make_job_config_defaults();
  config["active_joints"] = {2, 3, 6, 7};
  config["control"]["kp"] = {10, 20, 30, 40};
  config["control"]["mode"] = "feedback";
  config["learning"]["lwpr"]["init_D"] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  config["trajectory"]["kind"] = "figure_eight";
  config["mismatch"]["payload"]["mass"] = 2.5;
  const JobConfig parsed = parse_job_config(config, 7);
  EXPECT_EQ(parsed.active_joints, (std::vector<int>{2, 3, 6, 7}));
  EXPECT_EQ(parsed.control.kp[3], 40.0);
  EXPECT_EQ(parsed.control.mode, ControlMode::feedback);
  EXPECT_EQ(parsed.learning.lwpr.init_D.size(), 12);
  EXPECT_EQ(parsed.trajectory.kind, TrajectoryKind::figure_eight);
  EXPECT_EQ(parsed.mismatch.payload.mass, 2.5);
}

TEST(JobConfigJson, BadValuesNameTheirPath) {
  nlohmann::json config = make_job_config_defaults();
  config["active_joints"] = {2, 8};
  EXPECT_NE(error_of(config).find("active_joints[1]: joint 8 does not exist"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["control"]["mode"] = "pid";
  EXPECT_NE(error_of(config).find("control.mode: must be one of"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["control"]["kp"] = {1, 2, 3};
  EXPECT_NE(error_of(config).find("control.kp: has 3 values"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["learning"]["lwpr"]["w_gen"] = 2.0;
  EXPECT_NE(error_of(config).find("learning.lwpr"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["recording"]["series"] = {"POS", "TORQUE"};
  EXPECT_NE(error_of(config).find("recording.series[1]: unknown name"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["learning"]["mode"] = "none";
  EXPECT_NE(error_of(config).find("learning.mode"), std::string::npos) << error_of(config);
  config = make_job_config_defaults();
  config["trajectory"]["kind"] = "recorded";
  config["trajectory"]["recorded"]["file"] = "/nonexistent/motion.csv";
  EXPECT_NE(error_of(config).find("trajectory.recorded.file: /nonexistent/motion.csv"), std::string::npos) << error_of(config);
}

TEST(JobConfigJson, DefaultsTreeHoldsExactlyTheTableKeysWithTheStructDefaults) {
  const nlohmann::json defaults = make_job_config_defaults();
  // Every leaf of the tree is a table key (or the runner's model), and the other way round.
  std::set<std::string> leaves;
  const std::function<void(const nlohmann::json&, const std::string&)> walk = [&](const nlohmann::json& node,
                                                                                 const std::string& path) {
    if (!node.is_object()) {
      leaves.insert(path);
      return;
    }
    for (const auto& [key, value] : node.items()) walk(value, path.empty() ? key : path + "." + key);
  };
  walk(defaults, "");
  std::set<std::string> keys;
  for (const RunnerConfigKey& key : runner_config_keys()) keys.insert(key.path);
  for (const JobConfigKey& key : job_config_keys()) keys.insert(key.path);
  EXPECT_EQ(leaves, keys);
  // Values: the literal numbers of the structs, and the job's LWPR defaults rather than the library's.
  EXPECT_EQ(defaults["dt"], 0.01);
  EXPECT_EQ(defaults["integrator"], "runge_kutta_4");
  EXPECT_EQ(defaults["learning"]["lwpr"]["init_D"], 0.05);
  EXPECT_NE(defaults["learning"]["lwpr"]["init_D"], lwpr::LwprParams{}.init_D(0, 0));
  EXPECT_EQ(defaults["learning"]["lwpr"]["trust_n_data"], 5.0);
  EXPECT_EQ(defaults["recording"]["series"], nlohmann::json::array({"TRIAL"}));
  // Task-space defaults scale to the arm's reach: "auto" (trajectory_config.hpp), not the LWR III's numbers.
  EXPECT_EQ(defaults["trajectory"]["figure_eight"]["centre"], "auto");
  EXPECT_EQ(defaults["trajectory"]["reaching"]["box_min"], "auto");
}

TEST(JobConfigJson, EveryFieldRoundTripsThroughTheTable) {
  // Change keys of every value kind from their defaults, write every key, parse: each field reads back what was written.
  JobConfig changed;
  changed.active_joints = {1, 3};
  changed.seed = 7;
  changed.simulation.dt = 0.005;
  changed.simulation.integrator = IntegratorKind::verlet;
  changed.control.kp = Eigen::Vector2d(10.0, 20.0);
  changed.control.mode = ControlMode::feedback;
  changed.control.feed_forward = FeedForwardSource::analytic;
  changed.trajectory.kind = TrajectoryKind::reaching;
  changed.trajectory.recorded.filter = RecordedFilter::low_pass;
  changed.trajectory.reaching.profile = ReachProfile::sigmoid;
  changed.learning.mode = LearningMode::batch;
  changed.learning.lwpr.kernel = lwpr::Kernel::kBisquare;
  changed.learning.lwpr.init_D = Eigen::MatrixXd::Constant(6, 1, 0.3);
  changed.learning.lwpr.max_fields = 40;
  changed.mismatch.payload.offset = Eigen::Vector3d(0.0, 0.0, 0.1);
  changed.recording.series = {"PHI", "TOR"};
  changed.divergence.max_error_duration = 0.25;
  nlohmann::json written = make_job_config_defaults();
  for (const JobConfigKey& key : job_config_keys()) {
    nlohmann::json* node = &written;
    std::stringstream path(key.path);
    for (std::string part; std::getline(path, part, '.');) node = &(*node)[part];
    *node = make_field_json(key.field(changed));
  }
  JobConfig parsed = parse_job_config(written, 7);
  for (const JobConfigKey& key : job_config_keys()) {
    EXPECT_EQ(make_field_json(key.field(parsed)), make_field_json(key.field(changed))) << key.path;
  }
  EXPECT_EQ(parsed.simulation.integrator, IntegratorKind::verlet);
  EXPECT_EQ(parsed.trajectory.recorded.filter, RecordedFilter::low_pass);
  EXPECT_EQ(parsed.learning.lwpr.max_fields, 40u);
}

TEST(JobConfigJson, NullMeansTheDefaultAsInConfigurationsStoredBefore) {
  nlohmann::json config = make_job_config_defaults();
  config["learning"]["lwpr"]["init_D"] = nullptr;
  config["learning"]["lwpr"]["norm_in"] = nullptr;
  const JobConfig parsed = parse_job_config(config, 7);
  EXPECT_EQ(parsed.learning.lwpr.init_D(0, 0), 0.05);
  EXPECT_EQ(parsed.learning.lwpr.norm_in.size(), 1);
}

TEST(JobConfigJson, EveryProblemIsInTheOneMessageTheFirstPathLeads) {
  nlohmann::json config = make_job_config_defaults();
  config["dt"] = 1e-300;
  config["trajectory"]["sine"]["duration"] = 1e300;
  config["integrator_accuracy"] = 1e-300;
  try {
    parse_job_config(config, 7);
    FAIL() << "accepted";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.json_path(), "dt");
    const std::string text = error.what();
    EXPECT_NE(text.find("dt: 1e-300 s is outside the allowed range [0.0001, 0.1] s"), std::string::npos) << text;
    EXPECT_NE(text.find("; integrator_accuracy: 1e-300 is outside"), std::string::npos) << text;
    EXPECT_NE(text.find("; trajectory.sine.duration: 1e+300 s is outside"), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace armfarm

namespace armfarm {
namespace {

// Keys that take a number, a list or a matrix (learning.lwpr.init_D) are shown with their
// number as default but accept every shape in specs; a wrong shape is still refused by the
// validation, with its path.
TEST(JobConfigJson, MultiShapeKeysAcceptNumbersAndListsInSpecs) {
  const JobConfigSchema schema = make_experiment_config_schema();
  EXPECT_TRUE(schema.defaults["learning"]["lwpr"]["init_D"].is_number());
  EXPECT_TRUE(schema.type_reference()["learning"]["lwpr"]["init_D"].is_null());
  const std::string folder = std::string(ARMFARM_SOURCE_DIR) + "/sweeps";
  const std::string text = R"({"name": "shapes", "base": {"active_joints": [2, 4], "trajectory": {"sine": {"duration": 1}}},
      "sweep": {"grid": {"learning.lwpr.init_D": [0.05, [0.05, 0.05, 0.1, 0.1, 0.2, 0.2]]}}})";
  const ExpandedSweep sweep = expand_sweep(parse_sweep_spec(text, "shapes.json", folder, schema), schema);
  ASSERT_EQ(sweep.jobs.size(), 2u);
  EXPECT_NE(sweep.jobs[0].key, sweep.jobs[1].key);
  const std::string wrong = R"({"name": "shapes", "base": {"active_joints": [2, 4]},
      "sweep": {"grid": {"learning.lwpr.init_D": [[0.05, 0.05]]}}})";
  try {
    expand_sweep(parse_sweep_spec(wrong, "wrong.json", folder, schema), schema);
    ADD_FAILURE() << "a 2-element init_D for 6 inputs was accepted";
  } catch (const SpecError& error) {
    EXPECT_NE(error.lines().front().find("learning.lwpr.init_D"), std::string::npos) << error.lines().front();
  }
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/config/job_file_contents_test.cpp:
// A sweep's check reads a recorded trajectory once (JobFileContents, keyed by the content hash
// the configuration records), not once a job, and lends the samples to each job's check instead
// of copying them; a configuration that records another content, or none, reads its file.

namespace armfarm {
namespace {

namespace fs = std::filesystem;

TEST(JobFileContents, ARecordedTrajectoryIsReadOncePerContent) {
  const fs::path dir = fs::temp_directory_path() / ("armfarm_job_file_contents_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path csv = dir / "picking.csv";
  fs::copy_file(fs::path(ARMFARM_SOURCE_DIR) / "sweeps/thesis/data/picking_synthetic.csv", csv);

  nlohmann::json config = make_job_config_defaults();
  config["active_joints"] = {1, 2, 4};
  config["trajectory"]["kind"] = "recorded";
  config["trajectory"]["recorded"]["file"] = "picking.csv";
  config["trajectory"]["recorded"]["task_space"] = true;
  config["trajectory"]["recorded"]["sample_rate"] = 100;
  InputFileReader reader;
  const JobConfigSchema schema = make_experiment_config_schema();
  auto folder_of = [&](const std::string& field) { return field == "model" ? std::string(ARMFARM_SOURCE_DIR) : dir.string(); };
  ASSERT_TRUE(record_input_files(config, schema.input_files, folder_of, reader).empty());
  ASSERT_TRUE(config["inputs"].contains("trajectory.recorded.file"));
  const ModelFacts facts{7, {}, {}};

  JobFileContents contents;
  const std::string hash = config["inputs"]["trajectory.recorded.file"]["hash"];
  ValidJobConfig first = parse_recorded_job_config(config, facts, {}, &contents);
  ASSERT_GT(first.get().trajectory.recorded.samples.rows(), 10);
  const Eigen::MatrixXd samples = first.get().trajectory.recorded.samples;
  const std::vector<int> lines = first.get().trajectory.recorded.sample_lines;
  const double* storage = first.get().trajectory.recorded.samples.data();
  EXPECT_EQ(contents.recorded_hash, "");  // lent to `first`: nothing is held
  return_job_file_contents(std::move(first), contents);
  EXPECT_EQ(contents.recorded_hash, hash);
  EXPECT_EQ(contents.recorded_samples.data(), storage);

  // The file is gone: the same content is served from what the first job read, lent (the same
  // storage, not a copy)...
  fs::remove(csv);
  ValidJobConfig second = parse_recorded_job_config(config, facts, {}, &contents);
  EXPECT_EQ(second.get().trajectory.recorded.samples, samples);
  EXPECT_EQ(second.get().trajectory.recorded.sample_lines, lines);
  EXPECT_EQ(second.get().trajectory.recorded.samples.data(), storage);
  // ...while lent, the next check reads the file; and what an earlier check lent is not taken
  // back after a later one.
  EXPECT_THROW(parse_recorded_job_config(config, facts, {}, &contents), ConfigError);
  return_job_file_contents(std::move(second), contents);
  EXPECT_EQ(contents.recorded_hash, "");
  EXPECT_EQ(contents.recorded_samples.size(), 0);
  // ...but another recorded content, and a check without the contents, read the file.
  nlohmann::json other = config;
  other["inputs"]["trajectory.recorded.file"]["hash"] = "00000000000000000000000000000000";
  EXPECT_THROW(parse_recorded_job_config(other, facts, {}, &contents), ConfigError);
  EXPECT_THROW(parse_recorded_job_config(config, facts, {}, nullptr), ConfigError);
  // Returned, the contents serve the next job again.
  fs::copy_file(fs::path(ARMFARM_SOURCE_DIR) / "sweeps/thesis/data/picking_synthetic.csv", csv);
  return_job_file_contents(parse_recorded_job_config(config, facts, {}, &contents), contents);
  fs::remove(csv);
  EXPECT_EQ(parse_recorded_job_config(config, facts, {}, &contents).get().trajectory.recorded.samples, samples);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from runner/config/recorded_limits_test.cpp:
// Recorded joint-space trajectories are checked against the model's joint limits before any job
// runs: the first sample outside them is refused with its file line (issue 16).

namespace armfarm {
namespace {

// A 7-column joint-space recording of 20 rows at 0.1 rad, with `bad_row` (0-based data row,
// -1 for none) set to `value` in column `column`; a comment-free header on line 1.
std::string write_recording(const std::string& name, int bad_row, int column, double value) {
  const std::string path = test_support::scratch_file(name);
  std::ofstream out(path);
  out << "q1,q2,q3,q4,q5,q6,q7\n";
  for (int r = 0; r < 20; ++r) {
    if (r == 3) out << "\n";  // a blank line: file lines and rows differ from here on
    for (int c = 0; c < 7; ++c) out << (c ? "," : "") << (r == bad_row && c == column ? value : 0.1 + 0.001 * r);
    out << "\n";
  }
  return path;
}

nlohmann::json make_recorded_config(const std::string& file) {
  nlohmann::json config = make_job_config_defaults();
  config["trajectory"]["kind"] = "recorded";
  config["trajectory"]["recorded"]["file"] = file;
  config["trajectory"]["recorded"]["task_space"] = false;
  return config;
}

ModelFacts make_symmetric_facts(double limit) {
  ModelFacts facts;
  facts.movable_joints = 7;
  facts.lower_limits.assign(7, -limit);
  facts.upper_limits.assign(7, limit);
  return facts;
}

std::string error_of(const nlohmann::json& config, const ModelFacts& facts) {
  try {
    parse_job_config(config, facts);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "(accepted)";
}

TEST(RecordedLimits, TheFirstAngleOutsideItsLimitsIsRefusedWithItsLine) {
  // Data row 5 sits on file line 8 (the header, then a blank line after the third row).
  const std::string path = write_recording("limits_bad.csv", 5, 2, 100.0);
  const std::string error = error_of(make_recorded_config(path), make_symmetric_facts(2.0));
  std::remove(path.c_str());
  EXPECT_EQ(error.rfind("trajectory.recorded.file: " + path + ":8: ", 0), 0u) << error;
  EXPECT_NE(error.find(path + ":8: joint 3 angle 100 rad (column 3) is outside its limits [-2, 2] rad (the first sample outside them)"),
            std::string::npos)
      << error;
}

TEST(RecordedLimits, ARecordingWithinTheLimitsIsAccepted) {
  const std::string path = write_recording("limits_ok.csv", -1, 0, 0.0);
  EXPECT_EQ(error_of(make_recorded_config(path), make_symmetric_facts(2.0)), "(accepted)");
  // Without limits (the joint-count-only overload), 100 rad is not checked here.
  const std::string wild = write_recording("limits_unchecked.csv", 5, 2, 100.0);
  EXPECT_NO_THROW(parse_job_config(make_recorded_config(wild), 7));
  std::remove(path.c_str());
  std::remove(wild.c_str());
}

TEST(RecordedLimits, ActiveJointsMapColumnsToTheirJoints) {
  // Two active joints, 2 and 5: column 2 is joint 5, whose limit here is 0.5 rad.
  const std::string path = test_support::scratch_file("limits_active.csv");
  {
    std::ofstream out(path);
    out << "a,b\n";
    for (int r = 0; r < 20; ++r) out << "0.2," << (r == 10 ? 0.7 : 0.1) << "\n";
  }
  nlohmann::json config = make_recorded_config(path);
  config["active_joints"] = {2, 5};
  ModelFacts facts = make_symmetric_facts(3.0);
  facts.lower_limits[4] = -0.5;
  facts.upper_limits[4] = 0.5;
  const std::string error = error_of(config, facts);
  std::remove(path.c_str());
  EXPECT_NE(error.find(path + ":12: joint 5 angle 0.7 rad (column 2) is outside its limits [-0.5, 0.5] rad"), std::string::npos)
      << error;
}

TEST(RecordedLimits, ModelFactsCarryTheLwrLimits) {
  const ArmModel model = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf");
  const ModelFacts facts = make_model_facts(model);
  ASSERT_EQ(facts.movable_joints, 7);
  ASSERT_EQ(facts.lower_limits.size(), 7u);
  const Joint& first = model.joints[model.movable_joints()[0]];
  ASSERT_TRUE(first.has_position_limits);
  EXPECT_EQ(facts.lower_limits[0], first.lower);
  EXPECT_EQ(facts.upper_limits[0], first.upper);
  for (int j = 0; j < 7; ++j) EXPECT_LT(facts.lower_limits[j], facts.upper_limits[j]);
}

}  // namespace
}  // namespace armfarm
