// Numeric CSV reader with file:line error messages.
#include "runner/io/csv_reader.hpp"

#include "engine/io/input_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace armfarm::io {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  for (char c : line) {
    if (c == ',') {
      fields.push_back(field);
      field.clear();
    } else if (c != '\r') {
      field += c;
    }
  }
  fields.push_back(field);
  for (auto& f : fields) {
    const auto first = f.find_first_not_of(" \t");
    const auto last = f.find_last_not_of(" \t");
    f = first == std::string::npos ? "" : f.substr(first, last - first + 1);
  }
  return fields;
}

}  // namespace

CsvTable load_csv(const std::string& path) {
  std::istringstream in(read_input_file(path, InputFileKind::table));
  CsvTable table;
  std::string line;
  int line_number = 0;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> fields = split(line);
    auto fail = [&](const std::string& what) {
      throw std::runtime_error(path + ":" + std::to_string(line_number) + ": " + what);
    };
    if (table.header.empty()) {
      for (const auto& f : fields) {
        if (f.empty()) fail("empty column name in the header");
      }
      table.header = fields;
      continue;
    }
    if (fields.size() != table.header.size()) {
      fail(std::to_string(fields.size()) + " fields, expected " + std::to_string(table.header.size()));
    }
    std::vector<double> row;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const char* text = fields[i].c_str();
      char* end = nullptr;
      errno = 0;
      const double value = std::strtod(text, &end);
      if (fields[i].empty() || *end != '\0' || errno == ERANGE || !std::isfinite(value)) {
        fail("column '" + table.header[i] + "': '" + fields[i] + "' is not a finite number");
      }
      row.push_back(value);
    }
    rows.push_back(std::move(row));
  }
  if (table.header.empty()) throw std::runtime_error(path + ":1: empty file (expected a header row)");
  table.values.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(table.header.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t c = 0; c < rows[r].size(); ++c) table.values(r, c) = rows[r][c];
  }
  return table;
}

}  // namespace armfarm::io
