// Numeric CSV reader with file:line error messages.
#include "runner/io/csv_reader.hpp"

#include "engine/io/input_file.hpp"
#include "engine/io/number_text.hpp"

#include <algorithm>
#include <cctype>
#include <optional>
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
    } else {
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

// "column 'q3'" when the header name is a plain identifier, else "column 3": a message never
// quotes a file that is not the CSV it should be.
std::string describe_column(const std::vector<std::string>& header, std::size_t i) {
  const std::string& name = header[i];
  bool plain = !name.empty() && name.size() <= 32 && !std::isdigit(static_cast<unsigned char>(name[0]));
  for (char c : name) plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.');
  return plain ? "column '" + name + "'" : "column " + std::to_string(i + 1);
}

}  // namespace

CsvTable load_csv(const std::string& path) { return parse_csv(read_input_file(path, InputFileKind::table), path); }

CsvTable parse_csv(const std::string& bytes, const std::string& path) {
  std::istringstream in(bytes);
  CsvTable table;
  std::string line;
  int line_number = 0;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF line ends; a CR elsewhere is refused
    auto fail = [&](const std::string& what) {
      throw std::runtime_error(path + ":" + std::to_string(line_number) + ": " + what);
    };
    const std::size_t control = find_control_character(line);
    if (control != std::string::npos) {
      const auto field = std::count(line.begin(), line.begin() + static_cast<std::ptrdiff_t>(control), ',') + 1;
      fail(describe_control_character(line[control]) + " in field " + std::to_string(field) + " (byte " +
           std::to_string(control + 1) + " of the line)");
    }
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const std::vector<std::string> fields = split(line);
    if (table.header.empty()) {
      for (const auto& f : fields) {
        if (f.empty()) fail("empty column name in the header");
      }
      // A first row of numbers is data, not names: reading it as the header would drop a sample.
      if (std::all_of(fields.begin(), fields.end(), [](const std::string& f) { return parse_finite_number(f).has_value(); })) {
        fail("no header row: the first row holds numbers (the first row must name the columns, e.g. q1,q2,q3)");
      }
      table.header = fields;
      continue;
    }
    if (fields.size() != table.header.size()) {
      fail(std::to_string(fields.size()) + " fields, expected " + std::to_string(table.header.size()));
    }
    std::vector<double> row;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::optional<double> value = parse_finite_number(fields[i]);
      if (!value) fail(describe_column(table.header, i) + ": " + describe_bad_number(fields[i]));
      row.push_back(*value);
    }
    rows.push_back(std::move(row));
    table.lines.push_back(line_number);
  }
  if (table.header.empty()) throw std::runtime_error(path + ":1: empty file (expected a header row)");
  table.values.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(table.header.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (std::size_t c = 0; c < rows[r].size(); ++c) table.values(r, c) = rows[r][c];
  }
  return table;
}

}  // namespace armfarm::io
