// The metric catalog (engine/experiment/metric_catalog.cpp), assembled from its groups: each
// name once, each entry complete, and the held-out control-pass entries mirroring the
// evaluation pass's under the heldout_ prefix.
#include "engine/experiment/metric_catalog.hpp"

#include <gtest/gtest.h>

#include <map>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>

namespace armfarm {
namespace {

TEST(MetricCatalog, EveryNameOnceWithAUnitAndAMeaning) {
  std::set<std::string> names;
  for (const MetricInfo& info : metric_catalog()) {
    EXPECT_TRUE(names.insert(info.name).second) << info.name << " is listed twice";
    EXPECT_FALSE(info.unit.empty()) << info.name;
    EXPECT_FALSE(info.meaning.empty()) << info.name;
    EXPECT_EQ(&find_metric_info(info.name), &info) << info.name;
  }
  EXPECT_THROW(find_metric_info("no_such_metric"), std::out_of_range);
}

TEST(MetricCatalog, GroupsKeepTheirPlaceInTheStoredOrder) {
  // metric_info is written in catalog order: the first and last of each group, in order.
  std::map<std::string, std::size_t> position;
  for (std::size_t i = 0; i < metric_catalog().size(); ++i) position[metric_catalog()[i].name] = i;
  namespace n = metric_names;
  const std::string order[] = {n::tracking_nmse,      n::task_rmse,           n::window_tracking_nmse_x, n::window_tracking_rmse_z,
                               n::ff_fb_ratio_avg,    n::torque_saturation_fraction, n::same_run_test_nmse,
                               n::n_training_samples, n::id_nmse,             n::ff_untrusted_fraction, n::n_receptive_fields,
                               n::learner_fit_seconds, n::n_segments,         n::tracking_rmse_last_segment,
                               n::simulated_seconds,  n::sim_seconds_per_wall_second, n::tick_us_total, n::tick_us_learning,
                               n::work_checksum,      n::heldout_test_nmse,   n::heldout_diverged};
  EXPECT_EQ(position.at(order[0]), 0u);
  for (std::size_t i = 1; i < std::size(order); ++i) {
    EXPECT_LT(position.at(order[i - 1]), position.at(order[i])) << order[i - 1] << " before " << order[i];
  }
}

TEST(MetricCatalog, HeldoutControlEntriesMirrorTheEvaluationPass) {
  for (const std::string& name : heldout_control_metric_names()) {
    const MetricInfo& evaluation = find_metric_info(name);
    const MetricInfo& heldout = find_metric_info(metric_names::heldout_prefix + name);
    EXPECT_EQ(heldout.unit, evaluation.unit) << name;
    EXPECT_EQ(heldout.direction, evaluation.direction) << name;
    EXPECT_EQ(heldout.kind, evaluation.kind) << name;
    EXPECT_EQ(heldout.scope, MetricScope::checkpoint) << name;
    EXPECT_EQ(heldout.meaning, "held-out control pass, frozen learner: " + evaluation.meaning) << name;
  }
  // Every held-out entry is per checkpoint, and only those are.
  for (const MetricInfo& info : metric_catalog()) {
    EXPECT_EQ(info.scope == MetricScope::checkpoint, info.name.rfind(metric_names::heldout_prefix, 0) == 0) << info.name;
  }
}

}  // namespace
}  // namespace armfarm
