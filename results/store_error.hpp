#pragma once
// The one error type of the results store: a database that cannot be opened, is corrupt, is
// not SQLite, or was written by a newer schema. The message names the file.
#include <stdexcept>
#include <string>

namespace armfarm {

class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace armfarm
