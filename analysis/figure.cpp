#include "analysis/figure.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/printable_text.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace armfarm {

namespace {

// gnuplot text that cannot expand: runs of plain text in single quotes, inside which gnuplot
// runs no backtick command, expands no @macro and reads no backslash escape, joined by `.` to the
// constants "\n" and "'" for line breaks and quotes (gnuplot 5.4 reads a leading '' as an empty
// string, so a doubled quote cannot start a string). Other control characters and bytes that
// are not UTF-8 are replaced.
std::string quote_gnuplot(const std::string& text) {
  const std::string printable = make_printable_text(text, /*keep_newlines=*/true);
  std::string out;
  std::string run;
  const auto add = [&out](const std::string& piece) { out += (out.empty() ? "" : ".") + piece; };
  for (const char c : printable) {
    if (c != '\n' && c != '\'') {
      run += c;
      continue;
    }
    if (!run.empty()) add("'" + run + "'");
    run.clear();
    add(c == '\n' ? "\"\\n\"" : "\"'\"");
  }
  if (!run.empty() || out.empty()) add("'" + run + "'");
  return out;
}

// Runs `gnuplot script` with no shell in between (no path or name is ever parsed as a command),
// stdin from /dev/null and stdout and stderr into `log`. Returns the wait status, or -1 with
// errno set when gnuplot could not be started.
int run_gnuplot(const std::string& script, const std::string& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::string program = "gnuplot";
  std::vector<char*> argv = {program.data(), const_cast<char*>(script.c_str()), nullptr};
  pid_t pid = 0;
  const int error = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) {
    errno = error;
    return -1;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return status;
}

std::string data_file_name(std::size_t panel, std::size_t curve) {
  return "data_" + std::to_string(panel) + "_" + std::to_string(curve) + ".dat";
}

bool ends_with(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The legend below the panels: one entry per distinct title, as many to a row as fit the page.
struct LegendLayout {
  std::size_t rows = 0;
  std::size_t columns = 1;
};
LegendLayout make_legend_layout(const Figure& figure, double char_width_fraction) {
  std::vector<std::string> entries;
  std::size_t longest = 0;
  for (const Panel& panel : figure.panels) {
    for (const Curve& curve : panel.curves) {
      if (curve.title.empty() || std::find(entries.begin(), entries.end(), curve.title) != entries.end()) continue;
      entries.push_back(curve.title);
      longest = std::max(longest, curve.title.size());
    }
    const std::string& marks = panel.edge_mark_title;
    if (!panel.edge_marks_x.empty() && !marks.empty() && std::find(entries.begin(), entries.end(), marks) == entries.end()) {
      entries.push_back(marks);
      longest = std::max(longest, marks.size());
    }
  }
  const std::size_t per_row =
      std::max<std::size_t>(1, static_cast<std::size_t>(0.95 / (char_width_fraction * (1.15 * static_cast<double>(longest) + 12))));
  return {(entries.size() + per_row - 1) / per_row, per_row};
}

// The finite data range of a panel's axis (0: x with the edge marks, 1: y with the error bars' ends).
std::pair<double, double> find_data_range(const Panel& panel, int axis) {
  double low = INFINITY, high = -INFINITY;
  for (const Curve& curve : panel.curves) {
    for (const auto* values : axis == 0 ? std::vector<const std::vector<double>*>{&curve.x}
                                        : std::vector<const std::vector<double>*>{&curve.y, &curve.y_low, &curve.y_high}) {
      for (double v : *values) {
        if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
      }
    }
  }
  if (axis == 0) {
    for (double v : panel.edge_marks_x) {
      if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
    }
  }
  return {low, high};
}

// The x axis's range, always explicit (equal axes take make_equal_axes's instead): a time axis
// (tight_x) from the data's first to its last x (or from x_min); otherwise the data padded by 5 %
// of its span each side (of its decades on a log axis), so that no point or error bar sits on the
// frame. Empty: no data.
std::optional<std::pair<double, double>> find_x_axis_range(const Panel& panel) {
  auto [low, high] = find_data_range(panel, 0);
  if (!(high >= low) || !std::isfinite(low) || !std::isfinite(high)) return std::nullopt;
  if (panel.log_x && !(low > 0)) return std::nullopt;
  if (!panel.tight_x) {
    if (panel.log_x) {
      const double pad = std::pow(10.0, std::max(0.05, 0.05 * std::log10(high / low)));
      low /= pad;
      high *= pad;
    } else {
      const double pad = high > low ? 0.05 * (high - low) : std::max(0.5 * std::abs(low), 0.5);
      low -= pad;
      high += pad;
    }
  }
  if (panel.x_min && (!panel.log_x || *panel.x_min > 0)) low = *panel.x_min;
  if (!(high > low)) return std::nullopt;
  return std::make_pair(low, high);
}

std::size_t count_label_chars(double value) {
  char label[32];
  return static_cast<std::size_t>(std::snprintf(label, sizeof label, "%g", value));
}

// A linear axis's tick step: the finest 1, 2 or 5 × 10^k whose labels keep apart on the panel,
// `room` characters across (x: the widest label '%g' and 1.5 characters between neighbours) or
// lines down (y: 1.35 lines, 1.7 em, from label to label). On an axis that gnuplot extends (`extend`) the
// range grows to the next multiple of the step, as gnuplot's autoscale does.
double choose_linear_step(double low, double high, bool extend, double room, int axis) {
  const double range = high - low;
  double step = std::pow(10.0, std::floor(std::log10(range)) - 2);
  for (int i = 0; i < 30; ++i, step *= (i % 3 == 2 ? 2.5 : 2.0)) {  // 1, 2, 5, 10, 20, 50, …
    const double first = extend ? std::floor(low / step + 1e-9) * step : std::ceil(low / step - 1e-9) * step;
    const double last = extend ? std::ceil(high / step - 1e-9) * step : std::floor(high / step + 1e-9) * step;
    const int count = static_cast<int>(std::lround((last - first) / step)) + 1;
    const double span = extend ? last - first : range;
    if (count > 12 || !(span > 0)) continue;
    const double spacing = room * step / span;
    double needed = 1.35;
    if (axis == 0) {
      std::size_t widest = 0;
      for (int k = 0; k < count; ++k) {
        double value = first + k * step;
        if (std::abs(value) < step * 1e-9) value = 0.0;
        widest = std::max(widest, count_label_chars(value));
      }
      needed = static_cast<double>(widest) + 1.5;
    }
    if (spacing >= needed) return step;
  }
  return step;
}

// Equal axes (a path in a plane): both axes span one length about their data's centres (the
// larger data range and 5 % more), so that the panel is square, and share one tick step, the
// coarser of the two that choose_linear_step gives in the square's room. Where that step would
// leave an axis a single label (a flat path's short side), the length grows until both hold two:
// one step on both axes, as an equal scale needs (the sphere's side view had 0.05 on x, 0.02 on y).
struct EqualAxes {
  std::pair<double, double> range[2] = {{NAN, NAN}, {NAN, NAN}};
  double step = 0;  ///< 0: no finite data, ranges and ticks automatic
};

EqualAxes make_equal_axes(const Panel& panel, double room_chars, double room_lines) {
  EqualAxes axes;
  const auto [x_low, x_high] = find_data_range(panel, 0);
  const auto [y_low, y_high] = find_data_range(panel, 1);
  if (!(x_high >= x_low) || !(y_high >= y_low) || !std::isfinite(x_high - x_low) || !std::isfinite(y_high - y_low)) return axes;
  const double centre[2] = {(x_low + x_high) / 2, (y_low + y_high) / 2};
  double half = std::max({x_high - x_low, y_high - y_low, 1e-9}) * 0.525;
  for (int round = 0; round < 8; ++round) {
    double step = 0;
    for (int axis = 0; axis < 2; ++axis) {
      step = std::max(step, choose_linear_step(centre[axis] - half, centre[axis] + half, false, axis == 0 ? room_chars : room_lines, axis));
    }
    axes.step = step;
    // Two labels about a centre c: the multiples of the step at and above floor(c / step).
    double needed = half;
    for (const double c : centre) {
      const double below = std::floor(c / step + 1e-9) * step;
      needed = std::max(needed, std::max(c - below, below + step - c) * (1 + 1e-6));
    }
    if (needed <= half) break;
    half = needed;  // a longer span may want a coarser step: choose again
  }
  for (int axis = 0; axis < 2; ++axis) axes.range[axis] = {centre[axis] - half, centre[axis] + half};
  return axes;
}

std::string make_range_lines(const Panel& panel, const EqualAxes& equal) {
  std::string lines;
  char line[160];
  const auto x = panel.equal_axes ? std::optional<std::pair<double, double>>(equal.range[0]) : find_x_axis_range(panel);
  if (x && x->second > x->first) {
    std::snprintf(line, sizeof line, "set xrange [%.17g:%.17g]\n", x->first, x->second);
    lines += line;
  } else {
    lines += "set autoscale x\n";
  }
  if (panel.equal_axes) {
    const auto [y_low, y_high] = equal.range[1];
    if (y_high > y_low) {
      std::snprintf(line, sizeof line, "set yrange [%.17g:%.17g]\n", y_low, y_high);
      return lines + line;
    }
    return lines + "set autoscale y\n";
  }
  if (panel.y_min) {
    std::snprintf(line, sizeof line, "set yrange [%.17g:*]\n", *panel.y_min);
    return lines + line;
  }
  return lines + "set autoscale y\n";
}

// An axis's extent for its ticks: x as find_x_axis_range sets it; y the data and the bars' ends
// (from y_min), which gnuplot extends to the next ticks (`extend`).
struct AxisExtent {
  double low = INFINITY, high = -INFINITY;
  bool extend = false;
};

AxisExtent find_tics_extent(const Panel& panel, int axis) {
  AxisExtent extent;
  if (axis == 0) {
    const auto range = find_x_axis_range(panel);
    if (range) std::tie(extent.low, extent.high) = *range;
    return extent;
  }
  std::tie(extent.low, extent.high) = find_data_range(panel, 1);
  if (panel.y_min) extent.low = std::min(extent.low, *panel.y_min);
  extent.extend = true;
  return extent;
}

// The decade step of a log axis's labels: 1 when every decade's label fits, else the least k
// whose every k-th label from `first_shown` keeps apart (x: the widest label and a character
// between centres; y: 1.6 lines).
int choose_log_decade_step(int first, int last, int first_shown, double shown_high, double decades, double room, int axis) {
  int step = 1;
  for (; step < last - first; ++step) {
    double needed = 1.6;
    if (axis == 0) {
      std::size_t widest = 0;
      for (int k = first_shown; std::pow(10.0, k) <= shown_high * (1 + 1e-9); k += step) {
        widest = std::max(widest, count_label_chars(std::pow(10.0, k)));
      }
      needed = static_cast<double>(widest) + 1;
    }
    if (room * step / decades >= needed) break;
  }
  return step;
}

// "set Xtics add (…)": 2 and 5 of each decade (the nearest labels 0.3 decades apart), else 3
// (0.48), where they fit; "" when neither does.
std::string make_log_extra_labels(const char* name, int first, int last, double shown_low, double shown_high, double decades,
                                  double room, int axis) {
  for (const std::vector<double>& factors : {std::vector<double>{2, 5}, std::vector<double>{3}}) {
    const double closest = factors.size() == 2 ? std::log10(2.0) : std::log10(3.0);
    std::size_t widest = 0;
    std::string added;
    for (int k = first - 1; k <= last; ++k) {
      for (double factor : factors) {
        const double value = factor * std::pow(10.0, k);
        if (value < shown_low || value > shown_high) continue;
        char number[40];
        std::snprintf(number, sizeof number, "%.17g", value);
        added += (added.empty() ? "" : ", ") + std::string(number);
        widest = std::max(widest, count_label_chars(value));
      }
    }
    const double needed = axis == 0 ? static_cast<double>(widest) + 1.5 : 1.6;
    if (added.empty() || room * closest / decades < needed) continue;
    return std::string("set ") + name + " add (" + added + ")\n";
  }
  return "";
}

// A log axis's ticks: every decade when they fit, else every k-th decade from the lowest the
// axis reaches ("set xtics 10^first, 10^k"; a bare factor counts from 1, not from the data, and
// left a single label on a narrow panel over 0.01-3). Fewer than three decade labels: 2 and 5
// (or 3) of each decade too.
std::string make_log_tics_lines(const Panel& panel, const char* name, const AxisExtent& extent, double room, int axis) {
  const int first = static_cast<int>(std::floor(std::log10(extent.low) + 1e-9));
  const int last = std::max(first + 1, static_cast<int>(std::ceil(std::log10(extent.high) - 1e-9)));
  // The axis as drawn: gnuplot's autoscale ends a log axis on whole decades (y_min fixes the low end).
  const double shown_low = extent.extend && !panel.y_min ? std::pow(10.0, first) : extent.low;
  const double shown_high = extent.extend ? std::pow(10.0, last) : extent.high;
  const double decades = std::log10(shown_high / shown_low);
  // The lowest decade on the axis as drawn: labels count from it (from a decade below the
  // axis, every other label fell outside a padded 0.0075-4 axis and left one).
  const int first_shown = static_cast<int>(std::ceil(std::log10(shown_low) - 1e-9));
  const int step = choose_log_decade_step(first, last, first_shown, shown_high, decades, room, axis);
  if (step > 1) {
    char line[80];
    std::snprintf(line, sizeof line, "set %s %.17g, %.17g\n", name, std::pow(10.0, first_shown), std::pow(10.0, step));
    return line;
  }
  std::string lines = std::string("set ") + name + " autofreq\n";  // every decade
  int labelled = 0;
  for (int k = first; k <= last; ++k) labelled += std::pow(10.0, k) >= shown_low * (1 - 1e-9) && std::pow(10.0, k) <= shown_high * (1 + 1e-9);
  if (labelled >= 3) return lines;
  return lines + make_log_extra_labels(name, first, last, shown_low, shown_high, decades, room, axis);
}

// "set xtics …" / "set ytics …" for one panel, from the room its plot area has (`room_chars`
// across, `room_lines` down): linear ticks by choose_linear_step, log ticks by
// make_log_tics_lines, equal axes the one step of make_equal_axes.
std::string make_tics_lines(const Panel& panel, const EqualAxes& equal, double room_chars, double room_lines) {
  std::string lines;
  for (int axis = 0; axis < 2; ++axis) {
    const char* name = axis == 0 ? "xtics" : "ytics";
    const bool log = axis == 0 ? panel.log_x : panel.log_y;
    double step = 0;
    if (panel.equal_axes && !log) {
      step = equal.step;
    } else {
      const AxisExtent extent = find_tics_extent(panel, axis);
      const bool finite = extent.high >= extent.low && std::isfinite(extent.low) && std::isfinite(extent.high);
      if (finite && log && extent.low > 0) {
        lines += make_log_tics_lines(panel, name, extent, axis == 0 ? room_chars : room_lines, axis);
        continue;
      }
      if (finite && !log && extent.high > extent.low) {
        step = choose_linear_step(extent.low, extent.high, extent.extend, axis == 0 ? room_chars : room_lines, axis);
      }
    }
    if (!(step > 0)) {
      lines += std::string("set ") + name + " autofreq\n";
      continue;
    }
    char line[64];
    std::snprintf(line, sizeof line, "set %s %.10g\n", name, step);
    lines += line;
  }
  return lines;
}

// `text` with each line broken at spaces to at most `width` characters.
std::string wrap_text(const std::string& text, std::size_t width) {
  std::string out, line, word;
  auto flush_word = [&] {
    if (word.empty()) return;
    if (!line.empty() && line.size() + 1 + word.size() > width) {
      out += line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
    word.clear();
  };
  for (char c : text) {
    if (c == ' ' || c == '\n') {
      flush_word();
      if (c == '\n') {
        out += line + "\n";
        line.clear();
      }
    } else {
      word += c;
    }
  }
  flush_word();
  return out + line;
}


std::size_t count_characters(const std::string& utf8) {
  std::size_t n = 0;
  for (unsigned char c : utf8) n += (c & 0xC0) != 0x80;
  return n;
}

// `text` wrapped to as many lines as wrap_text(text, width) gives, but with lines of even length:
// the narrowest width that needs no more lines ("held-out test nMSE, joint 2, / checkpoint 5",
// not a "5" alone on the second line).
std::string wrap_balanced(const std::string& text, std::size_t width) {
  const std::string greedy = wrap_text(text, width);
  const auto lines = std::count(greedy.begin(), greedy.end(), '\n');
  if (lines == 0) return greedy;
  for (std::size_t narrower = std::max<std::size_t>(1, count_characters(text) / static_cast<std::size_t>(lines + 1)); narrower < width; ++narrower) {
    const std::string even = wrap_text(text, narrower);
    if (std::count(even.begin(), even.end(), '\n') == lines) return even;
  }
  return greedy;
}

// The grid's columns: the figure's choice, else 1 panel in 1, up to 4 in 2, more in 3.
std::size_t count_columns(const Figure& figure) {
  const std::size_t n = std::max<std::size_t>(figure.panels.size(), 1);
  if (figure.columns > 0) return std::min(figure.columns, n);
  return n <= 1 ? 1 : (n <= 4 ? 2 : 3);
}

// The lines under the legend: the table (in columns when it fits `page_chars`, else a wrapped
// line per row) and the caption's paragraphs wrapped to the page.
struct BelowBlock {
  std::vector<std::vector<std::string>> cells;  ///< the table set in columns: header, then rows
  std::vector<double> column_chars;             ///< each column's left edge, characters from the page's left
  std::vector<std::string> lines;               ///< the rest, top to bottom (rows that did not fit, the caption)
  std::size_t count_lines() const { return cells.size() + lines.size(); }
};

// Each column's width in characters: its widest cell, the header included.
std::vector<std::size_t> calc_column_widths(const FigureTable& table) {
  std::vector<std::size_t> widths(table.header.size(), 0);
  for (std::size_t c = 0; c < table.header.size(); ++c) widths[c] = count_characters(table.header[c]);
  for (const auto& row : table.rows) {
    for (std::size_t c = 0; c < row.size() && c < widths.size(); ++c) widths[c] = std::max(widths[c], count_characters(row[c]));
  }
  return widths;
}

BelowBlock make_below_block(const Figure& figure, double page_chars) {
  BelowBlock block;
  const auto width = static_cast<std::size_t>(std::max(10.0, page_chars - 2));
  const FigureTable& table = figure.table;
  if (!table.header.empty()) {
    const std::vector<std::size_t> widths = calc_column_widths(table);
    std::size_t total = 0;
    for (std::size_t w : widths) total += w + 2;
    if (static_cast<double>(total) <= page_chars - 1) {
      double x = 1;
      for (std::size_t w : widths) {
        block.column_chars.push_back(x);
        x += static_cast<double>(w) + 2;
      }
      block.cells.push_back(table.header);
      for (const auto& row : table.rows) block.cells.push_back(row);
    } else {
      for (const auto& row : table.rows) {
        std::string text;
        for (std::size_t c = 0; c < row.size(); ++c) {
          text += (c == 0 ? "" : "; ") + (c < table.header.size() && c > 0 ? table.header[c] + " " : std::string()) + row[c];
        }
        const std::string wrapped = wrap_text(text, width);
        std::istringstream in(wrapped);
        for (std::string line; std::getline(in, line);) block.lines.push_back(line);
      }
    }
  }
  for (const std::string& paragraph : figure.caption) {
    std::istringstream in(wrap_text(paragraph, width));
    for (std::string line; std::getline(in, line);) block.lines.push_back(line);
  }
  return block;
}


// The page in characters (0.55 em) across and lines (1.25 em) down, the unit of every margin
// (gnuplot takes screen fractions).
struct PageUnits {
  double chars = 0;   ///< the page's width in characters
  double char_w = 0;  ///< a character's width, a fraction of the page's
  double char_h = 0;  ///< a line's height, a fraction of the page's
};

PageUnits make_page_units(const TerminalSettings& terminal) {
  return {terminal.width_pt / (0.55 * terminal.font_pt), 0.55 * terminal.font_pt / terminal.width_pt,
          1.25 * terminal.font_pt / terminal.height_pt};
}

// Where the panels go (gnuplot's multiplot margins and spacing, screen fractions) and the room
// their titles and labels have.
struct GridLayout {
  std::size_t columns = 1, rows = 1;
  double left = 0, right = 1, bottom = 0, top = 1, row_spacing = 0;
  std::size_t label_chars = 8;                             ///< a title's or x label's wrap width
  std::size_t y_label_chars = 8, y_label_chars_inner = 8;  ///< a y label's, first column and others
  double plot_chars = 0, plot_lines = 10;                  ///< a plot area's room
  std::string figure_title;                                ///< wrapped to the page
  double below_lines = 0;                                  ///< the table and caption under the legend
  LegendLayout key;
  bool spare_cells = false;  ///< empty grid cells (7 joints on 3 × 3) hold the legend
};

// The tallest wrapped x label and panel title of the figure, in lines (0 titles when no panel
// has one: a single panel sits right under the figure's title).
std::pair<double, double> count_label_and_title_lines(const Figure& figure, std::size_t label_chars) {
  double x_label_lines = 1, title_lines = 0;
  for (const Panel& panel : figure.panels) {
    const std::string x = wrap_balanced(panel.x_label, label_chars), t = wrap_balanced(panel.title, label_chars);
    x_label_lines = std::max(x_label_lines, 1.0 + static_cast<double>(std::count(x.begin(), x.end(), '\n')));
    if (!panel.title.empty()) title_lines = std::max(title_lines, 1.0 + static_cast<double>(std::count(t.begin(), t.end(), '\n')));
  }
  return {x_label_lines, title_lines};
}

// Margins top and bottom and the room between rows: the x ticks, label and the next row's title
// between rows, the title lines on top, the legend rows, table and caption below.
void set_vertical_margins(GridLayout& grid, const Figure& figure, const TerminalSettings& terminal, const PageUnits& units) {
  std::size_t title_lines = figure.title.empty() ? 0 : 1;
  for (char c : grid.figure_title) title_lines += c == '\n';
  const auto [x_label_lines, title_lines_panel] = count_label_and_title_lines(figure, grid.label_chars);
  const std::size_t key_rows = grid.spare_cells ? 0 : grid.key.rows;
  grid.bottom = std::min(
      0.8, (3.0 + x_label_lines + terminal.key_row_lines * static_cast<double>(key_rows) + grid.below_lines) * units.char_h);
  // (2.6 lines hold a panel title's gaps; without one, 1.4 leave the top tick label its half line.)
  const double top_lines = (title_lines_panel > 0 ? 2.6 + title_lines_panel : 1.4) + 1.1 * static_cast<double>(title_lines);
  grid.top = std::max(std::min(0.95, grid.bottom + 0.15), 1 - top_lines * units.char_h);
  grid.row_spacing = std::min(0.3, (3.8 + x_label_lines + title_lines_panel) * units.char_h);
  grid.plot_lines =
      ((grid.top - grid.bottom) - grid.row_spacing * static_cast<double>(grid.rows - 1)) / static_cast<double>(grid.rows) / units.char_h;
  // A y label runs along its panel's height and past either end, beside the panel's title
  // above and the x tick labels below (both right of it), short of the figure's title, the
  // legend and the next row's label; 0.55 em a character. A label that fits is not wrapped
  // (the search plot's was, and a second line, unaccounted for, touched the tick labels).
  double beyond = std::min(1.5 + title_lines_panel, 2.5 + x_label_lines);
  if (grid.rows > 1) beyond = std::min(beyond, grid.row_spacing / units.char_h / 2 - 0.5);
  grid.y_label_chars = static_cast<std::size_t>(std::max(8.0, (grid.plot_lines + 2 * beyond) * 1.25 / 0.55));
  // Past the first column the left neighbour's last x tick label reaches under the label.
  grid.y_label_chars_inner = static_cast<std::size_t>(std::max(8.0, (grid.plot_lines + 0.4) * 1.25 / 0.55));
}

// The left margin (and the room between columns): the y tick labels and label, 12 characters,
// and each further line of a wrapped y label; from it the plot areas' width.
void set_horizontal_margins(GridLayout& grid, const Figure& figure, const PageUnits& units) {
  std::size_t y_label_lines = 1;
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    const std::string y =
        wrap_balanced(figure.panels[p].y_label, p % grid.columns == 0 ? grid.y_label_chars : grid.y_label_chars_inner);
    y_label_lines = std::max<std::size_t>(y_label_lines, 1 + static_cast<std::size_t>(std::count(y.begin(), y.end(), '\n')));
  }
  grid.left = std::min(0.3, (12 + 1.25 / 0.55 * static_cast<double>(y_label_lines - 1)) * units.char_w);
  grid.plot_chars =
      ((grid.right - grid.left) - grid.left * static_cast<double>(grid.columns - 1)) / static_cast<double>(grid.columns) / units.char_w;
}

GridLayout make_grid_layout(const Figure& figure, const TerminalSettings& terminal, const PageUnits& units, const BelowBlock& below) {
  GridLayout grid;
  const std::size_t n_panels = figure.panels.size();
  grid.columns = count_columns(figure);
  grid.rows = (std::max<std::size_t>(n_panels, 1) + grid.columns - 1) / grid.columns;
  grid.spare_cells = grid.rows * grid.columns > n_panels;
  grid.right = 1 - 3.5 * units.char_w;  // half of a last x tick label ("1000") and a gap
  // A panel's width less its y tick labels and label (12 characters left of each column); a
  // title or x label is centred on its plot area and may reach past it by the right margin (3.5
  // characters) each way before it leaves the page.
  const double panel_chars = (units.chars - 3.5) / static_cast<double>(grid.columns) - 12;
  grid.plot_chars = panel_chars;
  grid.label_chars = static_cast<std::size_t>(std::max(8.0, panel_chars + 7));
  grid.figure_title = wrap_balanced(figure.title, static_cast<std::size_t>(std::max(10.0, units.chars - 2)));
  grid.below_lines = below.count_lines() > 0 ? static_cast<double>(below.count_lines()) + 0.4 : 0.0;
  grid.key = make_legend_layout(figure, units.char_w);
  set_vertical_margins(grid, figure, terminal, units);
  set_horizontal_margins(grid, figure, units);
  return grid;
}

std::string make_preamble(const TerminalSettings& terminal, const std::string& output_path) {
  return terminal.terminal_line + "\n" + "set output " + quote_gnuplot(output_path) + "\n" + "set termoption noenhanced\n" +
         "set grid\nset key outside bottom center horizontal\n" + "set datafile missing 'nan'\n";
}

// The legend's place and the multiplot line. Column by column in the legend's rows; but gnuplot
// caps a vertical key's rows at the panel's height and spreads the rest over columns past the
// page's edges (a 60-job tracking figure showed 7 of its 13 entries), so a taller key fills row
// by row, `key.columns` to a row. The key sits on the table and caption; with spare grid cells,
// in them, bottom right.
std::string make_layout_lines(const GridLayout& grid, const Figure& figure, const TerminalSettings& terminal, const PageUnits& units) {
  std::string lines;
  char at[128];
  const std::size_t key_rows = grid.spare_cells ? 0 : grid.key.rows;
  std::snprintf(at, sizeof at, "set key at screen 0.5, screen %.4f center bottom",
                grid.below_lines > 0 ? grid.below_lines * units.char_h : 0.005);
  if (key_rows > 0 && static_cast<double>(key_rows) * terminal.key_row_lines <= grid.plot_lines) {
    lines += std::string(at) + " vertical maxrows " + std::to_string(key_rows) + "\n";
  } else if (key_rows > 0) {
    lines += std::string(at) + " horizontal maxcols " + std::to_string(grid.key.columns) + "\n";
  }
  if (grid.spare_cells) {
    std::snprintf(at, sizeof at, "set key at screen 0.97, screen %.4f right bottom vertical Left reverse\n",
                  std::max(0.06, (grid.below_lines + 0.5) * units.char_h));
    lines += at;
  }
  char margins[160];
  std::snprintf(margins, sizeof margins, " margins %.4f,%.4f,%.4f,%.4f spacing %.4f,%.4f", grid.left, grid.right, grid.bottom, grid.top,
                grid.left, grid.row_spacing);
  lines += "set multiplot layout " + std::to_string(grid.rows) + "," + std::to_string(grid.columns) + margins;
  if (!figure.title.empty()) lines += " title " + quote_gnuplot(grid.figure_title);
  return lines + "\n";
}

// The table and caption under the legend, as labels on the page drawn with the first panel:
// one per line (and per table cell), left-aligned, the last line half a line above the bottom.
std::string make_below_labels(const BelowBlock& below, const PageUnits& units) {
  std::string labels;
  const std::size_t total = below.count_lines();
  int number = 10001;  // past the edge marks' numbers
  const auto add = [&](std::size_t line, double x_chars, const std::string& text) {
    if (text.empty()) return;
    char place[96];
    std::snprintf(place, sizeof place, " at screen %.4f, screen %.4f left front\n", x_chars * units.char_w,
                  (static_cast<double>(total - 1 - line) + 0.7) * units.char_h);
    labels += "set label " + std::to_string(number++) + " " + quote_gnuplot(text) + place;
  };
  for (std::size_t r = 0; r < below.cells.size(); ++r) {
    for (std::size_t c = 0; c < below.cells[r].size() && c < below.column_chars.size(); ++c) add(r, below.column_chars[c], below.cells[r][c]);
  }
  for (std::size_t l = 0; l < below.lines.size(); ++l) add(below.cells.size() + l, 1, below.lines[l]);
  return labels;
}

// How much wider than the others an `underneath` curve is drawn.
constexpr double kUnderneathWidth = 2.5;

// The order a panel's curves are drawn in: underneath ones first, emphasised ones last (on top).
std::vector<std::size_t> make_drawing_order(const Panel& panel) {
  std::vector<std::size_t> order;
  for (int layer = 0; layer < 3; ++layer) {
    for (std::size_t c = 0; c < panel.curves.size(); ++c) {
      const Curve& curve = panel.curves[c];
      if ((curve.underneath && !curve.emphasised ? 0 : curve.emphasised ? 2 : 1) == layer) order.push_back(c);
    }
  }
  return order;
}

// Every curve's look ("with … lc … dt …") and the figure's one legend: an entry per distinct
// title, in the order the curves are declared (emphasised ones last), drawn once by the first panel (keyentry) with its
// curve's look, so that entries first seen in later panels do not land on the first's.
struct CurveLooks {
  std::vector<std::vector<std::string>> looks;  ///< [panel][curve]
  std::vector<std::pair<std::string, std::string>> legend;  ///< title, look
};

// A curve's look with colour `colour` (an index into figure_colours(); past 12 the colours repeat dashed).
std::string make_curve_look(const Curve& curve, std::size_t colour, double line_width) {
  char width[32];
  std::snprintf(width, sizeof width, "%g", line_width * (curve.underneath ? kUnderneathWidth : 1.0));
  const std::string lw = width;
  std::string look;
  switch (curve.style) {
    case Curve::Style::lines: look = "with lines lw " + lw; break;
    case Curve::Style::points: look = "with points pt 7 ps 0.6"; break;
    case Curve::Style::lines_points: look = "with linespoints lw " + lw + " pt 7 ps 0.7"; break;
    case Curve::Style::error_bars: look = "with yerrorlines lw " + lw + " pt 7 ps 0.7"; break;
    case Curve::Style::band: look = "with filledcurves fs transparent solid 0.25 noborder"; break;
  }
  if (curve.emphasised) return look + " lc rgb '#000000' dt 2";
  const auto& colours = figure_colours();
  return look + " lc rgb '" + colours[colour % colours.size()] + "' dt " + std::to_string(1 + colour / colours.size());
}

CurveLooks make_curve_looks(const Figure& figure, double line_width) {
  CurveLooks result;
  // A colour per distinct title over the whole figure, in first-declared order, so that one group
  // has one colour in every panel (and the feedback, feed-forward and composite torques the
  // palette's first three wherever the composite is drawn); untitled curves take the next free colour each.
  std::vector<std::string> colour_titles;
  const auto colour_of = [&](const std::string& title) {
    if (!title.empty()) {
      const auto found = std::find(colour_titles.begin(), colour_titles.end(), title);
      if (found != colour_titles.end()) return static_cast<std::size_t>(found - colour_titles.begin());
    }
    colour_titles.push_back(title);
    return colour_titles.size() - 1;
  };
  const auto listed = [&](const std::string& title) {
    return std::any_of(result.legend.begin(), result.legend.end(), [&](const auto& entry) { return entry.first == title; });
  };
  for (const Panel& panel : figure.panels) {
    std::vector<std::string>& looks = result.looks.emplace_back(panel.curves.size());
    for (std::size_t c = 0; c < panel.curves.size(); ++c) {
      const Curve& curve = panel.curves[c];
      looks[c] = make_curve_look(curve, curve.emphasised ? 0 : colour_of(curve.title), line_width);
    }
    for (const bool emphasised : {false, true}) {  // the emphasised (drawn on top) last
      for (std::size_t c = 0; c < panel.curves.size(); ++c) {
        const Curve& curve = panel.curves[c];
        if (curve.emphasised == emphasised && !curve.title.empty() && !listed(curve.title)) result.legend.emplace_back(curve.title, looks[c]);
      }
    }
    if (!panel.edge_marks_x.empty() && !panel.edge_mark_title.empty() && !listed(panel.edge_mark_title)) {
      result.legend.emplace_back(panel.edge_mark_title, "with points pt 11 ps 1.4 lc rgb '" + figure_edge_mark_colour() + "'");
    }
  }
  return result;
}

// A panel's ticks, title, labels, scales and ranges. A square panel (equal axes) has the smaller
// side's room both ways.
std::string make_panel_setup(const Panel& panel, std::size_t p, const GridLayout& grid) {
  const double side_em = std::min(grid.plot_chars * 0.55, grid.plot_lines * 1.25);
  const double room_chars = panel.equal_axes ? side_em / 0.55 : grid.plot_chars;
  const double room_lines = panel.equal_axes ? side_em / 1.25 : grid.plot_lines;
  const EqualAxes equal = panel.equal_axes ? make_equal_axes(panel, room_chars, room_lines) : EqualAxes{};
  std::ostringstream script;
  script << make_tics_lines(panel, equal, room_chars, room_lines);
  // gnuplot centres a wrapped y label's lines on the place of one, so that the last runs into
  // the tick labels ("(count)" on "1e+03"): each further line moves it left by about a line.
  const std::string y_label = wrap_balanced(panel.y_label, p % grid.columns == 0 ? grid.y_label_chars : grid.y_label_chars_inner);
  const auto y_lines = 1 + std::count(y_label.begin(), y_label.end(), '\n');
  script << "set title " << quote_gnuplot(wrap_balanced(panel.title, grid.label_chars)) << "\n"
         << "set xlabel " << quote_gnuplot(wrap_balanced(panel.x_label, grid.label_chars)) << "\n"
         << "set ylabel " << quote_gnuplot(y_label) << " offset " << -1.3 * static_cast<double>(y_lines - 1) << ",0\n"
         << (panel.log_x ? "set logscale x\nset format x '%g'\n" : "unset logscale x\nset format x '%g'\n")
         << (panel.log_y ? "set logscale y\nset format y '%.0e'\n" : "unset logscale y\nset format y '%g'\n")
         << (panel.equal_axes ? "set size ratio -1\n" : "set size noratio\n") << make_range_lines(panel, equal);
  return script.str();
}

// The marks of jobs without a value on the panel's top edge: graph coordinates in y, so they sit
// on the frame whatever the data's range.
std::string make_edge_mark_labels(const Panel& panel) {
  std::string labels;
  for (std::size_t m = 0; m < panel.edge_marks_x.size(); ++m) {
    char label[160];
    std::snprintf(label, sizeof label, "set label %zu '' at first %.17g, graph 1 point pt 11 ps 1.4 lc rgb '%s' front\n", m + 1,
                  panel.edge_marks_x[m], figure_edge_mark_colour().c_str());
    labels += label;
  }
  return labels;
}

// The panel's plot command: its curves in drawing order, untitled, and on the first panel the
// figure's legend as key entries.
std::string make_plot_command(const Figure& figure, std::size_t p, const CurveLooks& looks, const std::string& data_dir) {
  const Panel& panel = figure.panels[p];
  std::ostringstream script;
  script << "plot ";
  const std::vector<std::size_t> order = make_drawing_order(panel);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::size_t c = order[i];
    const Curve& curve = panel.curves[c];
    const std::string file = (std::filesystem::path(data_dir) / data_file_name(p, c)).string();
    script << (i ? ", \\\n     " : "") << quote_gnuplot(file)
           << (curve.style == Curve::Style::error_bars ? " using 1:2:3:4 "
               : curve.style == Curve::Style::band     ? " using 1:3:4 "
                                                       : " using 1:2 ")
           << looks.looks[p][c] << " notitle";
  }
  if (p == 0) {
    for (std::size_t e = 0; e < looks.legend.size(); ++e) {
      script << (order.empty() && e == 0 ? "" : ", \\\n     ") << "keyentry " << looks.legend[e].second << " title "
             << quote_gnuplot(looks.legend[e].first);
    }
  }
  if (order.empty() && (p != 0 || looks.legend.empty())) script << "keyentry notitle";  // a plot command needs an element
  script << "\n";
  return script.str();
}

}  // namespace

