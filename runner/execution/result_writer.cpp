#include "runner/execution/result_writer.hpp"

#include <algorithm>

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

void ResultWriter::push_finished(JobResultRecord result, std::function<void(bool)> on_committed) {
  std::lock_guard lock(mutex_);
  queued_.finished.push_back(std::move(result));
  queued_callbacks_.push_back(std::move(on_committed));
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

int ResultWriter::finished_not_saved() const {
  std::lock_guard lock(mutex_);
  return not_saved_;
}

int ResultWriter::discarded() const {
  std::lock_guard lock(mutex_);
  return discarded_;
}

std::string ResultWriter::error_text() const {
  std::lock_guard lock(mutex_);
  return error_text_;
}

void ResultWriter::write_loop() {
  for (;;) {
    JobBatch batch;
    std::vector<std::function<void(bool)>> callbacks;
    bool last = false;
    bool failed = false;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] {
        return closing_ || !queued_.started.empty() || !queued_.finished.empty() || !queued_.abandoned.empty();
      });
      std::swap(batch, queued_);
      std::swap(callbacks, queued_callbacks_);
      last = closing_;
      failed = error_ != nullptr;
    }
    if (failed) {
      // After a failed commit nothing more is written: what arrives is counted as lost.
      std::lock_guard lock(mutex_);
      not_saved_ += static_cast<int>(batch.finished.size());
    } else if (!batch.started.empty() || !batch.finished.empty() || !batch.abandoned.empty()) {
      bool committed = false;
      std::vector<std::string> fenced_out;
      try {
        batch.claim_owner = claim_owner_;
        fenced_out = store_.insert_job_batch(batch, sweep_name_);
        committed = true;
      } catch (const std::exception& e) {
        std::lock_guard lock(mutex_);
        error_ = std::current_exception();
        error_text_ = e.what();
        not_saved_ += static_cast<int>(batch.finished.size());
      } catch (...) {
        std::lock_guard lock(mutex_);
        error_ = std::current_exception();
        error_text_ = "unknown error";
        not_saved_ += static_cast<int>(batch.finished.size());
      }
      if (committed) {
        {
          std::lock_guard lock(mutex_);
          ++batches_;
          discarded_ += static_cast<int>(fenced_out.size());
        }
        std::sort(fenced_out.begin(), fenced_out.end());
        for (std::size_t i = 0; i < callbacks.size(); ++i) {
          const bool written = !std::binary_search(fenced_out.begin(), fenced_out.end(), batch.finished[i].key);
          if (callbacks[i]) callbacks[i](written);
        }
      }
    }
    if (last) {
      std::lock_guard lock(mutex_);
      if (queued_.started.empty() && queued_.finished.empty() && queued_.abandoned.empty()) return;
    }
  }
}

}  // namespace armfarm
