// Where a job's default gains are placed (JobSetup::fit_to_trajectories, engine/control/pd_gains.hpp):
// on the arm corpus's Kinova Gen3, which starts straight up where its vertical-axis joints carry
// a fraction of the inertia they carry along the default sine (M_11 0.008 kg·m² at the start,
// 0.23 along it) and where gravity's stiffness on its wrist exceeds kp at gain_scale 0.2, and
// on the LWR III, whose gains must stay those of its start posture bit for bit.
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/model/model_loading.hpp"
#include "engine/control/pd_gains.hpp"
#include "support/test_arms.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <string>
#include <nlohmann/json.hpp>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace armfarm {
namespace {

ArmModel load_gen3() { return load_arm_model(std::string(ARMFARM_TEST_DATA_DIR) + "/arms/kinova_gen3.urdf"); }

/// sweeps/quickstart.json's low-gain online job with the narrowest kernels (init_D 0.02), the
/// one that diverged longest on the Gen3 before the gains were placed for its postures.
JobConfig make_quickstart_low_gain_job() {
  JobConfig config;
  config.trajectory.sine.duration = 20.0;
  config.control.mode = ControlMode::composite;
  config.control.feed_forward = FeedForwardSource::learner;
  config.control.gain_scale = 0.2;
  config.learning.mode = LearningMode::online;
  config.learning.collect_gain_scale = 1.0;
  config.learning.lwpr.init_D = Eigen::MatrixXd::Constant(1, 1, 0.02);
  return config;
}

TEST(JobSetup, TheGen3sGainsHoldItAtEveryPostureItsTrajectoriesVisit) {
  const ArmModel model = load_gen3();
  const JobConfig config = make_quickstart_low_gain_job();
  JobSetup setup(model, config);
  const JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
  setup.fit_to_trajectories({&trajectories.training, &*trajectories.heldout});
  const double scale = config.control.gain_scale, omega2 = config.control.bandwidth * config.control.bandwidth;
  const Eigen::VectorXd kp = setup.gains_at(scale).kp * scale;
  for (const JointTrajectory* trajectory : {&trajectories.training, &*trajectories.heldout}) {
    for (int row = 0; row < trajectory->size(); row += 25) {
      const Eigen::VectorXd q = trajectory->q.row(row).transpose();
      const Eigen::MatrixXd mass = setup.nominal().calc_mass_matrix(q);
      const Eigen::MatrixXd stiffness = make_gravity_stiffness(setup.nominal(), q);
      for (int j = 0; j < setup.dof(); ++j) {
        // The full-scale bandwidth √(kp/M_jj) at least ω/√2 at every posture (within the 5 %
        // that sampling 20 postures per trajectory may miss).
        EXPECT_GE(setup.gains().kp[j] / mass(j, j), 0.95 * omega2 / kPlacementInertiaRatio) << "joint " << j + 1 << ", row " << row;
      }
      // The static stiffness Kp·s + ∂g/∂q stays positive definite: the feedback holds the arm up.
      const Eigen::MatrixXd held = Eigen::MatrixXd(kp.asDiagonal()) + 0.5 * (stiffness + stiffness.transpose());
      EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(held).eigenvalues().minCoeff(), 0.0) << "row " << row;
    }
  }
  // Placed on the start posture alone, joint 6's kp at 0.2 is below gravity's stiffness there.
  const Eigen::VectorXd start_inertia = setup.nominal().calc_mass_matrix(setup.nominal().start_positions()).diagonal();
  const PdGains start_gains = calc_pd_gains(config.control, start_inertia, setup.joint_numbers());
  const Eigen::MatrixXd start_stiffness = make_gravity_stiffness(setup.nominal(), setup.nominal().start_positions());
  EXPECT_LT(start_gains.kp[5] * scale, -start_stiffness(5, 5));
}

TEST(JobSetup, TheGen3sLowGainJobFinishesWhereTheStartPostureGainsDiverge) {
  const ArmModel model = load_gen3();
  JobConfig config = make_quickstart_low_gain_job();
  const JobOutcome placed = run_experiment(model, config);
  EXPECT_EQ(placed.status, JobStatus::done) << placed.message;
  // The same job with the gains as they were placed before, on the start posture alone (given
  // explicitly, so that they are run as given).
  JobSetup setup(model, config);
  const Eigen::VectorXd start_inertia = setup.nominal().calc_mass_matrix(setup.nominal().start_positions()).diagonal();
  const PdGains start_gains = calc_pd_gains(ControlConfig{}, start_inertia, setup.joint_numbers());
  config.control.kp = start_gains.kp;
  config.control.kd = start_gains.kd;
  const JobOutcome before = run_experiment(model, config);
  EXPECT_EQ(before.status, JobStatus::diverged) << before.message;
}