const std::vector<std::string>& figure_colours() {
  // Paul Tol's high-contrast scheme first (blue, yellow, red: apart in greyscale, L* 29 / 72 / 50,
  // and for every colour vision), so that feedback, feed-forward and composite torque read apart
  // in print; then the colours of his bright and muted schemes and Okabe and Ito's that stand
  // furthest from those already chosen (CIELAB distance under normal, protan, deutan and tritan
  // vision; tests/analysis/figure_test.cpp checks it).
  static const std::vector<std::string> colours = {"#004488", "#DDAA33", "#BB5566", "#33BBEE", "#4477AA", "#882255",
                                                   "#CC79A7", "#999933", "#228833", "#332288", "#EE6677", "#AA4499"};
  return colours;
}

const std::string& figure_edge_mark_colour() {
  static const std::string colour = "#CC3311";  // Tol's vibrant red
  return colour;
}

std::string make_gnuplot_script(const Figure& figure, const TerminalSettings& terminal, const std::string& output_path,
                                const std::string& data_dir) {
  const PageUnits units = make_page_units(terminal);
  const BelowBlock below = make_below_block(figure, units.chars);
  const GridLayout grid = make_grid_layout(figure, terminal, units, below);
  const CurveLooks looks = make_curve_looks(figure, terminal.line_width);
  std::ostringstream script;
  script << make_preamble(terminal, output_path) << make_layout_lines(grid, figure, terminal, units);
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    script << make_panel_setup(figure.panels[p], p, grid) << "unset label\n";
    if (p == 0) script << make_below_labels(below, units);
    script << make_edge_mark_labels(figure.panels[p]) << make_plot_command(figure, p, looks, data_dir);
  }
  script << "unset multiplot\n";
  script << "set output\n";
  return script.str();
}

