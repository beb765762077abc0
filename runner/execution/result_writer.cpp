#include "runner/execution/result_writer.hpp"

namespace armfarm {

ResultWriter::ResultWriter(ResultsStore& store, std::string sweep_name, std::string claim_owner)
    : store_(store),
      sweep_name_(std::move(sweep_name)),
      claim_owner_(std::move(claim_owner)),
      thread_([this] { write_loop(); }) {}

ResultWriter::~ResultWriter() {
  try {
    finish();
  } catch (...) {
    // Already reported by finish() to whoever called it; a destructor must not throw.
  }
}

void ResultWriter::push_finished(JobResultRecord result) {
  std::lock_guard lock(mutex_);
  queued_.finished.push_back(std::move(result));
  wake_.notify_one();
}

void ResultWriter::push_abandoned(const std::string& key) {
  std::lock_guard lock(mutex_);
  queued_.abandoned.push_back(key);
  wake_.notify_one();
}

void ResultWriter::finish() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
    wake_.notify_one();
  }
  if (thread_.joinable()) thread_.join();
  std::lock_guard lock(mutex_);
  if (error_) {
    std::exception_ptr error = error_;
    error_ = nullptr;
    std::rethrow_exception(error);
  }
}

bool ResultWriter::failed() const {
  std::lock_guard lock(mutex_);
  return error_ != nullptr;
}

int ResultWriter::batches_written() const {
  std::lock_guard lock(mutex_);
  return batches_;
}

void ResultWriter::write_loop() {
  for (;;) {
    JobBatch batch;
    bool last = false;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] {
        return closing_ || !queued_.started.empty() || !queued_.finished.empty() || !queued_.abandoned.empty();
      });
      std::swap(batch, queued_);
      last = closing_;
    }
    if (!batch.started.empty() || !batch.finished.empty() || !batch.abandoned.empty()) {
      try {
        batch.claim_owner = claim_owner_;
        store_.insert_job_batch(batch, sweep_name_);
        std::lock_guard lock(mutex_);
        ++batches_;
      } catch (...) {
        std::lock_guard lock(mutex_);
        if (!error_) error_ = std::current_exception();
      }
    }
    if (last) {
      std::lock_guard lock(mutex_);
      if (queued_.started.empty() && queued_.finished.empty() && queued_.abandoned.empty()) return;
    }
  }
}

}  // namespace armfarm
