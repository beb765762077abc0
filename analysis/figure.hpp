#pragma once
// A figure as plain data (panels of curves with labelled axes) and its rendering to SVG or
// PNG through gnuplot. Plots build a Figure from results; this file knows nothing of them.
#include <string>
#include <vector>

namespace armfarm {

struct Curve {
  enum class Style { lines, points, lines_points, error_bars };
  std::string title;
  std::vector<double> x;
  std::vector<double> y;
  std::vector<double> y_low;   ///< error_bars: lower end of each bar (same size as y)
  std::vector<double> y_high;  ///< error_bars: upper end of each bar
  Style style = Style::lines;
  bool emphasised = false;     ///< drawn last, black, dashed (e.g. a desired path on top)
};

struct Panel {
  std::string title;
  std::string x_label;  ///< with units, e.g. "time (s)"
  std::string y_label;
  bool log_x = false;
  bool log_y = false;
  bool equal_axes = false;  ///< same scale on x and y (paths in a plane)
  std::vector<Curve> curves;
};

struct Figure {
  std::string title;
  std::vector<Panel> panels;  ///< laid out in a grid
};

/// Colours: 12 distinct ones, then the same colours with dashed, dotted … line styles. A
/// curve title already shown in an earlier panel is not repeated, so the figure has one legend.
/// Renders `figure` to `out_path` (.svg or .png, chosen by extension) with gnuplot. The file is
/// written whole or not at all. Throws AnalysisError (gnuplot missing or failing, bad extension,
/// empty figure).
void write_figure(const Figure& figure, const std::string& out_path);

/// The gnuplot script that write_figure runs, with data files named data_<panel>_<curve>.dat
/// in `data_dir` (exposed for tests).
std::string make_gnuplot_script(const Figure& figure, const std::string& terminal_line, const std::string& output_path,
                                const std::string& data_dir);

}  // namespace armfarm