FigureStyle parse_figure_style(const std::string& word) {
  if (word == "paper") return FigureStyle::paper;
  if (word == "slide") return FigureStyle::slide;
  if (word == "screen") return FigureStyle::screen;
  throw AnalysisError("unknown figure style '" + word + "' (paper, slide or screen)");
}

namespace {

enum class Format { pdf, svg, png };

Format find_format(const std::string& out_path) {
  if (ends_with(out_path, ".pdf")) return Format::pdf;
  if (ends_with(out_path, ".svg")) return Format::svg;
  if (ends_with(out_path, ".png")) return Format::png;
  throw AnalysisError(out_path + ": the output must end in .pdf, .svg or .png");
}

// A style's page before the text under and over the panels is added: inches, points.
struct StylePage {
  double width = 0, height = 0, font = 0, line_width = 0;
};

StylePage make_style_page(FigureStyle style, std::size_t n_panels, std::size_t columns, std::size_t rows) {
  switch (style) {
    case FigureStyle::paper:
      // Panels stacked in one column (time series) are full width and need less height each.
      return {columns >= 3 ? 7.0 : 3.5, n_panels <= 1 ? 2.8 : 0.6 + (columns == 1 ? 1.45 : 1.9) * static_cast<double>(rows), 8, 1.0};
    case FigureStyle::slide:
      // A 3 × 3 grid on one slide needs small print.
      return {10.0, 5.625, static_cast<double>(rows >= 3 ? 10 : rows == 2 ? 12 : 16), 2.5};
    case FigureStyle::automatic:
    case FigureStyle::screen: break;
  }
  return {1000.0 / 96, 700.0 / 96, 12 * 72.0 / 96, 2.0};  // 1000 × 700 px at 12 px
}

// The height (inches) the figure's text adds to a page `width` wide at `font`: the legend's rows
// below the panels (unless spare grid cells hold it), so that many entries do not squeeze the
// panels; the title's lines past two (its notes); the table and caption under the legend. In
// every style: a slide that kept its 16:9 page clipped its caption and crowded its panels.
double calc_text_height(const Figure& figure, double width, double font, double key_row_lines) {
  const std::size_t columns = count_columns(figure);
  const std::size_t rows = (std::max<std::size_t>(figure.panels.size(), 1) + columns - 1) / columns;
  double height = 0;
  if (rows * columns == figure.panels.size()) {
    const LegendLayout legend = make_legend_layout(figure, 0.55 * font / (width * 72));
    height += key_row_lines * 1.25 * font * static_cast<double>(legend.rows) / 72;
  }
  const std::string title = wrap_balanced(figure.title, static_cast<std::size_t>(std::max(10.0, width * 72 / (0.55 * font) - 2)));
  const auto lines = static_cast<double>(std::count(title.begin(), title.end(), '\n')) + (title.empty() ? 0 : 1);
  height += 1.1 * 1.25 * font * std::max(0.0, lines - 2) / 72;
  const std::size_t below = make_below_block(figure, width * 72 / (0.55 * font)).count_lines();
  if (below > 0) height += 1.25 * font * (static_cast<double>(below) + 0.4) / 72;
  return height;
}

// The height (inches, before the text under the panels) at which square panels (equal axes)
// fill their plot areas, which are as wide as the grid's columns leave them: the margins and
// gaps of set_vertical_margins and set_horizontal_margins for one-line labels and titles.
double calc_square_panels_height(std::size_t columns, std::size_t rows, double width, double font) {
  const double char_w = 0.55 * font / 72, line = 1.25 * font / 72;  // inches
  const double left = 12 * char_w, right = 3.5 * char_w;
  const double side = (width - right - left * static_cast<double>(columns)) / static_cast<double>(columns);
  const double lines = (2.6 + 1 + 1.1) + (3.0 + 1) + (3.8 + 1 + 1) * static_cast<double>(rows - 1);
  return static_cast<double>(rows) * side + lines * line;
}

std::string make_terminal_line(Format format, double width, double height, double font) {
  char line[256];
  switch (format) {
    case Format::pdf:
      // pdfcairo: inches and points.
      std::snprintf(line, sizeof line, "set terminal pdfcairo size %.3fin,%.3fin font 'sans,%g' linewidth 1", width, height, font);
      break;
    case Format::svg:
      // 72 user units per inch: the font stands to the width as in the PDF.
      std::snprintf(line, sizeof line, "set terminal svg size %d,%d dynamic background rgb 'white' font 'sans,%g'",
                    static_cast<int>(std::lround(width * 72)), static_cast<int>(std::lround(height * 72)), font);
      break;
    case Format::png:
      // 300 dpi; pngcairo draws a point as a pixel at 96 dpi, so fonts and lines scale by 300/96.
      std::snprintf(line, sizeof line, "set terminal pngcairo size %d,%d font 'sans,%g' linewidth %g",
                    static_cast<int>(std::lround(width * 300)), static_cast<int>(std::lround(height * 300)), font * 300 / 96,
                    300.0 / 96);
      break;
  }
  return line;
}

// The style `options` ask for, automatic resolved by the format: paper for PDF and PNG, screen for SVG.
FigureStyle resolve_style(const std::string& out_path, const FigureOptions& options) {
  if (options.style != FigureStyle::automatic) return options.style;
  return find_format(out_path) == Format::svg ? FigureStyle::screen : FigureStyle::paper;
}

}  // namespace

