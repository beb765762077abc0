// What the export tests share: expected values as C99 hex floats (exact, whatever the printing),
// and a Python checker that reads an exported CSV with the csv module, as a user's script would,
// against the expected rows.
#pragma once

#include "support/command_line.hpp"

#include <cstdio>
#include <fstream>
#include <string>

namespace armfarm::test_support {

/// `value` as a C99 hex float ("0x1.999999999999ap-4"): Python's float.fromhex reads it exactly.
inline std::string make_hex(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%a", value);
  return text;
}

/// The start of every checker. argv[1]: the CSV; argv[2]: the expected data rows (JSON lines);
/// argv[3]: the expected header (a JSON list). Checks the header and the number of rows; leaves
/// `rows` (the data rows), `expected` and `header`, and defines digits(text) (the significant
/// digits of a number's text) and shortest(text) (the text is the shortest that reads back to
/// its double, as Python's repr; nan and inf pass).
inline const char* const kCsvCheckerStart = R"py(
import csv, json, math, sys
def digits(text):
    mantissa = text.lower().lstrip("+-").split("e")[0].replace(".", "")
    return mantissa.strip("0") or "0"
def shortest(text):
    return math.isnan(float(text)) or math.isinf(float(text)) or digits(text) == digits(repr(float(text)))
expected = [json.loads(line) for line in open(sys.argv[2])]
header = json.loads(open(sys.argv[3]).read())
with open(sys.argv[1], newline="") as f:
    rows = list(csv.reader(f))
assert rows[0] == header, (rows[0], header)
rows = rows[1:]
assert len(rows) == len(expected), (len(rows), len(expected))
)py";

/// Writes kCsvCheckerStart + `row_checks` (Python, after the start) to `script`, runs it on the
/// CSV, expected rows and header files and returns its exit code and output ("checked N rows"
/// when every assertion held).
inline CommandResult run_csv_checker(const std::string& script, const std::string& row_checks, const std::string& csv,
                                     const std::string& expected_rows, const std::string& header) {
  std::ofstream(script) << kCsvCheckerStart << row_checks << "print(\"checked\", len(rows), \"rows\")\n";
  return run_command_line("python3 " + script + " " + csv + " " + expected_rows + " " + header);
}

}  // namespace armfarm::test_support
