#pragma once
// The one thread that writes a sweep's results: workers push job events (finished, abandoned;
// a job's start is its claim, claim_keeper.hpp) into a queue; the writer takes everything
// queued at once and commits it as one transaction (ResultsStore::insert_job_batch), so batches
// grow when jobs finish faster than a commit takes.
#include "results/results_store.hpp"

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>

namespace armfarm {

class ResultWriter {
 public:
  /// Starts the thread. `store` must outlive the writer and must not be used by anyone else
  /// until finish() returns.
  /// `claim_owner`: the owner whose job claims finished and abandoned jobs release (JobBatch).
  ResultWriter(ResultsStore& store, std::string sweep_name, std::string claim_owner = {});
  ~ResultWriter();
  ResultWriter(const ResultWriter&) = delete;
  ResultWriter& operator=(const ResultWriter&) = delete;

  void push_finished(JobResultRecord result);
  void push_abandoned(const std::string& key);

  /// Writes what is queued, stops the thread; rethrows the first store error.
  void finish();
  /// True once a write failed (the runner then stops taking jobs).
  bool failed() const;
  /// Number of transactions committed.
  int batches_written() const;

 private:
  void write_loop();

  ResultsStore& store_;
  const std::string sweep_name_;
  const std::string claim_owner_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  JobBatch queued_;
  bool closing_ = false;
  std::exception_ptr error_;
  int batches_ = 0;
  std::thread thread_;
};

}  // namespace armfarm
