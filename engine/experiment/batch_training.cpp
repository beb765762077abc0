#include "engine/experiment/batch_training.hpp"

#include "engine/experiment/signal_statistics.hpp"
#include "engine/experiment/tick_timer.hpp"
#include "engine/random/random_stream.hpp"

#include <cmath>
#include <numeric>
#include <string>

namespace armfarm {
namespace {

/// The result of a stop during training: `where` says how far it got.
PassResult make_stopped(BatchTrainingResult& result, const std::string& where) {
  result.stopped = true;
  return PassResult{JobStatus::timeout, 0.0, "stopped during batch training (" + where + ")"};
}

}  // namespace

PassResult train_in_batch(Learner& learner, const std::vector<Sample>& samples, const LearningConfig& config,
                          std::uint64_t seed, LearnerClock* clock, const std::function<PassResult(int epoch)>& after_epoch,
                          const std::function<bool()>& should_stop, BatchTrainingResult& result) {
  const auto stop_requested = [&should_stop] { return should_stop && should_stop(); };
  RandomStream generator(seed, "learning.batch.shuffle");
  std::vector<std::size_t> order(samples.size());
  std::iota(order.begin(), order.end(), 0);
  generator.shuffle(order.begin(), order.end());
  const auto n_train = static_cast<std::size_t>(std::llround(config.train_fraction * static_cast<double>(samples.size())));
  std::vector<std::size_t> train(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(n_train));
  const std::vector<std::size_t> test(order.begin() + static_cast<std::ptrdiff_t>(n_train), order.end());
  result.training_samples = static_cast<long>(n_train);
  if (after_epoch) {
    PassResult checkpoint = after_epoch(0);
    if (!checkpoint.ok()) return checkpoint;
  }
  for (int epoch = 1; epoch <= config.epochs; ++epoch) {
    if (epoch > 1) generator.shuffle(train.begin(), train.end());
    for (std::size_t i = 0; i < train.size(); ++i) {
      if (stop_requested()) {
        return make_stopped(result, "epoch " + std::to_string(epoch) + " of " + std::to_string(config.epochs) + ", " +
                                        std::to_string(i) + " of " + std::to_string(train.size()) + " training samples learnt");
      }
      const std::size_t index = train[i];
      {
        ScopedSeconds timed(clock ? &clock->update_seconds : nullptr);
        learner.update(samples[index].x, samples[index].y);
      }
      if (clock) ++clock->updates;
    }
    if (after_epoch) {
      PassResult checkpoint = after_epoch(epoch);
      if (!checkpoint.ok()) return checkpoint;
    }
  }
  if (test.empty()) return PassResult{};
  const int n_out = learner.output_dim();
  NmseAccumulator accuracy(n_out);
  const std::unique_ptr<PredictionWorkspace> workspace = learner.make_workspace();
  Prediction prediction;  // kept across samples: values only (the score reads no bounds), no allocation per call
  for (std::size_t i = 0; i < test.size(); ++i) {
    if (stop_requested()) {
      return make_stopped(result, "scoring, " + std::to_string(i) + " of " + std::to_string(test.size()) + " test samples predicted");
    }
    const std::size_t index = test[i];
    {
      ScopedSeconds timed(clock ? &clock->predict_seconds : nullptr);
      learner.predict_values_into(samples[index].x, *workspace, prediction);
    }
    if (clock) ++clock->predictions;
    accuracy.add(samples[index].y, calc_trusted_part(prediction));
  }
  result.same_run_test = accuracy;
  result.test_indices = test;
  return PassResult{};
}

}  // namespace armfarm
