#pragma once
// Reading numeric CSV files (recorded trajectories, LWPR training data): a header row of column
// names, then rows of numbers separated by commas.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace armfarm::io {

/// A numeric table: column names from the header and one matrix row per data row.
struct CsvTable {
  std::vector<std::string> header;
  Eigen::MatrixXd values;  ///< rows × header.size()
  std::vector<int> lines;  ///< the file line (1-based) of each row of `values`
};

/// Loads `path` (a regular file under the CSV cap, engine/io/input_file.hpp). Throws
/// std::runtime_error "path:line: what" for a missing file, an empty file, a row with the wrong
/// number of fields, a field that is not entirely a finite decimal number (NaN, Inf, hex, text;
/// 1e-400, which underflows to zero, and 1e999 say so), a first row of numbers only (no header
/// row: it would silently lose the first sample), or a control character anywhere (NUL, a CR
/// that does not end the line, ...).
CsvTable load_csv(const std::string& path);

/// The table in `bytes`, read as load_csv reads a file; `path` names it in errors.
CsvTable parse_csv(const std::string& bytes, const std::string& path);

}  // namespace armfarm::io