// An explicit PD period that the start posture allows but the gains placed for the trajectories'
// postures do not (the Gen3 at pd_substeps 5, its "auto" choice before the placement; run anyway,
// its held-out collection diverged after 5 minutes of RK4 at 1000 steps per PD period) is refused
// before any pass runs, with the value that works.
TEST(JobSetup, AnExplicitPdPeriodUnstableAlongTheTrajectoriesIsRefused) {
  const ArmModel model = load_gen3();
  JobConfig config;
  config.trajectory.sine.duration = 5.0;
  config.simulation.pd_substeps = 5;
  try {
    run_experiment(model, config);
    ADD_FAILURE() << "pd_substeps 5 ran";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.rfind("pd_substeps: 5 is unstable: ", 0), 0u) << message;
    EXPECT_NE(message.find("at a posture along the job's trajectories"), std::string::npos) << message;
    EXPECT_NE(message.find("is stable with the criterion's margin"), std::string::npos) << message;
  }
}

TEST(JobSetup, TheLwrIIIsGainsAreThoseOfItsStartPostureBitForBit) {
  const ArmModel model = load_arm_model(std::string(ARMFARM_SOURCE_DIR) + "/models/dlr_lwr3.urdf");
  for (double scale : {0.2, 1.0}) {
    JobConfig config;
    config.control.gain_scale = scale;
    JobSetup setup(model, config);
    const JobTrajectories trajectories = build_job_trajectories(config, setup.nominal());
    setup.fit_to_trajectories({&trajectories.training, &*trajectories.heldout});
    const PdGains start = make_pd_gains(config.control, setup.nominal(), setup.joint_numbers());
    EXPECT_EQ(setup.gains().kp, start.kp);
    EXPECT_EQ(setup.gains().kd, start.kd);
    EXPECT_EQ(setup.gains_at(scale).kp, start.kp);  // the floor does not bind
    EXPECT_EQ(setup.gains_at(scale).kd, start.kd);
  }
}

}  // namespace
}  // namespace armfarm

// ------------------------------------------------------------------------------------------------
// Folded in from engine/experiment/physics_choices_test.cpp:
// Physics and control choices a job makes visible (issue 12): whether a gain scale keeps the
// damping ratio, and the armature switched per job. Checked against the closed form of the
// default gain rule kp = M_jj·ω², kd = 2ζ·M_jj·ω.

namespace armfarm {
namespace {

/// ζ = kd / (2·√(kp·M_jj)) of the controller's scaled gains, per joint.
Eigen::VectorXd calc_damping_ratios(JobSetup& setup) {
  const CompositeController controller = setup.make_controller();
  const Eigen::VectorXd inertia = setup.nominal().calc_mass_matrix(setup.nominal().start_positions()).diagonal();
  return controller.kd().array() / (2.0 * (controller.kp().array() * inertia.array()).sqrt());
}

TEST(PhysicsChoices, GainScaleKeepsTheDampingRatioOnlyWhenAsked) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  config.control.gain_scale = 0.2;
  JobSetup thesis(model, config);
  const Eigen::VectorXd dropped = calc_damping_ratios(thesis);
  config.control.keep_damping_ratio = true;
  JobSetup kept(model, config);
  const Eigen::VectorXd same = calc_damping_ratios(kept);
  for (int j = 0; j < dropped.size(); ++j) {
    EXPECT_NEAR(dropped[j], std::sqrt(0.2), 1e-12) << "joint " << j + 1;
    EXPECT_NEAR(same[j], 1.0, 1e-12) << "joint " << j + 1;
  }
  // kp is scaled alike either way.
  EXPECT_TRUE(thesis.make_controller().kp().isApprox(kept.make_controller().kp(), 1e-15));
  std::printf("gain scale 0.2: damping ratio %.3f (kd × 0.2) or %.3f (kd × √0.2)\n", dropped[0], same[0]);
}

TEST(PhysicsChoices, ArmatureScaleChangesTheMassMatrixDiagonalByTheArmature) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  JobSetup with(model, config);
  config.simulation.armature_scale = 0.0;
  JobSetup without(model, config);
  const Eigen::VectorXd q = with.nominal().start_positions();
  const Eigen::VectorXd difference =
      with.nominal().calc_mass_matrix(q).diagonal() - without.nominal().calc_mass_matrix(q).diagonal();
  const double omega = config.control.bandwidth;
  for (int j = 0; j < difference.size(); ++j) {
    const double armature = model.joints[static_cast<std::size_t>(model.movable_joints()[static_cast<std::size_t>(j)])].armature;
    EXPECT_NEAR(difference[j], armature, 1e-9) << "joint " << j + 1;
    // The default gains follow the diagonal: kp differs by armature·ω².
    EXPECT_NEAR(with.gains().kp[j] - without.gains().kp[j], armature * omega * omega, 1e-6) << "joint " << j + 1;
  }
  std::printf("armature share of M_jj at the start posture, joints 1-7:");
  const Eigen::VectorXd full = with.nominal().calc_mass_matrix(q).diagonal();
  for (int j = 0; j < difference.size(); ++j) std::printf(" %.2f", difference[j] / full[j]);
  std::printf("\n");
}

