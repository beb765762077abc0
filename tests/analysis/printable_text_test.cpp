// Text from a database someone else made, made safe to print: control characters and bytes that
// are not UTF-8 replaced (make_printable_text) or shown as their pictures (make_visible_text).
#include "analysis/printable_text.hpp"

#include <gtest/gtest.h>

#include <string>

namespace armfarm {
namespace {

TEST(PrintableText, ReplacesControlCharactersAndBrokenUtf8AndKeepsPrintableText) {
  EXPECT_EQ(make_printable_text("\x1b[31mred"), "\xEF\xBF\xBD[31mred");
  EXPECT_EQ(make_printable_text(std::string("a\0b", 3)), "a\xEF\xBF\xBD" "b");
  EXPECT_EQ(make_printable_text("a\nb"), "a\xEF\xBF\xBD" "b");
  EXPECT_EQ(make_printable_text("a\nb", true), "a\nb");
  EXPECT_EQ(make_printable_text("\xC2\x9B" "1m"), "\xEF\xBF\xBD" "1m");  // C1 CSI
  EXPECT_EQ(make_printable_text("\xff"), "\xEF\xBF\xBD");
  EXPECT_EQ(make_printable_text("\xE0\x80\x80"), "\xEF\xBF\xBD\xEF\xBF\xBD\xEF\xBF\xBD");  // overlong
  EXPECT_EQ(make_printable_text("Gen3 \xC3\xA9 \xE2\x86\x92 \xF0\x9F\x98\x80"), "Gen3 \xC3\xA9 \xE2\x86\x92 \xF0\x9F\x98\x80");
}

TEST(VisibleText, ShowsControlCharactersAsTheirPicturesAndKeepsLinesAndTabs) {
  EXPECT_EQ(make_visible_text("\x1b[31mred"), "\xE2\x90\x9B[31mred");                          // U+241B
  EXPECT_EQ(make_visible_text(std::string("a\0b", 3)), "a\xE2\x90\x80" "b");                   // U+2400
  EXPECT_EQ(make_visible_text("a\rb\x7f"), "a\xE2\x90\x8D" "b\xE2\x90\xA1");                 // U+240D, U+2421
  EXPECT_EQ(make_visible_text("\x1f"), "\xE2\x90\x9F");                                      // U+241F, the last C0
  EXPECT_EQ(make_visible_text("a\n\tb"), "a\n\tb");
  EXPECT_EQ(make_visible_text("\xC2\x9B" "1m \xff"), "\xEF\xBF\xBD" "1m \xEF\xBF\xBD");          // C1 CSI, not UTF-8
  EXPECT_EQ(make_visible_text("Gen3 \xC3\xA9 \xE2\x86\x92"), "Gen3 \xC3\xA9 \xE2\x86\x92");
}

}  // namespace
}  // namespace armfarm
