#pragma once
// The one thread that writes a sweep's results: workers push job events (finished, abandoned;
// a job's start is its claim, claim_keeper.hpp) into a queue; the writer takes everything
// queued at once and commits it as one transaction (ResultsStore::insert_job_batch), so batches
// grow when jobs finish faster than a commit takes. A finished job's callback runs on the writer
// thread once its transaction has committed; after the first failed commit nothing more is
// written (the run stops) and the finished jobs whose results were lost are counted.
#include "results/results_store.hpp"

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
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

  /// `on_committed` (may be empty) runs on the writer thread after the commit that holds `result`,
  /// with true when the result was written and false when the store's fence discarded it (its
  /// claim was taken over, ResultsStore::insert_job_batch); never when that commit fails.
  void push_finished(JobResultRecord result, std::function<void(bool written)> on_committed = {});
  void push_abandoned(const std::string& key);

  /// Writes what is queued, stops the thread; rethrows the first store error.
  void finish();
  /// True once a write failed (the runner then stops taking jobs).
  bool failed() const;
  /// Number of transactions committed.
  int batches_written() const;
  /// Finished jobs whose results were not committed because a write failed.
  int finished_not_saved() const;
  /// Finished jobs whose results the fence discarded (their claims were taken over).
  int discarded() const;
  /// The first write error's message ("" while none).
  std::string error_text() const;

 private:
  void write_loop();

  ResultsStore& store_;
  const std::string sweep_name_;
  const std::string claim_owner_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  JobBatch queued_;
  std::vector<std::function<void(bool)>> queued_callbacks_;  ///< one per queued_.finished entry
  bool closing_ = false;
  std::exception_ptr error_;
  int batches_ = 0;
  int not_saved_ = 0;
  int discarded_ = 0;
  std::string error_text_;
  std::thread thread_;
};

}  // namespace armfarm
