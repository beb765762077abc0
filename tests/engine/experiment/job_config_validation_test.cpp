// The one validation of a job configuration: every problem at once with its key path, unit and
// range, the cost bound among them (its tick counts: job_workload_test.cpp).
#include "engine/experiment/job_config_validation.hpp"
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/trajectory/trajectory.hpp"
#include "support/test_arms.hpp"
#include "engine/model/model_loading.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace armfarm {
namespace {

const ModelFacts kLwr3{7};

std::string problems_of(const JobConfig& config) { return make_problems_text(validate(config, kLwr3)); }

std::set<std::string> paths_of(const JobConfig& config) {
  std::set<std::string> paths;
  for (const ConfigProblem& problem : validate(config, kLwr3)) paths.insert(problem.path);
  return paths;
}

TEST(JobConfigValidation, DefaultsAreValid) {
  EXPECT_EQ(problems_of(JobConfig()), "");
  JobConfig config;
  config.active_joints = {2, 4};
  EXPECT_EQ(problems_of(config), "");
}

TEST(JobConfigValidation, EveryDefaultLiesInItsRange) {
  // The same check per key: a default outside its own range would make the defaults invalid.
  JobConfig config;
  for (const JobConfigKey& key : job_config_keys()) {
    const FieldRef field = key.field(config);
    if (field.kind == ValueKind::real) { EXPECT_TRUE(key.range.contains(field.real())) << key.path; }
    if (field.kind == ValueKind::integer) { EXPECT_TRUE(key.range.contains(static_cast<double>(field.get_integer(field.field)))) << key.path; }
    if (field.kind == ValueKind::integer_or_auto && field.optional_integer()) { EXPECT_TRUE(key.range.contains(*field.optional_integer())) << key.path; }
    if (field.kind == ValueKind::real_or_auto && field.optional_real()) { EXPECT_TRUE(key.range.contains(*field.optional_real())) << key.path; }
  }
}

TEST(JobConfigValidation, NegativeFigureEightScaleNamesPathAndRange) {
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::figure_eight;
  config.trajectory.figure_eight.scale = -1.0;
  EXPECT_EQ(problems_of(config), "trajectory.figure_eight.scale: -1 is outside the allowed range (0, 10]");
}

TEST(JobConfigValidation, ReturnsEveryProblemAtOnceWithUnits) {
  JobConfig config;
  config.simulation.dt = 1e-300;
  config.simulation.integrator_accuracy = 1e-300;
  config.trajectory.sine.duration = 1e300;
  config.trajectory.sine.frequency = Eigen::VectorXd::Constant(1, -1.0);
  config.control.kp = Eigen::VectorXd::Constant(3, 10.0);
  const std::string text = problems_of(config);
  EXPECT_EQ(paths_of(config), (std::set<std::string>{"dt", "integrator_accuracy", "trajectory.sine.duration",
                                                     "trajectory.sine.frequency[0]", "control.kp"}))
      << text;
  EXPECT_NE(text.find("dt: 1e-300 s is outside the allowed range [0.0001, 0.1] s"), std::string::npos) << text;
  EXPECT_NE(text.find("integrator_accuracy: 1e-300 is outside the allowed range [1e-12, 0.1]"), std::string::npos) << text;
  EXPECT_NE(text.find("trajectory.sine.duration: 1e+300 s is outside the allowed range (0, 86400] s"), std::string::npos) << text;
  EXPECT_NE(text.find("control.kp: has 3 values; give none (the stated rule), 1 (all joints) or one per active joint (7)"),
            std::string::npos)
      << text;
}

TEST(JobConfigValidation, RefusesJobsAboveTheCostBoundSayingWhy) {
  JobConfig config;
  config.trajectory.sine.duration = 60000.0;  // in range, but 6e6 ticks at dt = 0.01 s
  const std::vector<ConfigProblem> problems = validate(config, kLwr3);
  ASSERT_EQ(problems.size(), 1u) << make_problems_text(problems);
  EXPECT_EQ(problems[0].path, "trajectory.sine.duration");
  // 6e6 training ticks + the default held-out pass (1 period of 0.25 Hz = 400 ticks), collected and run once.
  EXPECT_NE(problems[0].message.find("6.0008e+06 control ticks"), std::string::npos) << problems[0].message;
  EXPECT_NE(problems[0].message.find("at most 5e+06 ticks"), std::string::npos) << problems[0].message;
  // Batch: collect passes count too (2 repeats + evaluation = 3 passes of 2e6 ticks).
  config.trajectory.sine.duration = 20000.0;
  EXPECT_EQ(paths_of(config), std::set<std::string>{});
  config.learning.mode = LearningMode::batch;
  EXPECT_EQ(paths_of(config), std::set<std::string>{"trajectory.sine.duration"});
  // Figure-eight: points × loops.
  config = JobConfig();
  config.trajectory.kind = TrajectoryKind::figure_eight;
  config.trajectory.figure_eight.loops = 10000;
  EXPECT_EQ(paths_of(config), std::set<std::string>{"trajectory.figure_eight.loops"});
  // Epochs × samples: 1000 epochs over 0.75 × 2 × 2000 samples = 3e6 updates is fine, × 10 is not.
  config = JobConfig();
  config.learning.mode = LearningMode::batch;
  config.learning.epochs = 1000;
  EXPECT_EQ(paths_of(config), std::set<std::string>{});
  config.trajectory.sine.duration = 200.0;
  EXPECT_EQ(paths_of(config), std::set<std::string>{"learning.epochs"});
  JobCostLimits generous;
  generous.max_learner_updates = 1e8;
  EXPECT_TRUE(validate(config, kLwr3, generous).empty());
}

TEST(JobConfigValidation, CostBoundCountsHeldOutPasses) {
  // Reaching, 100 points a reach: training 10 reaches = 1000 ticks; held-out 10000 reaches =
  // 1e6 ticks a pass, collected once and run at 4 checkpoints = 5e6 + 1000 ticks > 5e6.
  JobConfig config;
  config.trajectory.kind = TrajectoryKind::reaching;
  config.trajectory.reaching.reaches = 10;
  config.learning.heldout_segments = 10000;
  config.learning.heldout_checkpoints = {0, 2, 5, 10};
  const std::vector<ConfigProblem> problems = validate(config, kLwr3);
  ASSERT_EQ(problems.size(), 1u) << make_problems_text(problems);
  EXPECT_EQ(problems[0].path, "learning.heldout_checkpoints");
  EXPECT_NE(problems[0].message.find("5.001e+06 control ticks"), std::string::npos) << problems[0].message;
  EXPECT_NE(problems[0].message.find("held-out 1e+06 per pass × 5 passes"), std::string::npos) << problems[0].message;
  // Three checkpoints: 4e6 + 1000 ticks fit; so does the same job without held-out evaluation.
  config.learning.heldout_checkpoints = {0, 5, 10};
  EXPECT_EQ(problems_of(config), "");
  config.learning.heldout_checkpoints = {0, 2, 5, 10};
  config.learning.heldout = false;
  EXPECT_EQ(problems_of(config), "");
  // No checkpoints: one evaluation at the end (collection + 1 pass).
  config.learning.heldout = true;
  config.learning.heldout_checkpoints = {};
  config.learning.heldout_segments = 24990;  // 2 × 2.499e6 + 1000 = 4.999e6 ticks fit, 25000 would not
  EXPECT_EQ(problems_of(config), "");
  config.learning.heldout_segments = 25000;
  EXPECT_EQ(paths_of(config), std::set<std::string>{"learning.heldout_checkpoints"});
}

TEST(JobConfigValidation, CrossFieldAndShapeRules) {
  JobConfig config;
  config.active_joints = {2, 9, 2};
  config.learning.mode = LearningMode::none;  // while feed_forward is the learner
  config.trajectory.reaching.box_min = Eigen::Vector3d(0.8, 0.2, 0.0);
  config.trajectory.reaching.box_max = Eigen::Vector3d(0.7, 0.7, 0.5);
  config.learning.lwpr.init_D = Eigen::MatrixXd::Constant(2, 1, 1.0);  // neither 1 nor 3n elements
  config.recording.series = {"PHI", "TORQUE"};
  config.recording.every = 0;
  EXPECT_EQ(paths_of(config), (std::set<std::string>{"active_joints[1]", "active_joints[2]", "learning.mode",
                                                     "trajectory.reaching.box_max[0]", "learning.lwpr.init_D",
                                                     "recording.series[1]", "recording.every"}))
      << problems_of(config);
}

TEST(JobConfigValidation, SsgprBlockIsCheckedWhenSsgprLearns) {
  JobConfig config;
  config.learning.ssgpr.params.lengthscales = Eigen::VectorXd::Constant(4, 1.0);  // neither 1 nor 3n
  config.learning.ssgpr.fit_samples = 1;
  EXPECT_EQ(paths_of(config), (std::set<std::string>{"learning.ssgpr.lengthscales"})) << problems_of(config);  // lwpr learns
  config.learning.learner = LearnerKind::ssgpr;
  config.learning.ssgpr.params.features = 0;
  config.learning.ssgpr.params.forgetting = 0.0;
  EXPECT_EQ(paths_of(config), (std::set<std::string>{"learning.ssgpr.lengthscales", "learning.ssgpr.features",
                                                     "learning.ssgpr.forgetting", "learning.ssgpr.fit_samples"}))
      << problems_of(config);
  EXPECT_NE(problems_of(config).find("learning.ssgpr.features: 0 is outside the allowed range [1, 2000] (integers)"), std::string::npos)
      << problems_of(config);
  EXPECT_NE(problems_of(config).find("learning.ssgpr.lengthscales: has 4 values; give 1 or one per input (3 × 7 active joints = 21)"),
            std::string::npos)
      << problems_of(config);
  config = JobConfig();
  config.learning.learner = LearnerKind::ssgpr;
  EXPECT_TRUE(validate(config, kLwr3).empty()) << problems_of(config);
}

TEST(JobConfigValidation, ProblemsCarryPathMessageUnitAndRangeApart) {
  JobConfig config;
  config.simulation.dt = -1.0;
  bool found = false;
  for (const ConfigProblem& problem : validate(config, kLwr3)) {
    if (problem.path != "dt") continue;
    found = true;
    EXPECT_EQ(problem.unit, "s");
    ASSERT_TRUE(problem.range.has_value());
    EXPECT_FALSE(problem.range->contains(-1.0));
    EXPECT_TRUE(problem.range->contains(0.01));
    EXPECT_EQ(problem.message.find("dt:"), std::string::npos) << "the message repeats the path: " << problem.message;
  }
  EXPECT_TRUE(found) << problems_of(config);
  // A learner parameter's own problem, found by the learner's check, lands at its key with the
  // learner's words and no "LWPR parameter" prefix.
  config = JobConfig();
  config.learning.lwpr.init_D = Eigen::MatrixXd::Identity(21, 21);
  config.learning.lwpr.init_D(0, 1) = 0.5;  // not symmetric
  const std::vector<ConfigProblem> problems = validate(config, kLwr3);
  ASSERT_EQ(problems.size(), 1u) << problems_of(config);
  EXPECT_EQ(problems[0].path, "learning.lwpr.init_D");
  EXPECT_EQ(problems[0].message, "must be symmetric");
  EXPECT_EQ(problems[0].unit, "");
  EXPECT_FALSE(problems[0].range.has_value());
}

TEST(JobConfigValidation, SsgprCostBoundNamesTheFeatures) {
  JobConfig config;
  config.learning.learner = LearnerKind::ssgpr;
  config.trajectory.kind = TrajectoryKind::sine;
  config.trajectory.sine.duration = 3000.0;  // 300 000 online updates
  config.learning.ssgpr.params.features = 1000;  // × 4e6 = 1.2e12: allowed
  EXPECT_TRUE(validate(config, kLwr3).empty()) << problems_of(config);
  config.learning.ssgpr.params.features = 2000;  // × 1.6e7 = 4.8e12: refused
  EXPECT_EQ(paths_of(config), (std::set<std::string>{"learning.ssgpr.features"})) << problems_of(config);
  config.learning.learner = LearnerKind::lwpr;  // the block is LWPR's concern no more
  EXPECT_TRUE(validate(config, kLwr3).empty()) << problems_of(config);
}

// A sine set beyond the arm: checked against the LWR III's facts (joint 4: limits ±2.094 rad,
// 1.963 rad/s; start 1.571 rad), the held-out variant's amplitude included.
TEST(JobConfigValidation, SineBeyondAJointsLimitsNamesTheJointTheNeedAndTheLimit) {
  const ModelFacts lwr = make_model_facts(testing::load_lwr3());
  JobConfig config;
  EXPECT_EQ(make_problems_text(validate(config, lwr)), "");  // the default sine keeps within them
  config.trajectory.sine.frequency = Eigen::VectorXd::Constant(7, 0.25);
  config.trajectory.sine.frequency[3] = 1.5;
  config.trajectory.sine.amplitude = Eigen::VectorXd::Constant(1, 0.3);
  EXPECT_EQ(make_problems_text(validate(config, lwr)),
            "trajectory.sine.frequency: joint 4 needs 2.82743 rad/s (amplitude 0.3 rad × 2π × 1.5 Hz), above its velocity limit "
            "1.9635 rad/s; at this frequency an amplitude of at most 0.208333 rad keeps within it");
  config.trajectory.sine.frequency.resize(0);
  config.trajectory.sine.amplitude = Eigen::VectorXd::Constant(1, 0.6);  // about joint 4's start, 1.571 + 0.6 > 2.094
  EXPECT_EQ(make_problems_text(validate(config, lwr)),
            "trajectory.sine.amplitude: joint 4 would move over [0.970796, 2.1708] rad, outside its limits [-2.0944, 2.0944] rad; "
            "about offset 1.5708 rad an amplitude of at most 0.523599 rad keeps within them");
  config.learning.heldout_amplitude_scale = 1.2;  // a held-out variant larger than the training sine
  config.trajectory.sine.amplitude = Eigen::VectorXd::Constant(1, 0.5);
  EXPECT_NE(make_problems_text(validate(config, lwr)).find("(the held-out variant's amplitude"), std::string::npos);
  // Without a learner there is no held-out variant.
  config.learning.mode = LearningMode::none;
  config.control.feed_forward = FeedForwardSource::none;
  EXPECT_EQ(make_problems_text(validate(config, lwr)), "");
}

TEST(JobConfigValidation, TheDefaultSineShrinksToFitTheJointsRangeAndSpeed) {
  const JointRanges ranges{Eigen::Vector2d(-1.0, -3.07), Eigen::Vector2d(1.0, -0.07), Eigen::Vector2d(10.0, 0.2)};
  const SineTrajectoryConfig sine = resolve_sine_defaults(SineTrajectoryConfig{}, 2, Eigen::Vector2d(0.9, -0.1), &ranges);
  EXPECT_NEAR(sine.amplitude[0], kSineRangeShare * 0.1, 1e-15);                          // 0.1 rad to the upper limit
  EXPECT_NEAR(sine.amplitude[1], std::min(kSineRangeShare * 0.03, kSineVelocityShare * 0.2 / (2 * M_PI * 0.25)), 1e-15);
  // A given amplitude is kept (validate() judges it).
  SineTrajectoryConfig set;
  set.amplitude = Eigen::VectorXd::Constant(1, 0.5);
  EXPECT_EQ(resolve_sine_defaults(set, 2, Eigen::Vector2d(0.9, -0.1), &ranges).amplitude, Eigen::Vector2d::Constant(0.5));
}

TEST(JobConfigValidation, StartPostureIsOneValuePerJointInsideItsLimits) {
  const ModelFacts panda = make_model_facts(load_arm_model_file(std::string(ARMFARM_TEST_DATA_DIR) + "/arms/franka_panda.urdf"));
  JobConfig config;
  config.start_posture = (Eigen::VectorXd(7) << 0, 0, 0, -1.5, 0, 1.5, 0).finished();
  EXPECT_EQ(make_problems_text(validate(config, panda)), "");
  config.start_posture[3] = 0.0;  // joint 4's range excludes 0
  EXPECT_EQ(make_problems_text(validate(config, panda)),
            "start_posture[3]: joint 4 (panda_joint4) at 0 rad is outside its range [-3.0718, -0.0698] rad");
  config.start_posture[5] = 4.0;
  EXPECT_EQ(validate(config, panda).size(), 2u);  // every joint outside its range, at once
  config.start_posture = Eigen::VectorXd::Zero(3);
  EXPECT_EQ(make_problems_text(validate(config, panda)),
            "start_posture: has 3 values; give none (the stated rule) or one per joint of the arm (7, active or locked)");
  // One per joint of the arm, not per active joint: locked joints start somewhere too.
  config.active_joints = {1, 2, 4};
  EXPECT_NE(make_problems_text(validate(config, panda)), "");
}

TEST(JobConfigValidation, EnumTablesSpellEveryEnumeratorOnce) {
  for (const EnumNames* names : {&control_mode_names(), &feed_forward_source_names(), &trajectory_kind_names(),
                                 &differentiation_names(), &reach_profile_names(), &recorded_filter_names(),
                                 &learning_mode_names(), &lwpr_kernel_names(), &integrator_kind_names(),
                                 &learner_kind_names()}) {
    std::set<std::string> spellings;
    for (std::size_t i = 0; i < names->size(); ++i) {
      EXPECT_EQ((*names)[i].value, static_cast<int>(i)) << (*names)[i].name;  // declaration order, no gaps
      EXPECT_TRUE(spellings.insert((*names)[i].name).second) << (*names)[i].name;
    }
  }
}

}  // namespace
}  // namespace armfarm
