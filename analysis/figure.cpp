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

// With equal axes: both axes span the same length (the larger data range and 5 % more) about
// their data's centres, so that the panel is square and its ticks have one spacing.
std::pair<double, double> find_equal_axis_range(const Panel& panel, int axis) {
  const auto [x_low, x_high] = find_data_range(panel, 0);
  const auto [y_low, y_high] = find_data_range(panel, 1);
  if (!(x_high >= x_low) || !(y_high >= y_low)) return find_data_range(panel, axis);
  const double half = std::max({x_high - x_low, y_high - y_low, 1e-9}) * 0.525;
  const double centre = axis == 0 ? (x_low + x_high) / 2 : (y_low + y_high) / 2;
  return {centre - half, centre + half};
}

// The x axis's range, always explicit: equal axes as above; a time axis (tight_x) from the data's
// first to its last x (or from x_min); otherwise the data padded by 5 % of its span each side (of
// its decades on a log axis), so that no point or error bar sits on the frame. Empty: no data.
std::optional<std::pair<double, double>> find_x_axis_range(const Panel& panel) {
  if (panel.equal_axes) return find_equal_axis_range(panel, 0);
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

std::string make_range_lines(const Panel& panel) {
  std::string lines;
  char line[160];
  const auto x = find_x_axis_range(panel);
  if (x) {
    std::snprintf(line, sizeof line, "set xrange [%.17g:%.17g]\n", x->first, x->second);
    lines += line;
  } else {
    lines += "set autoscale x\n";
  }
  if (panel.equal_axes) {
    const auto [y_low, y_high] = find_equal_axis_range(panel, 1);
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

// "set xtics …" / "set ytics …" for one panel, from the room its plot area has (`room_chars`
// across, `room_lines` down): linear ticks by choose_linear_step (equal axes take the coarser
// of the two steps, so both have one spacing); a log axis labels every decade when they fit, else
// every k-th decade from the lowest the axis reaches ("set xtics 10^first, 10^k"; a bare factor
// counts from 1, not from the data, and left a single label on a narrow panel over 0.01-3). A
// log axis showing fewer than three decade labels also labels 2 and 5 (or 3) of each decade.
std::string make_tics_lines(const Panel& panel, double room_chars, double room_lines) {
  std::string lines;
  double linear_steps[2] = {0, 0};
  for (int axis = 0; axis < 2; ++axis) {
    const char* name = axis == 0 ? "xtics" : "ytics";
    const double room = axis == 0 ? room_chars : room_lines;
    double low = INFINITY, high = -INFINITY;
    bool extend = false;  // gnuplot extends the axis to its next ticks
    if (axis == 0) {
      const auto range = find_x_axis_range(panel);
      if (range) std::tie(low, high) = *range;
    } else if (panel.equal_axes) {
      std::tie(low, high) = find_equal_axis_range(panel, 1);
    } else {
      std::tie(low, high) = find_data_range(panel, 1);
      if (panel.y_min) low = std::min(low, *panel.y_min);
      extend = true;
    }
    const bool log = axis == 0 ? panel.log_x : panel.log_y;
    if (!(high >= low) || !std::isfinite(low) || !std::isfinite(high) || (log && !(low > 0))) {
      lines += std::string("set ") + name + " autofreq\n";
      continue;
    }
    if (log) {
      const int first = static_cast<int>(std::floor(std::log10(low) + 1e-9));
      const int last = std::max(first + 1, static_cast<int>(std::ceil(std::log10(high) - 1e-9)));
      // The axis as drawn: gnuplot's autoscale ends a log axis on whole decades (y_min fixes the low end).
      const double shown_low = extend && !panel.y_min ? std::pow(10.0, first) : low;
      const double shown_high = extend ? std::pow(10.0, last) : high;
      const double decades = std::log10(shown_high / shown_low);
      // The lowest decade on the axis as drawn: labels count from it (from a decade below the
      // axis, every other label fell outside a padded 0.0075-4 axis and left one).
      const int first_shown = static_cast<int>(std::ceil(std::log10(shown_low) - 1e-9));
      int step = 1;
      for (; step < last - first; ++step) {
        double needed = 1.6;  // lines between two y labels
        if (axis == 0) {      // characters between two x labels' centres: the widest and a gap
          std::size_t widest = 0;
          for (int k = first_shown; std::pow(10.0, k) <= shown_high * (1 + 1e-9); k += step) {
            widest = std::max(widest, count_label_chars(std::pow(10.0, k)));
          }
          needed = static_cast<double>(widest) + 1;
        }
        if (room * step / decades >= needed) break;
      }
      if (step > 1) {
        char line[80];
        std::snprintf(line, sizeof line, "set %s %.17g, %.17g\n", name, std::pow(10.0, first_shown), std::pow(10.0, step));
        lines += line;
        continue;
      }
      lines += std::string("set ") + name + " autofreq\n";  // every decade
      int labelled = 0;
      for (int k = first; k <= last; ++k) labelled += std::pow(10.0, k) >= shown_low * (1 - 1e-9) && std::pow(10.0, k) <= shown_high * (1 + 1e-9);
      if (labelled >= 3) continue;
      // 1, 2, 5 (the nearest labels 0.3 decades apart) or 1, 3 (0.48) where they fit.
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
        lines += std::string("set ") + name + " add (" + added + ")\n";
        break;
      }
      continue;
    }
    if (!(high > low)) {
      lines += std::string("set ") + name + " autofreq\n";
      continue;
    }
    linear_steps[axis] = choose_linear_step(low, high, extend, room, axis);
  }
  // Equal axes share the coarser step, unless it leaves an axis with a single label (a flat
  // path's short side): that axis keeps its own.
  if (panel.equal_axes && linear_steps[0] > 0 && linear_steps[1] > 0) {
    const double shared = std::max(linear_steps[0], linear_steps[1]);
    for (int axis = 0; axis < 2; ++axis) {
      const auto [low, high] = find_equal_axis_range(panel, axis);
      const double labels = std::floor(high / shared + 1e-9) - std::ceil(low / shared - 1e-9) + 1;
      if (labels >= 2) linear_steps[axis] = shared;
    }
  }
  for (int axis = 0; axis < 2; ++axis) {
    if (!(linear_steps[axis] > 0)) continue;
    char line[64];
    std::snprintf(line, sizeof line, "set %s %.10g\n", axis == 0 ? "xtics" : "ytics", linear_steps[axis]);
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

BelowBlock make_below_block(const Figure& figure, double page_chars) {
  BelowBlock block;
  const auto width = static_cast<std::size_t>(std::max(10.0, page_chars - 2));
  const FigureTable& table = figure.table;
  if (!table.header.empty()) {
    std::vector<std::size_t> widths(table.header.size(), 0);
    for (std::size_t c = 0; c < table.header.size(); ++c) widths[c] = count_characters(table.header[c]);
    for (const auto& row : table.rows) {
      for (std::size_t c = 0; c < row.size() && c < widths.size(); ++c) widths[c] = std::max(widths[c], count_characters(row[c]));
    }
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

}  // namespace

std::string make_gnuplot_script(const Figure& figure, const TerminalSettings& terminal, const std::string& output_path,
                                const std::string& data_dir) {
  const std::string& terminal_line = terminal.terminal_line;
  const double line_width = terminal.line_width;
  const std::size_t n_panels = figure.panels.size();
  const std::size_t columns = count_columns(figure);
  const std::size_t rows = (std::max<std::size_t>(n_panels, 1) + columns - 1) / columns;
  // The page in characters (0.55 em) across and lines (1.25 em) down; a panel's width less its
  // y tick labels and label (12 characters left of each column): room for wrapped titles and labels.
  const double page_chars = terminal.width_pt / (0.55 * terminal.font_pt);
  const double char_w = 0.55 * terminal.font_pt / terminal.width_pt;
  const double char_h = 1.25 * terminal.font_pt / terminal.height_pt;
  const double right = 1 - 3.5 * char_w;  // half of a last x tick label ("1000") and a gap
  const double panel_chars = (page_chars - 3.5) / static_cast<double>(columns) - 12;
  // A title or x label is centred on its plot area and may reach past it by the right margin
  // (3.5 characters) each way before it leaves the page.
  const std::size_t label_chars = static_cast<std::size_t>(std::max(8.0, panel_chars + 7));
  std::size_t y_label_chars = 8, y_label_chars_inner = 8;  // set below from the panels' height (first column, others)
  double plot_chars = panel_chars, plot_lines = 10;       // a plot area's room, set below
  const std::string figure_title = wrap_balanced(figure.title, static_cast<std::size_t>(std::max(10.0, page_chars - 2)));
  const BelowBlock below = make_below_block(figure, page_chars);
  const double below_lines = below.count_lines() > 0 ? static_cast<double>(below.count_lines()) + 0.4 : 0.0;
  std::ostringstream script;
  char width_text[32];
  std::snprintf(width_text, sizeof width_text, "%g", line_width);
  const std::string lw = width_text;
  script << terminal_line << "\n"
         << "set output " << quote_gnuplot(output_path) << "\n"
         << "set termoption noenhanced\n"
         << "set grid\nset key outside bottom center horizontal\n"
         << "set datafile missing 'nan'\n";
  // With empty grid cells (7 joints on 3 × 3) the legend goes into them, bottom right.
  const bool spare_cells = rows * columns > n_panels;
  {
    std::string layout = "set multiplot layout " + std::to_string(rows) + "," + std::to_string(columns);
    // Margins and spacing in character units of this page (gnuplot takes screen fractions):
    // room for the y tick labels and label left of every column, the x ticks, label and the
    // next row's title between rows, the title lines on top, the legend rows, table and caption below.
    {
      const LegendLayout key = make_legend_layout(figure, char_w);
      const std::size_t key_rows = spare_cells ? 0 : key.rows;
      std::size_t title_lines = figure.title.empty() ? 0 : 1;
      for (char c : figure_title) title_lines += c == '\n';
      // The tallest wrapped x label and panel title set the room between rows (no line for
      // titles when no panel has one: a single panel under the figure's title).
      double x_label_lines = 1, title_lines_panel = 0;
      for (const Panel& panel : figure.panels) {
        const std::string x = wrap_balanced(panel.x_label, label_chars), t = wrap_balanced(panel.title, label_chars);
        x_label_lines = std::max(x_label_lines, 1.0 + static_cast<double>(std::count(x.begin(), x.end(), '\n')));
        if (!panel.title.empty()) {
          title_lines_panel = std::max(title_lines_panel, 1.0 + static_cast<double>(std::count(t.begin(), t.end(), '\n')));
        }
      }
      const double bottom =
          std::min(0.8, (3.0 + x_label_lines + terminal.key_row_lines * static_cast<double>(key_rows) + below_lines) * char_h);
      // (2.6 lines hold a panel title's gaps; without one, 1.4 leave the top tick label its half line.)
      const double top_lines = (title_lines_panel > 0 ? 2.6 + title_lines_panel : 1.4) + 1.1 * static_cast<double>(title_lines);
      const double top = std::max(std::min(0.95, bottom + 0.15), 1 - top_lines * char_h);
      const double row_spacing = std::min(0.3, (4.8 + x_label_lines + title_lines_panel) * char_h);
      // A y label runs along its panel's height and past either end, beside the panel's title
      // above and the x tick labels below (both right of it), short of the figure's title, the
      // legend and the next row's label; 0.55 em a character. A label that fits is not wrapped
      // (the search plot's was, and a second line, unaccounted for, touched the tick labels).
      plot_lines = ((top - bottom) - row_spacing * static_cast<double>(rows - 1)) / static_cast<double>(rows) / char_h;
      double beyond = std::min(1.5 + title_lines_panel, 2.5 + x_label_lines);
      if (rows > 1) beyond = std::min(beyond, row_spacing / char_h / 2 - 0.5);
      y_label_chars = static_cast<std::size_t>(std::max(8.0, (plot_lines + 2 * beyond) * 1.25 / 0.55));
      // Past the first column the left neighbour's last x tick label reaches under the label.
      y_label_chars_inner = static_cast<std::size_t>(std::max(8.0, (plot_lines + 0.4) * 1.25 / 0.55));
      // Each further line of a wrapped y label widens the room left of every column.
      std::size_t y_label_lines = 1;
      for (std::size_t p = 0; p < figure.panels.size(); ++p) {
        const std::string y = wrap_balanced(figure.panels[p].y_label, p % columns == 0 ? y_label_chars : y_label_chars_inner);
        y_label_lines = std::max<std::size_t>(y_label_lines, 1 + static_cast<std::size_t>(std::count(y.begin(), y.end(), '\n')));
      }
      const double left = std::min(0.3, (12 + 1.25 / 0.55 * static_cast<double>(y_label_lines - 1)) * char_w);
      plot_chars = ((right - left) - left * static_cast<double>(columns - 1)) / static_cast<double>(columns) / char_w;
      char margins[160];
      std::snprintf(margins, sizeof margins, " margins %.4f,%.4f,%.4f,%.4f spacing %.4f,%.4f", left, right, bottom, top, left,
                    row_spacing);
      layout += margins;
      // Column by column in `key_rows` rows; but gnuplot caps a vertical key's rows at the
      // panel's height and spreads the rest over columns past the page's edges (a 60-job
      // tracking figure showed 7 of its 13 entries), so a taller key fills row by row,
      // `key.columns` to a row. The key sits on the table and caption.
      char at[96];
      std::snprintf(at, sizeof at, "set key at screen 0.5, screen %.4f center bottom", below_lines > 0 ? below_lines * char_h : 0.005);
      if (key_rows > 0 && static_cast<double>(key_rows) * terminal.key_row_lines <= plot_lines) {
        script << at << " vertical maxrows " << key_rows << "\n";
      } else if (key_rows > 0) {
        script << at << " horizontal maxcols " << key.columns << "\n";
      }
      if (spare_cells) {
        std::snprintf(at, sizeof at, "set key at screen 0.97, screen %.4f right bottom vertical Left reverse\n",
                      std::max(0.06, (below_lines + 0.5) * char_h));
        script << at;
      }
    }
    if (!figure.title.empty()) layout += " title " + quote_gnuplot(figure_title);
    script << layout << "\n";
  }
  // The table and caption under the legend, as labels on the page drawn with the first panel:
  // one per line (and per table cell), left-aligned, the last line half a line above the bottom.
  std::string below_labels;
  {
    const std::size_t total = below.count_lines();
    int number = 10001;  // past the edge marks' numbers
    const auto add = [&](std::size_t line, double x_chars, const std::string& text) {
      if (text.empty()) return;
      char place[96];
      std::snprintf(place, sizeof place, " at screen %.4f, screen %.4f left front\n", x_chars * char_w,
                    (static_cast<double>(total - 1 - line) + 0.7) * char_h);
      below_labels += "set label " + std::to_string(number++) + " " + quote_gnuplot(text) + place;
    };
    for (std::size_t r = 0; r < below.cells.size(); ++r) {
      for (std::size_t c = 0; c < below.cells[r].size() && c < below.column_chars.size(); ++c) add(r, below.column_chars[c], below.cells[r][c]);
    }
    for (std::size_t l = 0; l < below.lines.size(); ++l) add(below.cells.size() + l, 1, below.lines[l]);
  }
  // A red that none of the curves' colours is close to, for the marks of jobs without a value.
  static const char* const kEdgeMarkColour = "#CC3311";
  // Paul Tol's "muted" and "bright" schemes: distinguishable, also in greyscale print.
  static const char* const kColours[12] = {"#332288", "#88CCEE", "#44AA99", "#117733", "#999933", "#DDCC77",
                                           "#CC6677", "#882255", "#AA4499", "#4477AA", "#EE6677", "#000000"};
  // A colour per distinct title over the whole figure, in first-seen order, so that one group
  // has one colour in every panel; untitled curves take the next free colour each.
  std::vector<std::string> colour_titles;
  auto colour_of = [&](const std::string& title) {
    if (!title.empty()) {
      const auto found = std::find(colour_titles.begin(), colour_titles.end(), title);
      if (found != colour_titles.end()) return static_cast<std::size_t>(found - colour_titles.begin());
    }
    colour_titles.push_back(title);
    return colour_titles.size() - 1;
  };
  // Emphasised curves last in each panel, so that they are drawn on top.
  const auto drawing_order = [](const Panel& panel) {
    std::vector<std::size_t> order;
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t c = 0; c < panel.curves.size(); ++c) {
        if (panel.curves[c].emphasised == (pass == 1)) order.push_back(c);
      }
    }
    return order;
  };
  // A curve's look: "with … lc … dt …" (colours assigned in drawing order over the figure).
  const auto look_of = [&](const Curve& curve) {
    std::string look;
    switch (curve.style) {
      case Curve::Style::lines: look = "with lines lw " + lw; break;
      case Curve::Style::points: look = "with points pt 7 ps 0.6"; break;
      case Curve::Style::lines_points: look = "with linespoints lw " + lw + " pt 7"; break;
      case Curve::Style::error_bars: look = "with yerrorlines lw " + lw + " pt 7"; break;
      case Curve::Style::band: look = "with filledcurves fs transparent solid 0.25 noborder"; break;
    }
    if (curve.emphasised) return look + " lc rgb '#000000' dt 2";
    const std::size_t colour = colour_of(curve.title);
    return look + " lc rgb '" + kColours[colour % 12] + "' dt " + std::to_string(1 + colour / 12);
  };
  // The legend: one entry per distinct title over the figure, drawn once by the first panel
  // (keyentry), so that entries first seen in later panels do not land on the first's.
  std::vector<std::pair<std::string, std::string>> legend;  // title, look
  std::vector<std::vector<std::string>> looks(n_panels);
  for (std::size_t p = 0; p < n_panels; ++p) {
    const Panel& panel = figure.panels[p];
    looks[p].resize(panel.curves.size());
    for (std::size_t c : drawing_order(panel)) {
      const Curve& curve = panel.curves[c];
      looks[p][c] = look_of(curve);
      const bool listed = std::any_of(legend.begin(), legend.end(), [&](const auto& entry) { return entry.first == curve.title; });
      if (!curve.title.empty() && !listed) legend.emplace_back(curve.title, looks[p][c]);
    }
    const std::string& marks = panel.edge_mark_title;
    const bool listed = std::any_of(legend.begin(), legend.end(), [&](const auto& entry) { return entry.first == marks; });
    if (!panel.edge_marks_x.empty() && !marks.empty() && !listed) {
      legend.emplace_back(marks, std::string("with points pt 11 ps 1.4 lc rgb '") + kEdgeMarkColour + "'");
    }
  }
  for (std::size_t p = 0; p < n_panels; ++p) {
    const Panel& panel = figure.panels[p];
    // A square panel (equal axes) has the smaller side's room both ways.
    const double side_em = std::min(plot_chars * 0.55, plot_lines * 1.25);
    script << make_tics_lines(panel, panel.equal_axes ? side_em / 0.55 : plot_chars, panel.equal_axes ? side_em / 1.25 : plot_lines);
    // gnuplot centres a wrapped y label's lines on the place of one, so that the last runs into
    // the tick labels ("(count)" on "1e+03"): each further line moves it left by about a line.
    const std::string y_label = wrap_balanced(panel.y_label, p % columns == 0 ? y_label_chars : y_label_chars_inner);
    const auto y_lines = 1 + std::count(y_label.begin(), y_label.end(), '\n');
    script << "set title " << quote_gnuplot(wrap_balanced(panel.title, label_chars)) << "\n"
           << "set xlabel " << quote_gnuplot(wrap_balanced(panel.x_label, label_chars)) << "\n"
           << "set ylabel " << quote_gnuplot(y_label) << " offset " << -1.3 * static_cast<double>(y_lines - 1) << ",0\n"
           << (panel.log_x ? "set logscale x\nset format x '%g'\n" : "unset logscale x\nset format x '%g'\n")
           << (panel.log_y ? "set logscale y\nset format y '%.0e'\n" : "unset logscale y\nset format y '%g'\n")
           << (panel.equal_axes ? "set size ratio -1\n" : "set size noratio\n")
           << make_range_lines(panel);
    // Edge marks: graph coordinates in y, so they sit on the top frame whatever the data's range.
    script << "unset label\n";
    if (p == 0) script << below_labels;
    for (std::size_t m = 0; m < panel.edge_marks_x.size(); ++m) {
      char label[128];
      std::snprintf(label, sizeof label, "set label %zu '' at first %.17g, graph 1 point pt 11 ps 1.4 lc rgb '%s' front\n", m + 1,
                    panel.edge_marks_x[m], kEdgeMarkColour);
      script << label;
    }
    script << "plot ";
    const std::vector<std::size_t> order = drawing_order(panel);
    for (std::size_t i = 0; i < order.size(); ++i) {
      const std::size_t c = order[i];
      const Curve& curve = panel.curves[c];
      const std::string file = (std::filesystem::path(data_dir) / data_file_name(p, c)).string();
      script << (i ? ", \\\n     " : "") << quote_gnuplot(file)
             << (curve.style == Curve::Style::error_bars ? " using 1:2:3:4 "
                 : curve.style == Curve::Style::band     ? " using 1:3:4 "
                                                         : " using 1:2 ")
             << looks[p][c] << " notitle";
    }
    if (p == 0) {
      for (std::size_t e = 0; e < legend.size(); ++e) {
        script << (order.empty() && e == 0 ? "" : ", \\\n     ") << "keyentry " << legend[e].second << " title "
               << quote_gnuplot(legend[e].first);
      }
    }
    if (order.empty() && (p != 0 || legend.empty())) script << "keyentry notitle";  // a plot command needs an element
    script << "\n";
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

TerminalSettings make_terminal_settings(const std::string& out_path, const FigureOptions& options, const Figure& figure) {
  const std::size_t n_panels = figure.panels.size();
  enum class Format { pdf, svg, png };
  Format format;
  if (ends_with(out_path, ".pdf")) format = Format::pdf;
  else if (ends_with(out_path, ".svg")) format = Format::svg;
  else if (ends_with(out_path, ".png")) format = Format::png;
  else throw AnalysisError(out_path + ": the output must end in .pdf, .svg or .png");
  FigureStyle style = options.style;
  if (style == FigureStyle::automatic) style = format == Format::svg ? FigureStyle::screen : FigureStyle::paper;
  const std::size_t columns = count_columns(figure);
  const std::size_t rows = (std::max<std::size_t>(n_panels, 1) + columns - 1) / columns;
  double width = 0, height = 0, font = 0, line_width = 0;
  switch (style) {
    case FigureStyle::paper:
      width = columns >= 3 ? 7.0 : 3.5;
      // Panels stacked in one column (time series) are full width and need less height each.
      height = n_panels <= 1 ? 2.8 : 0.6 + (columns == 1 ? 1.45 : 1.9) * static_cast<double>(rows);
      font = 8;
      line_width = 1.0;
      break;
    case FigureStyle::slide:
      width = 10.0;
      height = 5.625;
      font = rows >= 3 ? 10 : rows == 2 ? 12 : 16;  // a 3 × 3 grid on one slide needs small print
      line_width = 2.5;
      break;
    case FigureStyle::automatic:
    case FigureStyle::screen:
      width = 1000.0 / 96;
      height = 700.0 / 96;
      font = 12 * 72.0 / 96;  // 12 px
      line_width = 2.0;
      break;
  }
  if (options.width_in) width = *options.width_in;
  if (options.font_pt) font = *options.font_pt;
  const double key_row_lines = format == Format::svg ? 1.25 : 1.0;
  // The legend's rows below the panels add to the height (unless the size is given), so that
  // many entries do not squeeze the panels; spare grid cells hold the legend instead.
  if (!options.height_in && rows * columns == n_panels) {
    const LegendLayout legend = make_legend_layout(figure, 0.55 * font / (width * 72));
    height += key_row_lines * 1.25 * font * static_cast<double>(legend.rows) / 72;
  }
  // So do the figure's title lines past two (its notes: error bars, marks, jobs not shown), but
  // on a slide, whose size is the screen's: four lines took a third of a 2-row paper figure.
  if (!options.height_in && style != FigureStyle::slide) {
    const std::string title = wrap_balanced(figure.title, static_cast<std::size_t>(std::max(10.0, width * 72 / (0.55 * font) - 2)));
    const auto lines = static_cast<double>(std::count(title.begin(), title.end(), '\n')) + (title.empty() ? 0 : 1);
    height += 1.1 * 1.25 * font * std::max(0.0, lines - 2) / 72;
    // And the table and caption under the legend.
    const std::size_t below = make_below_block(figure, width * 72 / (0.55 * font)).count_lines();
    if (below > 0) height += 1.25 * font * (static_cast<double>(below) + 0.4) / 72;
  }
  if (options.height_in) height = *options.height_in;
  if (!(width > 0 && height > 0 && font > 0 && width <= 100 && height <= 100 && font <= 200)) {
    throw AnalysisError(out_path + ": size and font size must be positive (at most 100 in and 200 pt)");
  }
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
  return {line, line_width, width * 72, height * 72, font, key_row_lines};
}

void write_figure(const Figure& figure, const std::string& out_path, const FigureOptions& options) {
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
    std::ifstream log(work / "gnuplot.log");
    // The first error line says why (warnings, such as the key's fitting, come first).
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
    throw AnalysisError(out_path + ": gnuplot failed" + (reason.empty() ? "" : ": " + make_printable_text(reason)));
  }
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

}  // namespace armfarm
