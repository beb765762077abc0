// Names from a database someone else made reach gnuplot as text, never as commands (issue 30,
// case 3): a corpus of hostile names (backticks, $(...), @ macros, quotes, newlines, NUL, ANSI
// escapes, bytes that are not UTF-8) as titles, labels and legends, rendered by the real
// gnuplot; no sentinel file appears and the SVG parses as XML text.
#include "analysis/figure.hpp"
#include "analysis/printable_text.hpp"

#include <gtest/gtest.h>

#include "support/scratch_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

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

// ---------------------------------------------------------------- the palette (issue 24, item 5)
// Checked by a computation of its own: sRGB to CIELAB (D65), and the colour-vision deficiencies
// simulated by Machado, Oliveira and Fernandes (2009) at severity 1 in linear RGB. The old
// palette's feed-forward (#88CCEE) and composite (#44AA99) were 16.8 apart for a tritan and 15
// in greyscale; its 12 colours came within 5.8 of each other for a protan (#CC6677, #EE6677).

using Rgb = std::array<double, 3>;
using Lab = std::array<double, 3>;

Rgb parse_hex_colour(const std::string& hex) {
  unsigned r = 0, g = 0, b = 0;
  EXPECT_EQ(std::sscanf(hex.c_str(), "#%02x%02x%02x", &r, &g, &b), 3) << hex;
  return {r / 255.0, g / 255.0, b / 255.0};
}

double to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

// `colour` as seen with `vision` (a 3 × 3 matrix on linear RGB), in CIELAB.
Lab calc_lab(const Rgb& colour, const std::array<std::array<double, 3>, 3>& vision) {
  Rgb linear{};
  for (int i = 0; i < 3; ++i) {
    double sum = 0;
    for (int j = 0; j < 3; ++j) sum += vision[i][j] * to_linear(colour[j]);
    linear[i] = std::clamp(sum, 0.0, 1.0);
  }
  const double x = (0.4124 * linear[0] + 0.3576 * linear[1] + 0.1805 * linear[2]) / 0.95047;
  const double y = 0.2126 * linear[0] + 0.7152 * linear[1] + 0.0722 * linear[2];
  const double z = (0.0193 * linear[0] + 0.1192 * linear[1] + 0.9505 * linear[2]) / 1.08883;
  const auto f = [](double t) { return t > 0.008856 ? std::cbrt(t) : 7.787 * t + 16.0 / 116; };
  return {116 * f(y) - 16, 500 * (f(x) - f(y)), 200 * (f(y) - f(z))};
}

const std::array<std::array<std::array<double, 3>, 3>, 4>& kVisions() {
  static const std::array<std::array<std::array<double, 3>, 3>, 4> visions = {{
      {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},                                                                  // normal
      {{{0.152286, 1.052583, -0.204868}, {0.114503, 0.786281, 0.099216}, {-0.003882, -0.048116, 1.051998}}},  // protan
      {{{0.367322, 0.860646, -0.227968}, {0.280085, 0.672501, 0.047413}, {-0.011820, 0.042940, 0.968881}}},   // deutan
      {{{1.255528, -0.076749, -0.178779}, {-0.078411, 0.930809, 0.147602}, {0.004733, 0.691367, 0.303900}}},  // tritan
  }};
  return visions;
}