TerminalSettings make_terminal_settings(const std::string& out_path, const FigureOptions& options, const Figure& figure) {
  const Format format = find_format(out_path);
  const FigureStyle style = resolve_style(out_path, options);
  const std::size_t columns = count_columns(figure);
  const std::size_t rows = (std::max<std::size_t>(figure.panels.size(), 1) + columns - 1) / columns;
  StylePage page = make_style_page(style, figure.panels.size(), columns, rows);
  const double width = options.width_in.value_or(page.width);
  const double font = options.font_pt.value_or(page.font);
  // A paper figure of square panels is no taller than its squares need (figure 6.11's rows stood
  // in 0.8 in of blank each): the plot areas, as wide as the columns leave them, are as tall.
  const bool all_square = !figure.panels.empty() &&
                          std::all_of(figure.panels.begin(), figure.panels.end(), [](const Panel& panel) { return panel.equal_axes; });
  if (style == FigureStyle::paper && all_square) page.height = std::min(page.height, calc_square_panels_height(columns, rows, width, font));
  const double key_row_lines = format == Format::svg ? 1.25 : 1.0;
  const double height = options.height_in ? *options.height_in : page.height + calc_text_height(figure, width, font, key_row_lines);
  if (!(width > 0 && height > 0 && font > 0 && width <= 100 && height <= 100 && font <= 200)) {
    throw AnalysisError(out_path + ": size and font size must be positive (at most 100 in and 200 pt)");
  }
  return {make_terminal_line(format, width, height, font), page.line_width, width * 72, height * 72, font, key_row_lines};
}

