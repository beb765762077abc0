#pragma once
// A whole sweep's recorded series as one long-form ("tidy") table for pandas, R or Matlab:
// one row per sample and value, columns
//   job, <each swept parameter>, time, joint, signal, value
// `time` is the row's "t" column (s; empty for a series without one), `joint` the 1-based
// joint of a per-joint column ("j3" → 3; empty otherwise), `signal` the series name for a
// per-joint column ("PHI") and "SERIES.column" for any other ("POS.x", "TRIAL.fb_abs_avg").
// Only jobs that are done are written, in the sweep's expansion order.
#include "results/results_store.hpp"

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace armfarm {

struct SweepExportCounts {
  int jobs = 0;          ///< done jobs written
  int jobs_skipped = 0;  ///< jobs of the sweep not done
  long long rows = 0;    ///< data rows written (not counting the header)
};

/// A column of a recorded series as the long-form table names it.
struct LongFormSignal {
  std::optional<int> joint;
  std::string signal;
};

/// "PHI", "j3" → {3, "PHI"}; "POS", "x" → {none, "POS.x"}.
LongFormSignal make_long_form_signal(const std::string& series, const std::string& column);

/// Writes the table of `sweep` to `out` as CSV (RFC 4180, shortest round-trip numbers).
/// `series` empty: every recorded series; otherwise those names, each of which must be recorded
/// by some done job (else std::invalid_argument naming it and listing what the sweep has).
SweepExportCounts write_sweep_long_csv(const ResultsStore& store, const std::string& sweep,
                                       const std::vector<std::string>& series, std::ostream& out);

/// The reason shown beside an undefined (null) metric value: the stored one, or a sentence
/// saying none was stored, so that no null goes out without a reason.
std::string describe_undefined_value(const std::string& stored_reason);

struct MetricExportCounts {
  int jobs = 0;                  ///< jobs with at least one metric row
  int jobs_without_metrics = 0;  ///< jobs of the sweep with none (pending, failed before measuring)
  long long rows = 0;            ///< data rows written (not counting the header)
};

/// Writes the scalar metrics of `sweep` as one long-form CSV, one row per stored metric:
///   job, status, <each swept parameter>, name, joint, checkpoint, value, unit, reason
/// `joint` is 1-based (empty for a job-level metric), `checkpoint` the held-out checkpoint
/// number (empty otherwise), `value` the shortest round-trip text (empty for an undefined
/// value, whose `reason` then says why), `unit` from metric_info. Every job of the sweep that
/// stored metrics is written (a diverged job's metrics too; `status` tells them apart), in
/// expansion order, metrics by name, joint and checkpoint.
MetricExportCounts write_sweep_metrics_csv(const ResultsStore& store, const std::string& sweep, std::ostream& out);

}  // namespace armfarm
