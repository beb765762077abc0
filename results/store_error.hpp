#pragma once
// The one error type of the results store: a database that cannot be opened, is corrupt, is
// not SQLite, or was written by a newer schema. The message names the file.
#include <stdexcept>
#include <string>

namespace armfarm {

class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
  /// what() is "FILE: DETAIL"; `sqlite_code` is SQLite's (extended) result code when SQLite
  /// refused, else 0. A caller that needs the detail or the code reads these fields, never the text.
  StoreError(const std::string& file, std::string detail, int sqlite_code = 0)
      : std::runtime_error(file + ": " + detail), detail_(std::move(detail)), sqlite_code_(sqlite_code) {}

  /// What is wrong, without the file ("" when the error was made from one whole message).
  const std::string& detail() const { return detail_; }
  /// SQLite's extended result code (SQLITE_BUSY = 5, SQLITE_LOCKED = 6, …), 0 when none is known.
  int sqlite_code() const { return sqlite_code_; }

 private:
  std::string detail_;
  int sqlite_code_ = 0;
};

}  // namespace armfarm