Figure arrange_for_style(Figure figure, FigureStyle style) {
  const std::size_t n = figure.panels.size();
  if (style == FigureStyle::slide && figure.columns == 1 && n >= 3) figure.columns = n <= 3 ? n : (n + 1) / 2;
  return figure;
}

bool spans_decades(const std::vector<double>& values) {
  double low = INFINITY, high = 0.0;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    if (v <= 0.0) return false;
    low = std::min(low, v);
    high = std::max(high, v);
  }
  return high > 0.0 && high / low >= 20.0;
}

Figure remove_caption(Figure figure) {
  figure.caption.clear();
  figure.table = {};
  return figure;
}

std::string format_caption_text(const Figure& figure) {
  std::string text;
  const FigureTable& table = figure.table;
  if (!table.header.empty()) {
    const std::vector<std::size_t> widths = calc_column_widths(table);
    const auto add_row = [&](const std::vector<std::string>& cells) {
      std::string line;
      for (std::size_t c = 0; c < cells.size(); ++c) {
        const std::size_t pad = c + 1 < cells.size() && c < widths.size() ? widths[c] + 2 - count_characters(cells[c]) : 0;
        line += cells[c] + std::string(pad, ' ');
      }
      text += line + "\n";
    };
    add_row(table.header);
    for (const auto& row : table.rows) add_row(row);
  }
  for (const std::string& paragraph : figure.caption) text += paragraph + "\n";
  return text;
}

