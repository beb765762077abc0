#pragma once
// The BLOB format of a recorded series: the samples as little-endian IEEE-754 float64, column
// after column (column-major, Eigen's own order), compressed as one zstd frame (level 3).
// results/README.md shows how to read it back in Python.
#include <Eigen/Core>

#include <string>
#include <vector>

namespace armfarm {

/// Packs `rows` (n_samples × n_columns) into a zstd-compressed column-major f64le BLOB.
std::vector<unsigned char> calc_series_blob(const Eigen::MatrixXd& rows);

/// Unpacks a BLOB of `n_rows × n_columns`. Throws StoreError naming `where` when the BLOB is not a
/// zstd frame or its size does not match.
Eigen::MatrixXd calc_series_matrix(const std::vector<unsigned char>& blob, long n_rows, long n_columns,
                                   const std::string& where);

}  // namespace armfarm
