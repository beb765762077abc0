#pragma once
// Collects the recorded signals a job's configuration asks for (the thesis's POS, PHI, VEL,
// ACC, their desired versions, TOR, F, FF, and our RF and TRIAL), row by row.
#include "engine/experiment/job_outcome.hpp"

#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

namespace armfarm {

/// The names a configuration may request: the signals of the job's own passes (POS … RF,
/// TRIAL), and each per-tick signal with the prefix `heldout_` ("heldout_F"), which records that
/// signal in every held-out control pass instead, stored per checkpoint (heldout_series_name).
const std::vector<std::string>& recordable_series_names();

/// `requested` without the held-out names: what the job's own passes record.
std::vector<std::string> select_pass_series(const std::vector<std::string>& requested);
/// The signals the held-out control passes record: the `heldout_` names of `requested`, prefix
/// removed ("heldout_F" → "F").
std::vector<std::string> select_heldout_series(const std::vector<std::string>& requested);
/// The stored name of signal `name` recorded in the held-out pass at `checkpoint`:
/// "heldout_F_c200" (the spelling of a checkpoint's metric column, results/).
std::string make_heldout_series_name(const std::string& name, long checkpoint);

class SeriesRecorder {
 public:
  /// `requested`: names from recordable_series_names(); `joint_numbers`: 1-based, for column names.
  SeriesRecorder(const std::vector<std::string>& requested, const std::vector<int>& joint_numbers);

  bool wants(const std::string& name) const { return buffers_.count(name) > 0; }
  /// Appends a row (time, values...) to `name` if it was requested.
  void add(const std::string& name, double time, const Eigen::VectorXd& values);
  /// Appends a row of explicitly named columns (used by TRIAL); the first call fixes the columns.
  void add_row(const std::string& name, const std::vector<std::string>& columns, const Eigen::VectorXd& values);

  std::vector<Series> take_series();

 private:
  struct Buffer {
    std::vector<std::string> columns;
    std::vector<double> values;  ///< row-major
  };
  std::vector<int> joint_numbers_;
  std::map<std::string, Buffer> buffers_;
};

}  // namespace armfarm
