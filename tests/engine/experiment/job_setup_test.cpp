// Where a job's default gains are placed (JobSetup::fit_to_trajectories, engine/control/pd_gains.hpp):
// on the arm corpus's Kinova Gen3, which starts straight up where its vertical-axis joints carry
// a fraction of the inertia they carry along the default sine (M_11 0.008 kg·m² at the start,
// 0.23 along it) and where gravity's stiffness on its wrist exceeds kp at gain_scale 0.2, and
// on the LWR III, whose gains must stay those of its start posture bit for bit.
#include "engine/experiment/heldout_evaluation.hpp"
#include "engine/experiment/job_setup.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "engine/model/model_loading.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <string>

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
