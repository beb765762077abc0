// Merging results files: new jobs are copied, identical ones accepted, conflicts reported.
#include "support/results_store_fixture.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace armfarm {
namespace {

using test_support::make_jobs;
using test_support::make_result;
using test_support::make_sweep;
using test_support::ResultsStoreTest;

TEST_F(ResultsStoreTest, MergeCopiesNewJobsAcceptsIdenticalOnesAndReportsConflicts) {
  {
    ResultsStore a = ResultsStore::open(path("a.db"), ResultsStore::Mode::read_write);
    a.insert_sweep_run(make_sweep("s"), make_jobs(2));
    a.insert_job_batch({{}, {make_result("key0", 1.0)}, {}}, "s");
    ResultsStore b = ResultsStore::open(path("b.db"), ResultsStore::Mode::read_write);
    std::vector<JobRegistration> jobs = make_jobs(3);
    b.insert_sweep_run(make_sweep("s"), jobs);
    b.insert_job_batch({{}, {make_result("key0", 1.0), make_result("key1", 3.0), make_result("key2", 5.0)}, {}}, "s");
    ResultsStore c = ResultsStore::open(path("c.db"), ResultsStore::Mode::read_write);
    c.insert_sweep_run(make_sweep("s"), make_jobs(1));
    c.insert_job_batch({{}, {make_result("key0", 7.0)}, {}}, "s");
  }
  ResultsStore out = ResultsStore::open(path("out.db"), ResultsStore::Mode::read_write);
  const MergeReport first = out.merge_from(path("a.db"));
  EXPECT_EQ(first.jobs_added, 2);
  const MergeReport second = out.merge_from(path("b.db"));
  EXPECT_EQ(second.jobs_identical, 1);  // key0 identical
  EXPECT_EQ(second.jobs_replaced, 1);   // key1 pending in a, done in b
  EXPECT_EQ(second.jobs_added, 1);      // key2
  EXPECT_TRUE(second.conflicts.empty());
  const MergeReport third = out.merge_from(path("c.db"));
  ASSERT_EQ(third.conflicts.size(), 1u);
  EXPECT_NE(third.conflicts[0].find("key0"), std::string::npos);
  EXPECT_EQ(out.find_jobs("s").size(), 3u);
  EXPECT_EQ(out.count_jobs_by_status("s").at("done"), 3);
  EXPECT_DOUBLE_EQ(out.find_metrics(out.find_job("key1")->id)[0].value.value(), 0.9);
  EXPECT_EQ(out.find_series(out.find_job("key2")->id, "POS")->rows(0, 1), 5.0);
}

}  // namespace
}  // namespace armfarm