namespace {

// Each curve's points as data_<panel>_<curve>.dat in `work`: x y, or x y low high for bars and bands.
void write_data_files(const Figure& figure, const std::filesystem::path& work) {
  for (std::size_t p = 0; p < figure.panels.size(); ++p) {
    for (std::size_t c = 0; c < figure.panels[p].curves.size(); ++c) {
      const Curve& curve = figure.panels[p].curves[c];
      std::ofstream data(work / data_file_name(p, c));
      char line[128];
      for (std::size_t i = 0; i < curve.x.size() && i < curve.y.size(); ++i) {
        if (curve.style == Curve::Style::error_bars || curve.style == Curve::Style::band) {
          const double low = i < curve.y_low.size() ? curve.y_low[i] : curve.y[i];
          const double high = i < curve.y_high.size() ? curve.y_high[i] : curve.y[i];
          std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g\n", curve.x[i], curve.y[i], low, high);
        } else {
          std::snprintf(line, sizeof line, "%.17g %.17g\n", curve.x[i], curve.y[i]);
        }
        data << line;
      }
    }
  }
}

// Why gnuplot failed: the first error line of its log (warnings, such as the key's fitting, come first).
std::string read_gnuplot_failure(const std::filesystem::path& log_path) {
  std::ifstream log(log_path);
  std::string line, reason;
  while (std::getline(log, line)) {
    if (line.empty()) continue;
    if (reason.empty()) reason = line;
    if (line.find(" line ") != std::string::npos && line.find("warning:") == std::string::npos) {
      reason = line;
      break;
    }
  }
  if (reason.size() > 300) reason = reason.substr(0, 300) + "...";
  return reason;
}

// Copies `rendered` next to `out_path` and renames it there: the file is whole or absent.
void publish_rendered(const std::filesystem::path& rendered, const std::string& out_path) {
  namespace fs = std::filesystem;
  const fs::path destination = fs::absolute(out_path);
  const fs::path partial = destination.string() + ".partial";
  std::error_code error;
  fs::copy_file(rendered, partial, fs::copy_options::overwrite_existing, error);
  if (!error) fs::rename(partial, destination, error);
  if (error) {
    std::error_code ignored;
    fs::remove(partial, ignored);
    throw AnalysisError(out_path + ": cannot write: " + error.message());
  }
}

}  // namespace

