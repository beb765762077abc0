// CSV reader: values and header, file:line errors for malformed rows.
#include "runner/io/csv_reader.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <filesystem>
#include <fstream>

namespace armfarm::io {
namespace {

std::string write_temp(const std::string& name, const std::string& text) {
  const auto path = test_support::scratch_file("csv_" + name);
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& path) {
  try {
    load_csv(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(CsvReader, ReadsHeaderAndValues) {
  const CsvTable t = load_csv(write_temp("ok.csv", "a, b,c\n1,2.5,-3e2\r\n\n4,5,6\n"));
  EXPECT_EQ(t.header, (std::vector<std::string>{"a", "b", "c"}));
  ASSERT_EQ(t.values.rows(), 2);
  EXPECT_EQ(t.values(0, 2), -300.0);
  EXPECT_EQ(t.values(1, 1), 5.0);
}

TEST(CsvReader, ErrorsNameFileAndLine) {
  const std::string short_row = write_temp("short.csv", "a,b\n1,2\n3\n");
  EXPECT_EQ(error_of(short_row), short_row + ":3: 1 fields, expected 2");
  const std::string text = write_temp("text.csv", "a,b\n1,x\n");
  EXPECT_EQ(error_of(text), text + ":2: column 'b': not a finite number (a 1-byte token, not shown)");
  const std::string nan = write_temp("nan.csv", "a\nnan\n");
  EXPECT_NE(error_of(nan).find(":2:"), std::string::npos);
  EXPECT_NE(error_of(write_temp("empty.csv", "")).find("empty file"), std::string::npos);
  EXPECT_EQ(error_of("/no/such/file.csv"), "/no/such/file.csv: no such file");
}

}  // namespace
}  // namespace armfarm::io
