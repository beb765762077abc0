#include "analysis/report.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/plots.hpp"
#include "analysis/search_summary.hpp"
#include "analysis/sweep_data.hpp"
#include "analysis/table.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace armfarm {

std::string escape_html(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

namespace fs = std::filesystem;

std::string format_html_table(const Table& table) {
  std::ostringstream out;
  out << "<h3>" << escape_html(table.title) << "</h3>\n<table>\n<tr>";
  for (const std::string& header : table.row_headers) out << "<th>" << escape_html(header) << "</th>";
  for (const TableColumn& column : table.columns) out << "<th>" << escape_html(column.header) << "</th>";
  out << "<th>jobs done</th></tr>\n";
  for (const TableRow& row : table.rows) {
    out << "<tr>";
    for (const std::string& label : row.labels) out << "<td>" << escape_html(label) << "</td>";
    for (std::size_t c = 0; c < row.cells.size(); ++c) {
      const SummaryStatistics& cell = row.cells[c];
      std::string text = "–";
      if (cell.count > 0) {
        text = format_number(cell.mean);
        if (cell.count > 1) text += " ± " + format_number(cell.std_dev, 2) + " (n=" + std::to_string(cell.count) + ")";
      }
      out << "<td class=\"num\">" << escape_html(text);
      if (row.footnotes[c]) out << "<sup>" << row.footnotes[c] << "</sup>";
      out << "</td>";
    }
    out << "<td>" << row.jobs_done;
    if (row.jobs_failed) out << " (" << row.jobs_failed << " failed)";
    out << "</td></tr>\n";
  }
  out << "</table>\n";
  if (!table.footnotes.empty()) {
    out << "<ol class=\"notes\">\n";
    for (const std::string& note : table.footnotes) out << "<li>" << escape_html(note) << "</li>\n";
    out << "</ol>\n";
  }
  return out.str();
}

std::string read_whole_file(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// An SVG file as an inline element: drop the XML prologue and DOCTYPE.
std::string make_inline_svg(const std::string& svg) {
  const auto start = svg.find("<svg");
  return start == std::string::npos ? std::string() : svg.substr(start);
}

void write_text_atomically(const fs::path& path, const std::string& text) {
  const fs::path partial = path.string() + ".partial";
  {
    std::ofstream out(partial);
    out << text;
    if (!out) throw AnalysisError(path.string() + ": cannot write");
  }
  std::error_code error;
  fs::rename(partial, path, error);
  if (error) throw AnalysisError(path.string() + ": cannot write: " + error.message());
}

const char* kStyle =
    "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
    "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px}"
    "th{background:#eee}td.num{text-align:right;font-family:monospace}pre{background:#f6f6f6;padding:1em;"
    "overflow-x:auto}.bad{color:#a00}svg{max-width:100%;height:auto}</style>";

std::string make_sweep_page(const ResultsStore& store, const SweepRecord& sweep, const fs::path& work_dir) {
  const SweepData data = load_sweep_data(store, sweep.name);
  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>armfarm sweep " << escape_html(sweep.name)
       << "</title>" << kStyle << "</head><body>\n";
  page << "<h1>Sweep " << escape_html(sweep.name) << "</h1>\n<p>" << escape_html(sweep.description) << "</p>\n";

  page << "<h2>Provenance</h2>\n<table>\n";
  const Provenance& p = sweep.provenance;
  const std::vector<std::pair<std::string, std::string>> rows = {
      {"started", sweep.started_at},
      {"finished", sweep.finished_at.value_or("(not finished)")},
      {"armfarm", p.armfarm_version},
      {"git commit", p.git_commit + (p.git_dirty ? " (dirty)" : "")},
      {"compiler", p.compiler},
      {"Simbody", p.simbody_version},
      {"host", p.host},
      {"spec hash", sweep.spec_hash},
      {"database", store.path()}};
  for (const auto& [name, value] : rows) page << "<tr><th>" << escape_html(name) << "</th><td>" << escape_html(value) << "</td></tr>\n";
  page << "</table>\n";

  page << "<h2>Status</h2>\n<table><tr><th>status</th><th>jobs</th></tr>\n";
  for (const auto& [status, count] : store.count_jobs_by_status(sweep.name)) {
    page << "<tr><td>" << escape_html(status) << "</td><td class=\"num\">" << count << "</td></tr>\n";
  }
  page << "</table>\n";
  bool any_failure = false;
  for (const JobResult& job : data.jobs) {
    if (job.status == "done" || job.status == "pending" || job.status == "running") continue;
    if (!any_failure) page << "<ul class=\"bad\">\n";
    any_failure = true;
    page << "<li>" << escape_html(job.key.substr(0, 12) + " " + job.status + ": " + job.message + " [" + make_job_label(job) + "]") << "</li>\n";
  }
  if (any_failure) page << "</ul>\n";

  page << "<h2>Tables</h2>\n";
  for (const TableSpec& spec : make_default_table_specs(data)) {
    try {
      page << format_html_table(make_table(data, spec));
    } catch (const AnalysisError& e) {
      page << "<p class=\"bad\">" << escape_html(spec.title + ": " + e.what()) << "</p>\n";
    }
  }

  if (const std::optional<SearchSummary> summary = load_search_summary(store, sweep.name)) {
    page << "<h2>Search</h2>\n<pre>" << escape_html(format_search_summary(*summary)) << "</pre>\n";
  }

  page << "<h2>Plots</h2>\n";
  for (PlotKind kind : find_available_plot_kinds(store, data)) {
    PlotRequest request;
    request.kind = kind;
    request.sweep = sweep.name;
    const fs::path svg_path = work_dir / (std::string(to_string(kind)) + ".svg");
    try {
      write_figure(make_plot_figure(store, request), svg_path.string());
      page << "<h3>" << escape_html(to_string(kind)) << "</h3>\n" << make_inline_svg(read_whole_file(svg_path)) << "\n";
    } catch (const AnalysisError& e) {
      page << "<p class=\"bad\">" << escape_html(std::string(to_string(kind)) + ": " + e.what()) << "</p>\n";
    }
  }

  page << "<h2>Spec</h2>\n<pre>" << escape_html(sweep.spec_text) << "</pre>\n</body></html>\n";
  return page.str();
}

}  // namespace

std::vector<std::string> write_report(const ResultsStore& store, const std::optional<std::string>& sweep,
                                      const std::string& out_dir) {
  std::vector<SweepRecord> sweeps;
  if (sweep) {
    auto record = store.find_sweep(choose_sweep(store, sweep));
    sweeps.push_back(*record);
  } else {
    sweeps = store.find_sweeps();
    if (sweeps.empty()) throw AnalysisError(store.path() + ": the database holds no sweep");
  }
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error) throw AnalysisError(out_dir + ": cannot create the directory: " + error.message());

  std::string pattern = (fs::temp_directory_path() / "armfarm-report-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw AnalysisError("cannot create a temporary directory");
  struct Cleanup {
    fs::path path;
    ~Cleanup() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  } cleanup{pattern};

  std::vector<std::string> written;
  std::ostringstream index;
  index << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>armfarm report</title>" << kStyle
        << "</head><body>\n<h1>armfarm report</h1>\n<p>" << escape_html(store.path()) << "</p>\n<ul>\n";
  for (const SweepRecord& record : sweeps) {
    const std::string file = make_sweep_view_name(record.name) + ".html";
    const fs::path path = fs::path(out_dir) / file;
    write_text_atomically(path, make_sweep_page(store, record, pattern));
    written.push_back(path.string());
    index << "<li><a href=\"" << escape_html(file) << "\">" << escape_html(record.name) << "</a> — "
          << escape_html(record.description) << "</li>\n";
  }
  index << "</ul>\n</body></html>\n";
  const fs::path index_path = fs::path(out_dir) / "index.html";
  write_text_atomically(index_path, index.str());
  written.push_back(index_path.string());
  return written;
}

}  // namespace armfarm
