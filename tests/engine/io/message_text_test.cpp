// The one home of short messages (engine/io/message_text.hpp): lists past ten entries end in
// "… and N more", and an over-long line is cut at a character boundary with the bytes left out.
#include "engine/io/message_text.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace armfarm {
namespace {

TEST(MessageText, ListsPastTenEntriesAreShortened) {
  std::vector<std::string> names;
  for (int i = 0; i < 10000; ++i) names.push_back("l" + std::to_string(i));
  EXPECT_EQ(join_shortened(names), "l0, l1, l2, l3, l4, l5, l6, l7, l8, l9 … and 9990 more");
  names.resize(10);
  EXPECT_EQ(join_shortened(names).find("more"), std::string::npos);  // exactly ten: all listed
  EXPECT_EQ(join_shortened({"a", "b", "c"}, "; ", 2), "a; b … and 1 more");
  EXPECT_EQ(join_shortened({}), "");
}

TEST(MessageText, LongLinesAreCutAtACharacterBoundary) {
  EXPECT_EQ(cap_message_line("short"), "short");
  const std::string long_line(89000, 'x');
  const std::string capped = cap_message_line(long_line);
  EXPECT_EQ(capped, std::string(1000, 'x') + " … (88000 more bytes)");
  // "é" is two bytes; a cut inside it steps back to before it.
  EXPECT_EQ(cap_message_line("abé", 3), "ab … (2 more bytes)");
  // Each line of a multi-line message (a SpecError's problems) is capped on its own.
  EXPECT_EQ(cap_message_line("abcdef\nxy", 4), "abcd … (2 more bytes)\nxy");
}

}  // namespace
}  // namespace armfarm
