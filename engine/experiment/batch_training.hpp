#pragma once
// Batch training: the collected samples are split at random (learning.train_fraction; stream
// "learning.batch.shuffle"), the learner learns the training share for learning.epochs epochs
// (reshuffled each epoch), and is scored on the withheld share. That score is
// same_run_test_nmse: its test samples are 10 ms samples of the *same* runs as the training
// samples (the thesis's 75/25 split), not held-out data — see heldout_evaluation.hpp for that.
#include "engine/experiment/control_pass.hpp"
#include "engine/experiment/feed_forward_source.hpp"
#include "engine/experiment/signal_statistics.hpp"
#include "engine/learner/learner.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace armfarm {

struct BatchTrainingResult {
  NmseAccumulator same_run_test;  ///< prediction against torque on the withheld samples (count 0: none)
  long training_samples = 0;
  std::vector<std::size_t> test_indices;  ///< the withheld samples: indices into the collected samples, as scored
  bool stopped = false;  ///< should_stop fired during an epoch or the scoring (the result is then timeout)
};

/// Trains `learner` as above. `after_epoch(e)` runs after epoch e (1-based) and after the split
/// with e = 0 (before any training); a result that is not ok stops training and is returned.
/// `should_stop` (may be empty) is polled before every update and every scoring prediction, as a
/// control pass polls it every tick: when it returns true, training ends at once with status
/// timeout, result.stopped set and end_time 0 (training advances no plant time); the learner is
/// then part-trained and the result unscored. Training is a pure function of the samples, the
/// configuration and the seed, so a job run again from its configuration trains to the same model.
PassResult train_in_batch(Learner& learner, const std::vector<Sample>& samples, const LearningConfig& config,
                          std::uint64_t seed, LearnerClock* clock, const std::function<PassResult(int epoch)>& after_epoch,
                          const std::function<bool()>& should_stop, BatchTrainingResult& result);

}  // namespace armfarm
