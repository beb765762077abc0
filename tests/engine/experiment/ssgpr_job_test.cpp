// A job with learning.learner = "ssgpr": every phase (batch training, the same-run and held-out
// scores, the learner's feed-forward, online learning) drives SSGPR through the Learner
// interface. Compared against feedback alone on the same plant, so it cannot pass by construction.
#include "engine/experiment/metric_catalog.hpp"
#include "engine/experiment/run_experiment.hpp"
#include "../physics/test_arms.hpp"
#include "job_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

namespace armfarm {
namespace {

using testing::job_metrics;

// Joints 2 and 4 (6 inputs, 2 outputs) on a 6 s sine at low gains.
JobConfig make_ssgpr_config(LearningMode mode) {
  JobConfig config;
  config.active_joints = {2, 4};
  config.trajectory.kind = TrajectoryKind::sine;
  config.trajectory.sine.duration = 6.0;
  config.control.gain_scale = 0.2;
  config.learning.mode = mode;
  config.learning.learner = LearnerKind::ssgpr;
  config.learning.ssgpr.params.features = 60;
  config.learning.ssgpr.fit_samples = 120;
  config.learning.ssgpr.fit.iterations = 40;
  return config;
}

TEST(SsgprJob, BatchLearnedFeedForwardBeatsLowGainFeedback) {
  const ArmModel model = testing::load_lwr3();
  JobConfig feedback = make_ssgpr_config(LearningMode::none);
  feedback.control.mode = ControlMode::feedback;
  feedback.control.feed_forward = FeedForwardSource::none;
  const JobConfig learned = make_ssgpr_config(LearningMode::batch);
  const JobOutcome f_outcome = run_experiment(model, feedback), l_outcome = run_experiment(model, learned);
  ASSERT_EQ(f_outcome.status, JobStatus::done) << f_outcome.message;
  ASSERT_EQ(l_outcome.status, JobStatus::done) << l_outcome.message;
  auto f = job_metrics(f_outcome), l = job_metrics(l_outcome);
  EXPECT_LT(5.0 * l["tracking_nmse"], f["tracking_nmse"]);
  for (int joint : {2, 4}) EXPECT_GE(l["ff_fb_ratio_avg_j" + std::to_string(joint)], 0.8) << "joint " << joint;
  EXPECT_LT(l["same_run_test_nmse"], 0.1);
  EXPECT_LT(l["heldout_test_nmse"], 1.0);
  EXPECT_EQ(l["n_receptive_fields"], 60.0);  // D
  // The numbers the model stores, counted independently: Ω (D×6), L (F×F), B and W (F×2), the
  // update scratch φ, rotated, gain (F each), y_scaled and error (2 each) and the output scale (2), F = 2D.
  const double F = 120.0;
  EXPECT_EQ(l["learner_memory_bytes"], 8.0 * (60 * 6 + F * F + 2 * F * 2 + 3 * F + 3 * 2));
  EXPECT_GT(l["learner_fit_seconds"], 0.0);
  EXPECT_GT(l["learner_us_per_update"], 0.0);
  std::printf("batch SSGPR D = 60, gain 0.2: tracking nMSE %.5f (feedback %.4f), ff/fb j2 %.2f j4 %.2f, same-run nMSE %.4f, "
              "held-out nMSE %.4f, fit %.2f s, %.1f us/update, %.1f us/predict\n",
              l["tracking_nmse"], f["tracking_nmse"], l["ff_fb_ratio_avg_j2"], l["ff_fb_ratio_avg_j4"], l["same_run_test_nmse"],
              l["heldout_test_nmse"], l["learner_fit_seconds"], l["learner_us_per_update"], l["learner_us_per_predict"]);
}

TEST(SsgprJob, OnlineSsgprIsDeterministicAndUntrustedUntilFitted) {
  const ArmModel model = testing::load_lwr3();
  JobConfig config = make_ssgpr_config(LearningMode::online);
  const JobOutcome first = run_experiment(model, config), second = run_experiment(model, config);
  ASSERT_EQ(first.status, JobStatus::done) << first.message;
  ASSERT_EQ(first.metrics.size(), second.metrics.size());
  for (std::size_t i = 0; i < first.metrics.size(); ++i) {
    if (find_metric_info(first.metrics[i].name).kind != MetricKind::result) continue;
    EXPECT_EQ(first.metrics[i].name, second.metrics[i].name);
    EXPECT_EQ(first.metrics[i].value, second.metrics[i].value) << first.metrics[i].name;
  }
  auto m = job_metrics(first);
  // 600 ticks, the first 120 kept for the fit: feed-forward untrusted (0) on at least those.
  for (int joint : {2, 4}) {
    const double untrusted = m["ff_untrusted_fraction_j" + std::to_string(joint)];
    EXPECT_GE(untrusted, 120.0 / 600.0 - 1e-12) << joint;
    EXPECT_LT(untrusted, 0.5) << joint;
  }
  // A seed of the frequency draw alone changes the learnt model, hence the scores.
  config.learning.ssgpr.params.seed = 2;
  auto other = job_metrics(run_experiment(model, config));
  EXPECT_NE(other["heldout_test_nmse"], m["heldout_test_nmse"]);
  EXPECT_NE(other["tracking_nmse"], m["tracking_nmse"]);
}

}  // namespace
}  // namespace armfarm
