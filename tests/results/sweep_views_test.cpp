// The per-sweep view answers "nMSE of joint 2 by init_D" in plain SQL.
#include "support/results_store_fixture.hpp"
#include "support/sqlite_rows.hpp"

#include <gtest/gtest.h>

#include <string>

namespace armfarm {
namespace {

using test_support::make_jobs;
using test_support::make_result;
using test_support::make_sweep;
using test_support::ResultsStoreTest;

TEST_F(ResultsStoreTest, SweepViewAnswersNmseOfJointTwoByInitD) {
  ResultsStore store = ResultsStore::open(path("r.db"), ResultsStore::Mode::read_write);
  const RegisteredRun run = store.insert_sweep_run(make_sweep("my-sweep"), make_jobs(3));
  store.insert_job_batch({{}, {make_result("key0", 1.0), make_result("key1", 2.0), make_result("key2", 4.0)}, {}},
                         "my-sweep");
  store.update_run_finished(run.run_id, "complete", 3, 0, make_utc_timestamp());
  const std::string view = make_sweep_view_name("my-sweep");
  EXPECT_EQ(view.substr(0, 15), "sweep_my_sweep_");  // '-' was replaced: a hash keeps it unique
  EXPECT_EQ(view.size(), 21u);
  const auto rows = test_support::query_rows_read_only(
      path("r.db"), "SELECT \"learning.lwpr.init_D\", tracking_nmse_j2 FROM " + view + " ORDER BY 1");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], "10.0|0.2");
  EXPECT_EQ(rows[2], "30.0|0.8");
  const auto long_form = test_support::query_rows_read_only(
      path("r.db"),
      "SELECT json_extract(params, '$.\"learning.lwpr.init_D\"'), value FROM job_metrics "
      "WHERE sweep = 'my-sweep' AND name = 'tracking_nmse' AND joint = 2 ORDER BY 1");
  EXPECT_EQ(long_form, rows);
}

}  // namespace
}  // namespace armfarm
