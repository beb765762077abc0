#pragma once
// The results store's tests (tests/results/results_store_test.cpp, store_writes_test.cpp,
// store_reads_test.cpp, sweep_views_test.cpp, store_merge_test.cpp): one fixture, a scratch folder
// per test, shared by the files so that the suite ResultsStoreTest has one fixture class; a sweep,
// n jobs (init_D = 10, 20, ...) and a finished job's result scaled by `scale`.
#include "results/results_store.hpp"
#include "support/scratch_file.hpp"

#include <string>
#include <vector>

namespace armfarm::test_support {

class ResultsStoreTest : public ScratchFolderTest {
 protected:
  ResultsStoreTest() : ScratchFolderTest("store") {}
};

inline SweepRegistration make_sweep(const std::string& name, const std::string& hash = "h1") {
  SweepRegistration sweep;
  sweep.name = name;
  sweep.description = "a test sweep";
  sweep.spec_text = "{\"name\": \"" + name + "\"}";
  sweep.spec_hash = hash;
  sweep.started_at = make_utc_timestamp();
  sweep.provenance.armfarm_version = "0.1.0";
  sweep.provenance.host = "testhost";
  return sweep;
}

inline std::vector<JobRegistration> make_jobs(int n) {
  std::vector<JobRegistration> jobs;
  for (int i = 0; i < n; ++i) {
    const double init_D = 10.0 * (i + 1);
    jobs.push_back({"key" + std::to_string(i), {{"learning.lwpr.init_D", init_D}},
                    {{"learning", {{"lwpr", {{"init_D", init_D}}}}}, {"seed", i}}, i});
  }
  return jobs;
}

inline JobResultRecord make_result(const std::string& key, double scale) {
  JobResultRecord result;
  result.key = key;
  result.status = "done";
  result.end_time = 20.0;
  result.wall_seconds = 1.5;
  result.started_at = result.finished_at = make_utc_timestamp();
  result.metrics = {{0, "tracking_nmse", 1, 0.1 * scale, ""}, {0, "tracking_nmse", 2, 0.2 * scale, ""}, {0, "test_nmse", {}, 0.3 * scale, ""}};
  Eigen::MatrixXd rows(3, 2);
  rows << 0.0, scale, 0.1, 2 * scale, 0.2, 3 * scale;
  result.series = {{0, "POS", {"t", "q1"}, rows}};
  return result;
}

}  // namespace armfarm::test_support
