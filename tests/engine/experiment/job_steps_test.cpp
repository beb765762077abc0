// A job's PD and integrator steps (engine/experiment/job_steps.hpp) on real arms: the
// armature-free KUKA LBR iiwa 14 of the arm corpus (damping 0.5 N·m·s/rad, last link
// 0.001 kg·m²), whose default job diverged at the old fixed steps (1 PD period, 1 RK4 step per
// tick), and the LWR III, whose default job must keep them.
#include "engine/experiment/control_pass.hpp"
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/experiment/job_model.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/experiment/job_steps.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/model/model_loading.hpp"
#include "job_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace armfarm {
namespace {

ArmModel load_iiwa() {
  EndEffectorConfig tip;
  tip.link = "tool_tcp";  // two leaves: the job names one
  return load_arm_model(std::string(ARMFARM_TEST_DATA_DIR) + "/arms/kuka_iiwa14.urdf", tip);
}

/// One feedback pass of `config` over its training sine with the steps the setup holds.
PassResult run_feedback_pass(const ArmModel& model, const JobConfig& config) {
  JobSetup setup(model, config);
  const JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
  ArmSimulation plant = setup.make_plant();
  const CompositeController controller = setup.make_controller();
  PassOptions options;
  options.controller = &controller;
  return run_control_pass(setup, plant, trajectories.training, options);
}

TEST(JobSteps, AutoMakesTheArmatureFreeArmsDefaultJobFinish) {
  const ArmModel model = load_iiwa();
  JobConfig config;  // the default job: online LWPR on the 20 s sine, held-out evaluation
  config.end_effector.link = "tool_tcp";
  const JobOutcome outcome = run_experiment(model, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  const auto metrics = testing::job_metrics(outcome);
  EXPECT_EQ(metrics.at("heldout_diverged"), 0.0);
  EXPECT_GT(metrics.at("pd_substeps_used") * metrics.at("integrator_steps_used"), 1.0);
  std::printf("iiwa 14 default job: pd_substeps %g, integrator_steps_per_tick %g, tracking_nmse %.4g\n",
              metrics.at("pd_substeps_used"), metrics.at("integrator_steps_used"), metrics.at("tracking_nmse"));
}

TEST(JobSteps, TheOldFixedStepsDivergeOnThatArmAndAreRefused) {
  const ArmModel model = load_iiwa();
  JobConfig config;
  config.end_effector.link = "tool_tcp";
  config.trajectory.sine.duration = 2.0;
  config.learning.mode = LearningMode::none;
  config.control.mode = ControlMode::feedback;
  config.control.feed_forward = FeedForwardSource::none;
  // Run as they are (JobSetup takes explicit steps without judging them): the pass diverges.
  config.simulation.pd_substeps = 1;
  config.simulation.integrator_steps_per_tick = 1;
  const PassResult old_steps = run_feedback_pass(model, config);
  EXPECT_EQ(old_steps.status, JobStatus::diverged);
  EXPECT_LT(old_steps.end_time, 0.5) << old_steps.message;
  // The diverged pass says what to change.
  EXPECT_NE(old_steps.message.find("set pd_substeps to"), std::string::npos) << old_steps.message;
  // validate() refuses them, naming the key, the joint and a value that works.
  try {
    run_experiment(model, config);
    ADD_FAILURE() << "the old steps ran";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("integrator_steps_per_tick: 1 is unstable: ", 0), 0u) << message;
    EXPECT_NE(message.find("joint 7"), std::string::npos) << message;
    EXPECT_NE(message.find("are stable with the criterion's margin"), std::string::npos) << message;
  }
  // "auto" on both: the same pass finishes.
  config.simulation.pd_substeps.reset();
  config.simulation.integrator_steps_per_tick.reset();
  const PassResult automatic = run_feedback_pass(model, config);
  EXPECT_EQ(automatic.status, JobStatus::done) << automatic.message;
}

TEST(JobSteps, TheLwrIiiDefaultJobKeepsOnePdPeriodAndOneStepPerTick) {
  const ArmModel model = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf");
  JobConfig config;
  JobSetup setup(model, config);
  const JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
  setup.fit_to_trajectories({&trajectories.training, &*trajectories.heldout});
  EXPECT_EQ(setup.pd_substeps(), 1);
  EXPECT_EQ(setup.integrator_steps(), 1);
  const StepChoice start = calc_start_posture_steps(config, make_model_facts(model));
  EXPECT_TRUE(start.found);
  EXPECT_EQ(start.pd_substeps, 1);
  EXPECT_EQ(start.integrator_steps, 1);
  // Without armature its wrist's passive decay (b·h/M = 0.05 × 0.01 / 1.25e-4 = 4 on joint 7)
  // is outside RK4's region at one step per tick: the criterion asks for finer steps.
  config.simulation.armature_scale = 0.0;
  const StepChoice bare = calc_start_posture_steps(config, make_model_facts(model));
  EXPECT_TRUE(bare.found);
  EXPECT_GT(bare.pd_substeps * bare.integrator_steps, 1);
}

// The criterion judges the configured start posture, not the file's: planar2's mass matrix at
// q = (0, π/2) against the closed form of the double pendulum with distributed masses
// (models/planar2.urdf: M11 = I1 + m1·lc1² + I2 + m2·(l1² + lc2² + 2·l1·lc2·cos q2),
// M12 = I2 + m2·(lc2² + l1·lc2·cos q2), M22 = I2 + m2·lc2²), and the same loops as on the job's model.
TEST(JobSteps, StartPostureLoopsUseTheConfiguredPosture) {
  const ArmModel file = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/planar2.urdf");
  const double i1 = 0.1668666667, i2 = 0.08015, m1 = 2.0, m2 = 1.5, l1 = 1.0, lc1 = 0.5, lc2 = 0.4;
  const auto closed_form = [&](double q2) {
    Eigen::Matrix2d mass;
    mass(0, 0) = i1 + m1 * lc1 * lc1 + i2 + m2 * (l1 * l1 + lc2 * lc2 + 2.0 * l1 * lc2 * std::cos(q2));
    mass(0, 1) = mass(1, 0) = i2 + m2 * (lc2 * lc2 + l1 * lc2 * std::cos(q2));
    mass(1, 1) = i2 + m2 * lc2 * lc2;
    return mass;
  };
  const ModelFacts facts = make_model_facts(file);
  JobConfig config;
  const std::optional<StartPostureLoops> stated = make_start_posture_loops(config, facts);
  ASSERT_TRUE(stated);
  EXPECT_LT((stated->plants[0].mass - closed_form(0.0)).norm(), 1e-9);  // the file's posture: q = 0
  config.start_posture = Eigen::Vector2d(0.0, M_PI / 2);
  const std::optional<StartPostureLoops> set = make_start_posture_loops(config, facts);
  ASSERT_TRUE(set);
  EXPECT_LT((set->plants[0].mass - closed_form(M_PI / 2)).norm(), 1e-9);
  // The gains follow the posture's M_jj (kp = ω²·M_jj), and agree with the job's own model.
  const std::optional<StartPostureLoops> job = make_start_posture_loops(config, make_model_facts(make_job_model(file, config)));
  ASSERT_TRUE(job);
  EXPECT_LT((set->plants[0].mass - job->plants[0].mass).norm(), 1e-12);
  ASSERT_EQ(set->controllers.size(), job->controllers.size());
  EXPECT_LT((set->controllers[0].gains.kp - job->controllers[0].gains.kp).norm(), 1e-9);
  EXPECT_LT(set->controllers[0].gains.kp[0], stated->controllers[0].gains.kp[0]);
}

// The memo of a model's facts (ModelFacts::step_checks) gives the problems check_job_steps gives,
// key and message, for loops with and without problems (the iiwa at the old fixed steps is
// refused on joint 7; "auto" is not), computes each distinct loop once, and tells loops apart
// that differ only in a gain scale; validate() with and without it finds the same problems. The
// gravity stiffness at the start posture, computed once, is the bits a fresh model's gives.
TEST(JobSteps, TheStepCheckMemoGivesCheckJobStepsProblemsOncePerDistinctLoop) {
  const ArmModel model = load_iiwa();
  const ModelFacts facts = make_model_facts(model);
  ASSERT_TRUE(facts.step_checks);
  ModelFacts plain = facts;
  plain.step_checks = nullptr;
  std::vector<JobConfig> configs;
  for (double scale : {0.2, 1.0, 3.0}) {
    for (bool old_steps : {false, true}) {
      JobConfig config;
      config.end_effector.link = "tool_tcp";
      config.control.gain_scale = scale;
      if (old_steps) {
        config.simulation.pd_substeps = 1;
        config.simulation.integrator_steps_per_tick = 1;
      }
      configs.push_back(config);
    }
  }
  std::size_t refused = 0;
  for (int round = 0; round < 2; ++round) {
    for (const JobConfig& config : configs) {
      const std::optional<StartPostureLoops> loops = make_start_posture_loops(config, facts);
      ASSERT_TRUE(loops);
      const std::vector<StepProblem> direct = check_job_steps(config, loops->plants, loops->controllers, loops->joint_numbers);
      const std::vector<StepProblem> memo = facts.step_checks->check(config, *loops);
      ASSERT_EQ(memo.size(), direct.size());
      for (std::size_t i = 0; i < direct.size(); ++i) {
        EXPECT_EQ(memo[i].key, direct[i].key);
        EXPECT_EQ(memo[i].message, direct[i].message);
      }
      if (round == 0) refused += direct.empty() ? 0 : 1;
      const std::vector<ConfigProblem> with_memo = validate(config, facts), without = validate(config, plain);
      ASSERT_EQ(with_memo.size(), without.size());
      for (std::size_t i = 0; i < without.size(); ++i) {
        EXPECT_EQ(with_memo[i].path, without[i].path);
        EXPECT_EQ(with_memo[i].message, without[i].message);
      }
    }
  }
  EXPECT_GE(refused, 1u);                               // the old steps on the iiwa
  EXPECT_LT(refused, configs.size());                    // not "auto"
  EXPECT_EQ(facts.step_checks->computed(), configs.size());  // six loops, each checked once
  // The start posture's gravity stiffness: computed once, the same bits as a fresh computation.
  const std::vector<double>& start = facts.start_positions;
  const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(start.data(), static_cast<Eigen::Index>(start.size()));
  const Eigen::MatrixXd first = facts.gravity_stiffness_at(q), again = facts.gravity_stiffness_at(q);
  const Eigen::MatrixXd fresh = make_model_facts(model).gravity_stiffness_at(q);
  EXPECT_TRUE(first == fresh);
  EXPECT_TRUE(again == fresh);
  EXPECT_GT(fresh.norm(), 0.0);
  // Elsewhere it is computed for the posture asked.
  Eigen::VectorXd bent = q;
  bent[1] += 0.5;
  EXPECT_FALSE(facts.gravity_stiffness_at(bent) == fresh);
}

// The coupled criterion against the simulated arm: planar2's gains placed on the diagonal give
// kd·h/M_jj = 0.4 on both joints at h = 10 ms, inside the one-joint bound, but its fastest coupled
// mode has kd·h/M = 0.4 / (1 − r) = 2.61 (r = M12/√(M11·M22) = 0.847 at q2 = 0), outside it
// (ρ = 1.64 per PD period). Simulated, the loop at one PD period per tick does not settle: the
// error grows until the coupling's nonlinearity (r falls with cos q2) holds it in a limit cycle
// (planar2 has no effort or velocity limits, so nothing reports it as diverged), with a mean
// |feedback| over the last segment (4–5 s) of a 5 s pass of 489 N·m against 18.5 N·m at two periods (what
// "auto" picks; measured with this test's printout).
TEST(JobSteps, ThePlanarArmsCoupledModeIsUnstableAtOnePdPeriodAndNotAtTwo) {
  const ArmModel model = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/planar2.urdf");
  JobConfig config;
  config.trajectory.sine.duration = 5.0;
  config.learning.mode = LearningMode::none;
  config.control.mode = ControlMode::feedback;
  config.control.feed_forward = FeedForwardSource::none;
  config.simulation.integrator_steps_per_tick = 1;
  const auto mean_feedback = [&](int pd_substeps) {
    config.simulation.pd_substeps = pd_substeps;
    JobSetup setup(model, config);
    const JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
    ArmSimulation plant = setup.make_plant();
    const CompositeController controller = setup.make_controller();
    PassStatistics statistics(setup.dof(), 0.0);
    PassOptions options;
    options.controller = &controller;
    options.statistics = &statistics;
    const PassResult result = run_control_pass(setup, plant, trajectories.training, options);
    EXPECT_EQ(result.status, JobStatus::done) << result.message;
    return statistics.calc_segment_feedback(statistics.segments().back());
  };
  const double one = mean_feedback(1), two = mean_feedback(2);
  std::printf("planar2 feedback pass, mean |fb| over the last segment: %.4g N·m at 1 PD period, %.4g at 2\n", one, two);
  EXPECT_GT(one, 10.0 * two);
  config.simulation.pd_substeps.reset();
  config.simulation.integrator_steps_per_tick.reset();
  EXPECT_EQ(calc_start_posture_steps(config, make_model_facts(model)).pd_substeps, 2);
  const std::optional<StartPostureLoops> loops = make_start_posture_loops(config, make_model_facts(model));
  ASSERT_TRUE(loops);
  EXPECT_FALSE(calc_loop_stability(loops->plants[0], &loops->controllers[0].gains, LoopSteps{0.01, 1, 1, true}).stable());
  EXPECT_TRUE(calc_loop_stability(loops->plants[0], &loops->controllers[0].gains, LoopSteps{0.01, 2, 1, true}).stable());
}

TEST(JobSteps, CollectionUsesTheJobsGainsUnlessCollectGainScaleIsSet) {
  JobConfig config;
  config.control.gain_scale = 0.2;
  config.learning.mode = LearningMode::batch;
  EXPECT_EQ(calc_collect_gain_scale(config), 0.2);
  const PdGains gains{Eigen::VectorXd::Constant(2, 100.0), Eigen::VectorXd::Constant(2, 10.0)};
  EXPECT_EQ(make_job_controllers(config, gains, Eigen::VectorXd()).size(), 1u);  // one controller: the job's
  config.learning.collect_gain_scale = 1.0;
  EXPECT_EQ(calc_collect_gain_scale(config), 1.0);
  const std::vector<JobController> both = make_job_controllers(config, gains, Eigen::VectorXd());
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[1].scale_key, "learning.collect_gain_scale");
  EXPECT_EQ(both[1].gains.kp[0], 100.0);
}

}  // namespace
}  // namespace armfarm
