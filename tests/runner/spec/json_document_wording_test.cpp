// The spec reader and the thesis results reader word a JSON syntax error alike (base/json_syntax_error.hpp).
// Not in json_document_test.cpp: that file is in the sanitizer subset, whose binary does not link
// analysis/ (tests/CMakeLists.txt), and this test calls the analysis's thesis results reader.
#include "runner/spec/json_document.hpp"
#include "runner/spec/spec_error.hpp"
#include "analysis/analysis_error.hpp"
#include "analysis/thesis_comparison.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace armfarm {
namespace {

// The spec reader and the thesis results reader parse with different rules but word a syntax
// error the same way, from one home (base/json_syntax_error.hpp): the same text gives the same
// line after the file name, and nlohmann's "last read" bytes are never printed.
TEST(JsonDocument, ASyntaxErrorIsWordedAsTheThesisResultsReaderWordsIt) {
  const std::string path = "dir/broken.json";
  const std::vector<std::string> texts = {"{\"tables\": [}", "{\n  \"a\": tru\n}", "root:x:0:0", "{\"a\": \"\\uZZZZ\"}", ""};
  for (const std::string& text : texts) {
    std::string spec_line, thesis_line;
    try {
      parse_json_document(text, path);
    } catch (const SpecError& e) {
      spec_line = e.what();
    }
    try {
      parse_thesis_results_text(text, path);
    } catch (const AnalysisError& e) {
      thesis_line = e.what();
    }
    EXPECT_EQ(spec_line, thesis_line) << text;
    EXPECT_NE(spec_line.find(": not valid JSON: "), std::string::npos) << spec_line;
    EXPECT_EQ(spec_line.find("last read"), std::string::npos) << spec_line;
  }
  try {
    parse_json_document("{\"tables\": [}", "f.json");
    ADD_FAILURE() << "a syntax error parsed";
  } catch (const SpecError& e) {
    EXPECT_EQ(std::string(e.what()), "f.json: line 1, column 13: not valid JSON: syntax error while parsing value - unexpected '}'; "
                                     "expected '[', '{', or a literal");
  }
}

}  // namespace
}  // namespace armfarm