void write_figure(const Figure& figure, const std::string& out_path, const FigureOptions& options) {
  if (!options.caption && (!figure.caption.empty() || !figure.table.header.empty())) {
    FigureOptions drawn = options;
    drawn.caption = true;
    return write_figure(remove_caption(figure), out_path, drawn);
  }
  const FigureStyle style = resolve_style(out_path, options);
  if (style == FigureStyle::slide && figure.columns == 1 && figure.panels.size() >= 3) {
    return write_figure(arrange_for_style(figure, style), out_path, options);
  }
  const TerminalSettings terminal = make_terminal_settings(out_path, options, figure);
  if (figure.panels.empty()) throw AnalysisError(out_path + ": nothing to plot");
  for (const Panel& panel : figure.panels) {
    bool any = false;
    for (const Curve& curve : panel.curves) any = any || !curve.x.empty();
    if (!any) throw AnalysisError(out_path + ": panel '" + panel.title + "' has no data");
  }

  namespace fs = std::filesystem;
  std::string pattern = (fs::temp_directory_path() / "armfarm-plot-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw AnalysisError("cannot create a temporary directory for gnuplot");
  const fs::path work(pattern);
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  } cleanup{work};
  write_data_files(figure, work);
  // gnuplot writes into the work folder, whose name we chose; the user's path never reaches its
  // script. The result is copied next to the destination and renamed: whole or absent.
  const fs::path rendered =
      work / (ends_with(out_path, ".svg") ? "figure.svg" : ends_with(out_path, ".pdf") ? "figure.pdf" : "figure.png");
  {
    std::ofstream script_file(work / "plot.gp");
    script_file << make_gnuplot_script(figure, terminal, rendered.string(), work.string());
  }
  const int status = run_gnuplot((work / "plot.gp").string(), (work / "gnuplot.log").string());
  if (status == -1 && errno == ENOENT) {
    throw AnalysisError("gnuplot is not installed (Debian package gnuplot-nox; `make deps` installs it)");
  }
  if (status != 0 || !fs::exists(rendered)) {
    const std::string reason = read_gnuplot_failure(work / "gnuplot.log");
    throw AnalysisError(out_path + ": gnuplot failed" + (reason.empty() ? "" : ": " + make_printable_text(reason)));
  }
  publish_rendered(rendered, out_path);
}

}  // namespace armfarm
