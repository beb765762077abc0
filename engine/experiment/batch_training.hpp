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
};

/// Trains `learner` as above. `after_epoch(e)` runs after epoch e (1-based) and after the split
/// with e = 0 (before any training); a result that is not ok stops training and is returned.
PassResult train_in_batch(Learner& learner, const std::vector<Sample>& samples, const LearningConfig& config,
                          std::uint64_t seed, LearnerClock* clock, const std::function<PassResult(int epoch)>& after_epoch,
                          BatchTrainingResult& result);

}  // namespace armfarm
