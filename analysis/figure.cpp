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
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace armfarm {

namespace {

// gnuplot text that cannot expand: single quotes, inside which gnuplot runs no backtick command,
// expands no @macro and reads no backslash escape ('' is a quote). A line break becomes the
// string expression '…'."\n".'…'; other control characters and non-UTF-8 bytes are replaced.
std::string quote_gnuplot(const std::string& text) {
  const std::string printable = make_printable_text(text, /*keep_newlines=*/true);
  std::string out = "'";
  for (const char c : printable) {
    if (c == '\n') {
      out += "'.\"\\n\".'";
    } else if (c == '\'') {
      out += "''";
    } else {
      out += c;
    }
  }
  return out + "'";
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

}  // namespace

std::string make_gnuplot_script(const Figure& figure, const std::string& terminal_line, const std::string& output_path,
                                const std::string& data_dir) {
  std::ostringstream script;
  const std::size_t n_panels = figure.panels.size();
  const std::size_t columns = n_panels <= 1 ? 1 : (n_panels <= 4 ? 2 : 3);
  const std::size_t rows = (n_panels + columns - 1) / columns;
  script << terminal_line << "\n"
         << "set output " << quote_gnuplot(output_path) << "\n"
         << "set termoption noenhanced\n"
         << "set grid\nset key outside bottom center horizontal\n"
         << "set datafile missing 'nan'\n";
  if (n_panels > 1 || !figure.title.empty()) {
    script << "set multiplot layout " << rows << "," << columns;
    if (n_panels > 1) script << " margins 0.07,0.98,0.12,0.86 spacing 0.08,0.12";
    if (!figure.title.empty()) script << " title " << quote_gnuplot(figure.title);
    script << "\n";
  }
  // Paul Tol's "muted" and "bright" schemes: distinguishable, also in greyscale print.
  static const char* const kColours[12] = {"#332288", "#88CCEE", "#44AA99", "#117733", "#999933", "#DDCC77",
                                           "#CC6677", "#882255", "#AA4499", "#4477AA", "#EE6677", "#000000"};
  std::vector<std::string> titles_shown;
  // With empty grid cells (7 joints on 3 × 3) the legend goes into them, bottom right.
  const bool spare_cells = n_panels > 1 && rows * columns > n_panels;
  if (spare_cells) {
    script << "set key at screen 0.97, screen 0.06 right bottom vertical Left reverse\n";
  }
  for (std::size_t p = 0; p < n_panels; ++p) {
    const Panel& panel = figure.panels[p];
    if (!spare_cells && panel.curves.size() > 6) script << "set key outside right top vertical\n";
    script << "set title " << quote_gnuplot(panel.title) << "\n"
           << "set xlabel " << quote_gnuplot(panel.x_label) << "\n"
           << "set ylabel " << quote_gnuplot(panel.y_label) << "\n"
           << (panel.log_x ? "set logscale x\nset format x '%g'\n" : "unset logscale x\nset format x '%g'\n")
           << (panel.log_y ? "set logscale y\nset format y '%.0e'\n" : "unset logscale y\nset format y '%g'\n")
           << (panel.equal_axes ? "set size ratio -1\n" : "set size noratio\n");
    script << "plot ";
    // Emphasised curves last, so that they are drawn on top.
    std::vector<std::size_t> order;
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t c = 0; c < panel.curves.size(); ++c) {
        if (panel.curves[c].emphasised == (pass == 1)) order.push_back(c);
      }
    }
    std::size_t plain = 0;
    for (std::size_t i = 0; i < order.size(); ++i) {
      const std::size_t c = order[i];
      const Curve& curve = panel.curves[c];
      const std::string file = (std::filesystem::path(data_dir) / data_file_name(p, c)).string();
      script << (i ? ", \\\n     " : "") << quote_gnuplot(file);
      switch (curve.style) {
        case Curve::Style::lines: script << " using 1:2 with lines lw 2"; break;
        case Curve::Style::points: script << " using 1:2 with points pt 7 ps 0.6"; break;
        case Curve::Style::lines_points: script << " using 1:2 with linespoints lw 2 pt 7"; break;
        case Curve::Style::error_bars: script << " using 1:2:3:4 with yerrorlines lw 2 pt 7"; break;
      }
      if (curve.emphasised) {
        script << " lc rgb '#000000' dt 2";
      } else {
        script << " lc rgb '" << kColours[plain % 12] << "' dt " << 1 + plain / 12;
        ++plain;
      }
      const bool repeated = std::find(titles_shown.begin(), titles_shown.end(), curve.title) != titles_shown.end();
      if (repeated || curve.title.empty()) {
        script << " notitle";
      } else {
        script << " title " << quote_gnuplot(curve.title);
        titles_shown.push_back(curve.title);
      }
    }
    script << "\n";
  }
  if (n_panels > 1 || !figure.title.empty()) script << "unset multiplot\n";
  script << "set output\n";
  return script.str();
}

void write_figure(const Figure& figure, const std::string& out_path) {
  std::string terminal_line;
  if (ends_with(out_path, ".svg")) {
    terminal_line = "set terminal svg size 1000,700 dynamic background rgb 'white' font 'sans,12'";
  } else if (ends_with(out_path, ".png")) {
    terminal_line = "set terminal pngcairo size 1200,840 font 'sans,11'";
  } else {
    throw AnalysisError(out_path + ": the output must end in .svg or .png");
  }
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
        if (curve.style == Curve::Style::error_bars) {
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
  const fs::path rendered = work / (ends_with(out_path, ".svg") ? "figure.svg" : "figure.png");
  {
    std::ofstream script_file(work / "plot.gp");
    script_file << make_gnuplot_script(figure, terminal_line, rendered.string(), work.string());
  }
  const int status = run_gnuplot((work / "plot.gp").string(), (work / "gnuplot.log").string());
  if (status == -1 && errno == ENOENT) {
    throw AnalysisError("gnuplot is not installed (Debian package gnuplot-nox; `make deps` installs it)");
  }
  if (status != 0 || !fs::exists(rendered)) {
    std::ifstream log(work / "gnuplot.log");
    std::string first_line;
    std::getline(log, first_line);
    throw AnalysisError(out_path + ": gnuplot failed" + (first_line.empty() ? "" : ": " + make_printable_text(first_line)));
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
