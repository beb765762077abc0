#pragma once
// A figure as plain data (panels of curves with labelled axes) and its rendering to PDF, SVG
// or PNG through gnuplot. Plots build a Figure from results; this file knows nothing of them.
#include <optional>
#include <string>
#include <vector>

namespace armfarm {

struct Curve {
  /// band: the area between y_low and y_high (a confidence band), translucent, no line; y unused.
  enum class Style { lines, points, lines_points, error_bars, band };
  std::string title;
  std::vector<double> x;
  std::vector<double> y;
  std::vector<double> y_low;   ///< error_bars, band: lower end of each bar (same size as y)
  std::vector<double> y_high;  ///< error_bars, band: upper end of each bar
  Style style = Style::lines;
  bool emphasised = false;     ///< drawn last, black, dashed (e.g. a desired path on top)
  /// Drawn first and 2.5 times as wide as the others, so that curves lying on it stay visible on
  /// top: a sum such as the composite torque, which is the feedback where the feed-forward is near
  /// zero (figure 6.8's joint 1 showed the composite alone). The legend shows the same width.
  bool underneath = false;
};

struct Panel {
  std::string title;
  std::string x_label;  ///< with units, e.g. "time (s)"
  std::string y_label;
  bool log_x = false;
  bool log_y = false;
  bool equal_axes = false;  ///< same scale on x and y (paths in a plane), the panel square around the data
  bool tight_x = false;     ///< x axis ends at the data (time series), not at the next tick
  std::optional<double> y_min;  ///< the y axis starts here (a bar clipped at the axis ends on it); empty = automatic
  std::optional<double> x_min;  ///< the x axis starts here (0 reaches); empty = at the data (tight) or padded
  std::vector<Curve> curves;
  /// x positions of marks drawn on the top edge of the panel (jobs without a value there, e.g.
  /// diverged ones), with one legend entry `edge_mark_title`.
  std::vector<double> edge_marks_x;
  std::string edge_mark_title;
};

/// A small table set under the figure (below the legend): the numbers a panel title cannot hold
/// at paper width (the thesis's value beside armfarm's per joint). Columns are left-aligned at
/// widths from their longest cell; a table wider than the page is set as one wrapped line per row.
struct FigureTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

struct Figure {
  std::string title;              ///< short: what is drawn (the notes go into the caption)
  std::vector<Panel> panels;      ///< laid out in a grid
  std::size_t columns = 0;        ///< the grid's columns; 0: 1 panel in 1, up to 4 in 2, else 3
  FigureTable table;              ///< under the legend; empty header: none
  std::vector<std::string> caption;  ///< paragraphs under the table, each wrapped to the page (sources, error bars, jobs not shown)
};

/// How a figure is sized and lettered. paper: 3.5 in wide (the single column of a two-column
/// paper; 7 in when the panels need three columns), 8 pt fonts, thin lines. slide: 10 × 5.6 in,
/// 16 pt, thick lines. screen: 1000 × 700 px at 12 pt (the report's inline SVG).
enum class FigureStyle { automatic, paper, slide, screen };

/// "paper", "slide", "screen"; throws AnalysisError otherwise.
FigureStyle parse_figure_style(const std::string& word);

struct FigureOptions {
  FigureStyle style = FigureStyle::automatic;  ///< automatic: paper for .pdf and .png, screen for .svg
  std::optional<double> width_in;              ///< override of the style's size, inches
  std::optional<double> height_in;
  std::optional<double> font_pt;               ///< override of the style's font size, points
  /// Draw the figure's caption and table under the legend (the page grows for them in every
  /// style). false: the figure ends at its legend, for a document that sets its own caption
  /// (format_caption_text gives the text left out).
  bool caption = true;
};

/// The gnuplot terminal line and the line width for `out_path`'s format (by extension: .pdf,
/// .svg, .png) at `options`, for `figure` (its panels and legend entries). PNG renders at 300 dpi. Throws
/// AnalysisError for another extension.
struct TerminalSettings {
  std::string terminal_line;
  double line_width = 2.0;
  double width_pt = 750, height_pt = 525, font_pt = 9;  ///< the page, for margins in character units
  double key_row_lines = 1.25;  ///< a legend row's height in lines of 1.25 em (gnuplot's svg 1.5 em, cairo's 1.17 em)
};
TerminalSettings make_terminal_settings(const std::string& out_path, const FigureOptions& options, const Figure& figure);

/// The curves' colours, the one home of the palette: 12 that stay apart in greyscale print (the
/// first three) and for colour-blind readers ("#RRGGBB"). Curves take them in the order their
/// titles are first declared over the figure; past 12 the same colours repeat dashed, dotted ….
/// A curve title already shown in an earlier panel is not repeated, so the figure has one legend,
/// and a title keeps its colour in every panel (the same colour is the same group).
const std::vector<std::string>& figure_colours();
/// The colour of the marks of jobs without a value (diverged, failed) on a panel's top edge.
const std::string& figure_edge_mark_colour();

/// `figure` as `style` sets it out (write_figure applies it): on a slide, panels the figure
/// stacks in one column (time series, full width on paper) go side by side, up to three to a
/// row, since three stacked rows left each plot area 0.6 in of a 5.6 in slide.
Figure arrange_for_style(Figure figure, FigureStyle style);

/// Whether values want a log axis by default: all finite ones positive, the largest at least 20
/// times the smallest (non-finite values are skipped). The one automatic rule of every plot kind.
bool spans_decades(const std::vector<double>& values);

/// `figure` without its caption and table (what FigureOptions::caption = false draws).
Figure remove_caption(Figure figure);

/// The caption and table as plain text: the table's rows in aligned columns, then a line per
/// caption paragraph ("" when the figure has neither). For `plot --no-caption`, which prints it.
std::string format_caption_text(const Figure& figure);

/// Renders `figure` to `out_path` (.pdf, .svg or .png, chosen by extension) with gnuplot. The file is
/// written whole or not at all. Throws AnalysisError (gnuplot missing or failing, bad extension,
/// empty figure).
void write_figure(const Figure& figure, const std::string& out_path, const FigureOptions& options = {});

/// The gnuplot script that write_figure runs, with data files named data_<panel>_<curve>.dat
/// in `data_dir` (exposed for tests).
std::string make_gnuplot_script(const Figure& figure, const TerminalSettings& terminal, const std::string& output_path,
                                const std::string& data_dir);

}  // namespace armfarm