// The smallest CIELAB distance of two colours over the four visions.
double calc_worst_distance(const std::string& a, const std::string& b) {
  double worst = INFINITY;
  for (const auto& vision : kVisions()) {
    const Lab p = calc_lab(parse_hex_colour(a), vision), q = calc_lab(parse_hex_colour(b), vision);
    worst = std::min(worst, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
  }
  return worst;
}

TEST(FigurePalette, TheFirstThreeStayApartInGreyscaleAndEveryColourForColourBlindReaders) {
  const std::vector<std::string>& colours = figure_colours();
  ASSERT_EQ(colours.size(), 12u);
  // The closed form first: white is L* 100, black 0, the sRGB primaries' L* 53.2 / 87.7 / 32.3.
  const auto identity = kVisions()[0];
  EXPECT_NEAR(calc_lab({1, 1, 1}, identity)[0], 100.0, 0.01);
  EXPECT_NEAR(calc_lab({1, 0, 0}, identity)[0], 53.24, 0.05);
  EXPECT_NEAR(calc_lab({0, 1, 0}, identity)[0], 87.73, 0.05);
  EXPECT_NEAR(calc_lab({0, 0, 1}, identity)[0], 32.30, 0.05);
  // Feedback, feed-forward and composite (the first three): apart in every vision and in
  // greyscale (L*), and dark enough for a thin line on white paper.
  std::vector<double> lightness;
  for (std::size_t i = 0; i < 3; ++i) lightness.push_back(calc_lab(parse_hex_colour(colours[i]), identity)[0]);
  std::sort(lightness.begin(), lightness.end());
  EXPECT_GE(lightness[1] - lightness[0], 18.0);
  EXPECT_GE(lightness[2] - lightness[1], 18.0);
  EXPECT_LE(lightness[2], 75.0);
  for (std::size_t i = 0; i < colours.size(); ++i) {
    EXPECT_LE(calc_lab(parse_hex_colour(colours[i]), identity)[0], 75.0) << colours[i] << ": too light for a line on white";
    EXPECT_GE(calc_worst_distance(colours[i], figure_edge_mark_colour()), 10.0) << colours[i] << " beside the edge marks' red";
    EXPECT_GE(calc_worst_distance(colours[i], "#000000"), 15.0) << colours[i] << " beside the emphasised curves' black";
    for (std::size_t j = i + 1; j < colours.size(); ++j) {
      EXPECT_GE(calc_worst_distance(colours[i], colours[j]), i < 3 && j < 3 ? 30.0 : 10.0) << colours[i] << " and " << colours[j];
    }
  }
}

// ---------------------------------------------------------------- the gnuplot script

// The "set xtics S" and "set ytics S" steps and the ranges of each panel of `script`, in order.
struct ScriptAxes {
  double x_step = 0, y_step = 0, x_low = 0, x_high = 0, y_low = 0, y_high = 0;
};
std::vector<ScriptAxes> read_script_axes(const std::string& script) {
  std::vector<ScriptAxes> panels;
  std::istringstream in(script);
  ScriptAxes current;
  for (std::string line; std::getline(in, line);) {
    std::sscanf(line.c_str(), "set xtics %lf", &current.x_step);
    std::sscanf(line.c_str(), "set ytics %lf", &current.y_step);
    std::sscanf(line.c_str(), "set xrange [%lf:%lf]", &current.x_low, &current.x_high);
    std::sscanf(line.c_str(), "set yrange [%lf:%lf]", &current.y_low, &current.y_high);
    if (line.rfind("plot ", 0) == 0) {
      panels.push_back(current);
      current = {};
    }
  }
  return panels;
}

double count_multiples(double low, double high, double step) { return std::floor(high / step + 1e-9) - std::ceil(low / step - 1e-9) + 1; }

// Figure 6.11's side view of the sphere (issue 24, item 4): a path long on one axis and flat on
// the other kept a finer tick step on its short side, so that equal lengths read as unequal. Over
// flat paths at many offsets, in the four panels of 6.11 at paper style and alone on a slide,
// every equal-axes panel has one step on both axes and at least two labels on each.
TEST(EqualAxes, OneTickStepOnBothAxesAndTwoLabelsOnEach) {
  for (const char* style : {"paper", "slide"}) {
    for (int k = 0; k < 40; ++k) {
      const double offset = 0.013 * k, long_side = 0.1 + 0.02 * (k % 7), flat = 0.002 * (k % 5);
      Figure figure;
      for (int p = 0; p < (style == std::string("paper") ? 4 : 1); ++p) {
        Panel panel;
        panel.title = "sphere (y-z)";
        panel.x_label = "y (m)";
        panel.y_label = "z (m)";
        panel.equal_axes = true;
        Curve path;
        for (int i = 0; i <= 50; ++i) {
          const double s = i / 50.0;
          const bool tall = (p + k) % 2 == 1;
          const double along = 0.3 + offset + long_side * s, across = 0.2 + 0.7 * offset + flat * std::sin(6.3 * s);
          path.x.push_back(tall ? across : along);
          path.y.push_back(tall ? along : across);
        }
        panel.curves.push_back(path);
        figure.panels.push_back(panel);
      }
      FigureOptions options;
      options.style = parse_figure_style(style);
      const std::string script = make_gnuplot_script(figure, make_terminal_settings("f.svg", options, figure), "f.svg", "/tmp");
      const auto axes = read_script_axes(script);
      ASSERT_EQ(axes.size(), figure.panels.size());
      for (std::size_t p = 0; p < axes.size(); ++p) {
        const ScriptAxes& a = axes[p];
        SCOPED_TRACE(std::string(style) + " case " + std::to_string(k) + " panel " + std::to_string(p));
        ASSERT_GT(a.x_step, 0);
        EXPECT_DOUBLE_EQ(a.x_step, a.y_step);
        EXPECT_NEAR(a.x_high - a.x_low, a.y_high - a.y_low, 1e-12);  // equal lengths: a square panel
        EXPECT_GE(count_multiples(a.x_low, a.x_high, a.x_step), 2);
        EXPECT_GE(count_multiples(a.y_low, a.y_high, a.y_step), 2);
        // The data inside the range.
        for (double x : figure.panels[p].curves[0].x) EXPECT_TRUE(x >= a.x_low && x <= a.x_high);
        for (double y : figure.panels[p].curves[0].y) EXPECT_TRUE(y >= a.y_low && y <= a.y_high);
      }
    }
  }
}

// The curves of one panel in the order `script`'s first plot command draws them (their data
// files' curve numbers) and each one's "lw".
std::vector<std::pair<int, double>> read_first_plot(const std::string& script) {
  std::vector<std::pair<int, double>> drawn;
  const auto start = script.find("\nplot ");
  const auto end = script.find("keyentry", start);
  for (auto at = script.find("data_0_", start); at < end; at = script.find("data_0_", at + 1)) {
    const int curve = std::atoi(script.c_str() + at + 7);
    const auto lw = script.find(" lw ", at);
    drawn.emplace_back(curve, lw < end ? std::atof(script.c_str() + lw + 4) : 0.0);
  }
  return drawn;
}

// A sum drawn under its parts (issue 24, item 3): figure 6.8's composite torque lay on the
// feedback and hid it where the feed-forward was near zero.
TEST(CurveLayers, AnUnderneathCurveIsDrawnFirstAndWiderAndItsLegendEntryShowsIt) {
  Figure figure;
  Panel panel;
  for (const char* title : {"feedback", "feed-forward", "composite"}) {
    Curve curve;
    curve.title = title;
    curve.x = {0, 1, 2};
    curve.y = {1, 2, 1};
    curve.underneath = curve.title == "composite";
    panel.curves.push_back(curve);
  }
  figure.panels.push_back(panel);
  FigureOptions paper;
  paper.style = FigureStyle::paper;
  const std::string script = make_gnuplot_script(figure, make_terminal_settings("f.pdf", paper, figure), "f.pdf", "/tmp");
  const auto drawn = read_first_plot(script);
  ASSERT_EQ(drawn.size(), 3u) << script;
  EXPECT_EQ(drawn[0].first, 2);  // the composite first, under the others
  EXPECT_EQ(drawn[1].first, 0);
  EXPECT_EQ(drawn[2].first, 1);
  EXPECT_DOUBLE_EQ(drawn[0].second, 2.5 * drawn[1].second);
  // The legend keeps the declared order and shows the composite as drawn; the colours are the
  // palette's first three in that order.
  const auto feedback = script.find("keyentry with lines lw 1 lc rgb '" + figure_colours()[0] + "' dt 1 title 'feedback'");
  const auto feed_forward = script.find("keyentry with lines lw 1 lc rgb '" + figure_colours()[1] + "' dt 1 title 'feed-forward'");
  const auto composite = script.find("keyentry with lines lw 2.5 lc rgb '" + figure_colours()[2] + "' dt 1 title 'composite'");
  ASSERT_NE(feedback, std::string::npos) << script;
  ASSERT_NE(feed_forward, std::string::npos) << script;
  ASSERT_NE(composite, std::string::npos) << script;
  EXPECT_LT(feedback, feed_forward);
  EXPECT_LT(feed_forward, composite);
}

// A caption for a document that sets its own (issue 24, item 1): the figure without it is
// shorter by its lines, draws none of its text, and format_caption_text gives that text.
TEST(FigureCaption, LeftOutItShortensThePageAndItsTextIsGivenApart) {
  Figure figure;
  figure.title = "a figure";
  Panel panel;
  panel.curves.push_back(Curve{"a", {0, 1}, {1, 2}, {}, {}});
  figure.panels.push_back(panel);
  figure.table.header = {"joint", "thesis"};
  figure.table.rows = {{"1", "0.5"}, {"2", "0.75"}};
  figure.caption = {"first paragraph", "second paragraph"};
  FigureOptions paper;
  paper.style = FigureStyle::paper;
  const TerminalSettings with = make_terminal_settings("f.pdf", paper, figure);
  const Figure bare = remove_caption(figure);
  const TerminalSettings without = make_terminal_settings("f.pdf", paper, bare);
  // Five lines (header, two rows, two paragraphs) and 0.4 of a gap at 8 pt, 1.25 em a line.
  EXPECT_NEAR(with.height_pt - without.height_pt, 1.25 * 8 * 5.4, 1e-9);
  const std::string script = make_gnuplot_script(bare, without, "f.pdf", "/tmp");
  EXPECT_EQ(script.find("paragraph"), std::string::npos);
  EXPECT_EQ(script.find("0.75"), std::string::npos);
  EXPECT_EQ(format_caption_text(figure), "joint  thesis\n1      0.5\n2      0.75\nfirst paragraph\nsecond paragraph\n");
  EXPECT_EQ(format_caption_text(bare), "");
}

}  // namespace
}  // namespace armfarm
