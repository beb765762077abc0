#pragma once
// Recording the job's outcome: the evaluation pass's metrics and TRIAL rows, the learner's
// figures, batch training's same-run split, and the run's cost.
#include "engine/experiment/batch_training.hpp"
#include "engine/experiment/control_pass.hpp"
#include "engine/experiment/experiment_metrics.hpp"
#include "engine/experiment/feed_forward_source.hpp"
#include "engine/experiment/pass_statistics.hpp"
#include "engine/experiment/series_recorder.hpp"
#include "engine/learner/learner.hpp"

namespace armfarm {

/// The evaluation pass's metrics (un-prefixed names: the pass on the training trajectory) and
/// one TRIAL row per segment.
void write_evaluation_report(MetricWriter& writer, const PassStatistics& statistics, const ErrorFloors& floors,
                             SeriesRecorder& recorder);

/// same_run_test_nmse/_rmse (per joint and job) and n_training_samples.
void write_batch_training_report(MetricWriter& writer, const BatchTrainingResult& training, const ErrorFloors& floors);

/// n_receptive_fields, learner_us_per_update (without the one-off fit), learner_us_per_predict,
/// learner_memory_bytes, learner_fit_seconds.
void write_learner_report(MetricWriter& writer, const Learner& learner, const LearnerClock& clock);

/// The learner's size over its outputs (n_receptive_fields_per_output): for LWPR the receptive
/// fields of one output's model, the count the thesis prints (sweeps/thesis/README.md, "Fields").
double calc_fields_per_output(const Learner& learner);

/// tick_us_total and the tick_us_* stage times per tick (nothing when no tick was timed).
void write_tick_report(MetricWriter& writer, const TickClock& clock);

/// simulated_seconds and sim_seconds_per_wall_second.
void write_cost_report(MetricWriter& writer, double simulated_seconds, double wall_seconds);

}  // namespace armfarm
