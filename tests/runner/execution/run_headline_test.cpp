// The run's headline: the first result metric of the catalog that most jobs define, with its
// direction, its best and worst job; timing metrics and metrics without a direction never lead.
#include "runner/execution/run_headline.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <vector>

namespace armfarm {
namespace {

TEST(RunHeadline, TheFirstCatalogResultMetricMostJobsDefineWithItsDirection) {
  // tracking_nmse (lower) comes before ff_fb_ratio_avg (higher) in the catalog and wins when as common.
  std::vector<HeadlineJob> jobs = {{"a", {{"tracking_nmse", 0.3}, {"ff_fb_ratio_avg", 0.9}}},
                                   {"b", {{"tracking_nmse", 0.1}, {"ff_fb_ratio_avg", 0.5}}},
                                   {"c", {{"tracking_nmse", 0.2}, {"ff_fb_ratio_avg", 0.7}}}};
  std::optional<RunHeadline> headline = choose_run_headline(jobs);
  ASSERT_TRUE(headline);
  EXPECT_EQ(headline->metric, "tracking_nmse");
  EXPECT_EQ(headline->direction, "lower");
  EXPECT_EQ(headline->jobs, 3);
  EXPECT_EQ(headline->best_label, "b");
  EXPECT_EQ(headline->worst_label, "a");
  // Undefined (NaN) tracking_nmse in two jobs: ff_fb_ratio_avg, higher is better.
  jobs[0].metrics["tracking_nmse"] = std::nan("");
  jobs[1].metrics.erase("tracking_nmse");
  headline = choose_run_headline(jobs);
  ASSERT_TRUE(headline);
  EXPECT_EQ(headline->metric, "ff_fb_ratio_avg");
  EXPECT_EQ(headline->best_label, "a");
  EXPECT_DOUBLE_EQ(headline->best, 0.9);
  EXPECT_EQ(headline->worst_label, "b");
  EXPECT_NE(make_headline_text(*headline).find("higher is better, 3 jobs): best 0.9 a; worst 0.5 b"), std::string::npos)
      << make_headline_text(*headline);
  // Timing metrics and metrics without a direction never lead.
  EXPECT_FALSE(choose_run_headline({{"a", {{"learner_us_per_update", 3.0}, {"ff_abs_avg", 1.0}}}}));
  EXPECT_FALSE(choose_run_headline({}));
}

}  // namespace
}  // namespace armfarm
