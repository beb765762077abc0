// Names from a database someone else made reach gnuplot as text, never as commands (issue 30,
// case 3): a corpus of hostile names (backticks, $(...), @ macros, quotes, newlines, NUL, ANSI
// escapes, bytes that are not UTF-8) as titles, labels and legends, rendered by the real
// gnuplot; no sentinel file appears and the SVG parses as XML text.
#include "analysis/figure.hpp"
#include "analysis/printable_text.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> make_hostile_names(const std::string& sentinel) {
  return {"rep`touch " + sentinel + "`",
          "$(touch " + sentinel + ")",
          "a@b @c",
          "q'uote\"s\\",
          "x\nrm -rf DIR\n#",
          std::string("nul\0x", 5),
          "\x1b[31mred\x1b[0m\r",
          "bad \xff\xfe utf8",
          "'`touch " + sentinel + "`'"};
}

// Found with the whole gnuplot log: gnuplot 5.4 reads the leading '' of the quoted name
// '`touch ...`' as an empty string, so a name starting with a quote broke the script (no command ran).
TEST(HostileNames, GnuplotRunsNoCommandAndTheSvgIsPlainText) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) GTEST_SKIP() << "gnuplot not installed";
  const fs::path dir = test_support::make_scratch_folder("hostile_plot");
  const std::string sentinel = (dir / "sentinel").string();
  const std::vector<std::string> names = make_hostile_names(sentinel);
  Figure figure;
  figure.title = names[0] + "\n" + names[4];
  for (const std::string& name : names) {
    Panel panel;
    panel.title = name;
    panel.x_label = name;
    panel.y_label = name;
    panel.curves.push_back(Curve{name, {0, 1}, {1, 2}, {}, {}});
    figure.panels.push_back(panel);
  }
  const fs::path out = dir / "out.svg";
  write_figure(figure, out.string());
  EXPECT_FALSE(fs::exists(sentinel)) << "gnuplot ran a command";
  std::ifstream in(out);
  const std::string svg((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  // Plain text: no control character but line breaks and tabs, well-formed UTF-8.
  // (gnuplot indents its SVG with tabs, which make_printable_text replaces: set them aside.)
  std::string untabbed = svg;
  untabbed.erase(std::remove(untabbed.begin(), untabbed.end(), '\t'), untabbed.end());
  EXPECT_EQ(make_printable_text(untabbed, true), untabbed);
  EXPECT_EQ(svg.find('\x1b'), std::string::npos) << "an escape reached the SVG";
  // The names are shown, quotes and backticks literally.
  EXPECT_NE(svg.find("rep`touch "), std::string::npos);
  EXPECT_NE(svg.find("q'uote"), std::string::npos);
  fs::remove_all(dir);
}

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

}  // namespace
}  // namespace armfarm