// The gain set's numbers are the paramfile's: checked against the thesis's facts file, which
// was typed from appendix D separately.
TEST(PhysicsChoices, AppendixDGainsAreThePublishedPidLines) {
  std::ifstream file(std::string(ARMFARM_SOURCE_DIR) + "/sweeps/thesis/thesis_results.json");
  const nlohmann::json facts = nlohmann::json::parse(file);
  const nlohmann::json& rows = facts.at("appendix_d").at("pid").at("rows");
  const PdGains gains = make_appendix_d_gains({1, 2, 3, 4, 5, 6, 7});
  ASSERT_EQ(rows.size(), 6u);
  for (std::size_t line = 0; line < rows.size(); ++line) {
    EXPECT_EQ(rows[line][0].get<int>(), static_cast<int>(line));
    EXPECT_EQ(gains.kp[static_cast<Eigen::Index>(line)], rows[line][1].get<double>()) << "joint " << line + 1;
    EXPECT_EQ(rows[line][2].get<double>(), 0.0);  // I = 0: armfarm has no integral term
    EXPECT_EQ(gains.kd[static_cast<Eigen::Index>(line)], rows[line][3].get<double>()) << "joint " << line + 1;
  }
  EXPECT_EQ(gains.kp[6], gains.kp[5]);  // the thesis's arm had six joints: joint 7 takes joint 6's line
  const PdGains subset = make_appendix_d_gains({2, 4});
  EXPECT_EQ(subset.kp, Eigen::Vector2d(70.0, 60.0));
  EXPECT_EQ(subset.kd, Eigen::Vector2d(80.0, 50.0));

  // Through a job: the gain set applies where kp / kd are not given.
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  config.active_joints = {1, 2, 4};
  config.control.gain_set = GainSet::appendix_d;
  config.control.kd = Eigen::VectorXd::Constant(1, 5.0);
  JobSetup setup(model, config);
  EXPECT_EQ(setup.gains().kp, Eigen::Vector3d(60.0, 70.0, 60.0));
  EXPECT_EQ(setup.gains().kd, Eigen::Vector3d::Constant(5.0));
}

// Held damping over a period h is stable only while kd·h/I < 2. The LWR III's wrist has
// kd·h/I ≈ 6.8 under appendix D's gains at h = 10 ms (they diverged within a few ticks when
// armfarm ran them so): the step-stability criterion refuses pd_substeps 1 at validation,
// naming the key and a value that works, and "auto" picks a PD loop fine enough to run them.
TEST(PhysicsChoices, AppendixDGainsAreRefusedAtTenMillisecondsAndRunWithAutoPdSubsteps) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config;
  config.active_joints = {1, 2, 3, 4, 5, 6};
  config.control.mode = ControlMode::feedback;
  config.control.feed_forward = FeedForwardSource::none;
  config.control.gain_set = GainSet::appendix_d;
  config.trajectory.sine.duration = 1.0;
  config.learning.heldout = false;
  {
    JobSetup setup(model, config);
    const Eigen::VectorXd inertia = setup.nominal().calc_mass_matrix(setup.nominal().start_positions()).diagonal();
    const double ratio = setup.gains().kd[4] * config.simulation.dt / inertia[4];
    EXPECT_GT(ratio, 2.0) << "joint 5: kd·h/I at 10 ms";
    std::printf("appendix D, joint 5: kd·h/I = %.2f at h = 10 ms, %.2f at 1 ms; \"auto\" picks pd_substeps %d\n", ratio, ratio / 10.0,
                setup.pd_substeps());
    EXPECT_GE(setup.pd_substeps(), 6);  // kd·h/I below 2 at 1.5 × h needs h ≤ 10 ms / 5.1
  }
  config.simulation.pd_substeps = 1;
  try {
    run_experiment(model, config);
    ADD_FAILURE() << "pd_substeps 1 ran";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    std::printf("%s\n", message.c_str());
    EXPECT_EQ(message.rfind("pd_substeps: 1 is unstable: ", 0), 0u) << message;
    EXPECT_NE(message.find("is stable with the criterion's margin"), std::string::npos) << message;
  }
  config.simulation.pd_substeps.reset();
  const JobOutcome automatic = run_experiment(model, config);
  EXPECT_EQ(automatic.status, JobStatus::done) << automatic.message;
}

}  // namespace
}  // namespace armfarm
