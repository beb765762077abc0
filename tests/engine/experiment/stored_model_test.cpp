// Learned models as results (issue 12): a job returns its learner's model file, and a second job
// started from that file predicts exactly what the first predicted at its end.
#include "engine/experiment/run_experiment.hpp"
#include "engine/learning/learner_model_file.hpp"
#include "engine/experiment/job_config_validation.hpp"
#include "../physics/test_arms.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

namespace armfarm {
namespace {

std::map<std::string, double> checkpoint_metrics(const JobOutcome& outcome, std::int64_t checkpoint) {
  std::map<std::string, double> metrics;
  for (const Metric& metric : outcome.metrics) {
    if (!metric.checkpoint || metric.checkpoint->number != checkpoint || !metric.value) continue;
    metrics[metric.joint ? metric.name + "_j" + std::to_string(*metric.joint) : metric.name] = *metric.value;
  }
  return metrics;
}

// Two joints learnt online over two periods of the default sine: a few seconds of simulation.
JobConfig make_online_config() {
  JobConfig config;
  config.active_joints = {2, 4};
  config.trajectory.kind = TrajectoryKind::sine;
  config.trajectory.sine.duration = 8.0;
  config.control.gain_scale = 0.2;
  config.learning.mode = LearningMode::online;
  config.learning.store_model = true;
  return config;
}

TEST(StoredModel, AFrozenSecondJobPredictsExactlyWhatTheFirstPredictedAtItsEnd) {
  const ArmModel arm = testing::load_lwr3();
  const JobConfig first_config = make_online_config();
  const JobOutcome first = run_experiment(arm, first_config);
  ASSERT_EQ(first.status, JobStatus::done) << first.message;
  ASSERT_FALSE(first.model_file.empty());
  const auto learnt = decode_learner_model(first.model_file);
  ASSERT_GT(learnt->size(), 0u);
  ASSERT_GT(learnt->n_updates(), 0u);

  JobConfig second_config = first_config;
  second_config.learning.mode = LearningMode::frozen;
  second_config.learning.initial_model = "first job";
  second_config.learning.initial_model_bytes = first.model_file;
  const JobOutcome second = run_experiment(arm, second_config);
  ASSERT_EQ(second.status, JobStatus::done) << second.message;
  // Frozen: the model the second job ends with is, byte for byte, the one it started from.
  EXPECT_EQ(second.model_file, first.model_file);

  // The held-out set is the same realisation in both jobs (same trajectory and seed). The first
  // job scored it with its learner in memory at the end of learning (checkpoint = all periods),
  // the second with the learner decoded from the file before its pass (checkpoint 0): every
  // held-out figure must agree exactly.
  std::int64_t last = 0;
  for (const Metric& m : first.metrics) {
    if (m.checkpoint) last = std::max(last, m.checkpoint->number);
  }
  const auto a = checkpoint_metrics(first, last), b = checkpoint_metrics(second, 0);
  ASSERT_GT(a.count("heldout_test_nmse"), 0u);
  ASSERT_GT(a.count("heldout_tracking_nmse"), 0u);
  for (const char* name : {"heldout_test_nmse", "heldout_tracking_nmse", "heldout_ff_fb_ratio_avg_j2", "heldout_ff_fb_ratio_avg_j4",
                           "heldout_learner_updates", "heldout_n_receptive_fields"}) {
    ASSERT_GT(a.count(name), 0u) << name;
    ASSERT_GT(b.count(name), 0u) << name;
    EXPECT_EQ(a.at(name), b.at(name)) << name;
  }
  EXPECT_EQ(b.at("heldout_learner_updates"), static_cast<double>(learnt->n_updates()));
  std::printf("stored model: %zu fields, %llu updates, %zu bytes; held-out test nMSE %.4g in both jobs\n", learnt->size(),
              static_cast<unsigned long long>(learnt->n_updates()), first.model_file.size(), a.at("heldout_test_nmse"));
}

TEST(StoredModel, AnOnlineJobContinuesLearningFromTheStoredModel) {
  const ArmModel arm = testing::load_lwr3();
  JobConfig config = make_online_config();
  config.learning.heldout = false;
  config.trajectory.sine.duration = 4.0;
  const JobOutcome first = run_experiment(arm, config);
  ASSERT_EQ(first.status, JobStatus::done) << first.message;
  JobConfig again = config;
  again.learning.initial_model = "first job";
  again.learning.initial_model_bytes = first.model_file;
  const JobOutcome second = run_experiment(arm, again);
  ASSERT_EQ(second.status, JobStatus::done) << second.message;
  const auto a = decode_learner_model(first.model_file), b = decode_learner_model(second.model_file);
  // The second job's learner started with the first one's samples: it learnt the same pass again.
  EXPECT_EQ(b->n_updates(), 2 * a->n_updates());
}

// An SSGPR job that fits its hyperparameters on its first samples stores the fitted model (on main
// it failed after its whole simulation: the model-file dispatch had no case for that learner).
TEST(StoredModel, AnSsgprJobThatFitsItsHyperparametersStoresTheFittedModel) {
  const ArmModel arm = testing::load_lwr3();
  JobConfig config = make_online_config();
  config.learning.heldout = false;
  config.trajectory.sine.duration = 2.0;
  config.control.gain_scale = 1.0;  // full-gain feedback while the learner waits for its fit batch
  config.learning.learner = LearnerKind::ssgpr;
  config.learning.ssgpr.params.features = 20;
  config.learning.ssgpr.fit_samples = 40;
  config.learning.ssgpr.fit.iterations = 5;
  ASSERT_TRUE(validate(config, ModelFacts{7}).empty());
  const JobOutcome outcome = run_experiment(arm, config);
  ASSERT_EQ(outcome.status, JobStatus::done) << outcome.message;
  ASSERT_EQ(find_learner_model_kind(outcome.model_file), "ssgpr");
  const auto learnt = decode_learner_model(outcome.model_file);
  EXPECT_EQ(learnt->size(), 20u);
  EXPECT_GT(learnt->n_updates(), 40u);  // the fit batch and every sample after it
  EXPECT_EQ(learnt->input_dim(), 6);
}

TEST(StoredModel, ValidationRefusesAModelOfTheWrongSizeAndAFrozenJobWithoutOne) {
  const ArmModel arm = testing::load_lwr3();
  JobConfig config = make_online_config();
  config.learning.heldout = false;
  config.trajectory.sine.duration = 2.0;
  const JobOutcome two_joints = run_experiment(arm, config);
  ASSERT_EQ(two_joints.status, JobStatus::done) << two_joints.message;

  JobConfig three = config;
  three.active_joints = {1, 2, 4};
  three.learning.initial_model = "two.lwpr";
  three.learning.initial_model_bytes = two_joints.model_file;
  std::vector<ConfigProblem> problems = validate(three, ModelFacts{7});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "learning.initial_model");
  EXPECT_NE(problems[0].message.find("maps 6 inputs to 2 outputs"), std::string::npos) << problems[0].message;

  JobConfig corrupt = config;
  corrupt.learning.initial_model = "bad.lwpr";
  corrupt.learning.initial_model_bytes = two_joints.model_file;
  corrupt.learning.initial_model_bytes[corrupt.learning.initial_model_bytes.size() / 2] ^= 0x5a;
  problems = validate(corrupt, ModelFacts{7});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].message.find("checksum"), std::string::npos) << problems[0].message;

  JobConfig frozen = config;
  frozen.learning.mode = LearningMode::frozen;
  problems = validate(frozen, ModelFacts{7});
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_EQ(problems[0].path, "learning.mode");
}

}  // namespace
}  // namespace armfarm
