// Fuzz target: numeric CSV files (runner/io/csv_reader: recorded trajectories, training data).
// A well-formed rejection is a std::runtime_error naming the file.
#include "runner/io/csv_reader.hpp"
#include "tests/fuzz/fuzz_input.hpp"

#include <cstdlib>
#include <stdexcept>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = armfarm::fuzz::write_scratch(data, size, ".csv");
  try {
    const armfarm::io::CsvTable table = armfarm::io::load_csv(path);
    if (static_cast<std::size_t>(table.values.rows()) != table.lines.size() || !table.values.allFinite()) std::abort();
  } catch (const std::runtime_error& error) {
    if (std::string(error.what()).rfind(path, 0) != 0) std::abort();  // every message names the file
  }
  return 0;
}
