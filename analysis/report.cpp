#include "analysis/report.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/plots.hpp"
#include "analysis/search_summary.hpp"
#include "analysis/sweep_data.hpp"
#include "analysis/table.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
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

// A cell's value for the sorting script: full precision, so that 1.5e-03 sorts below 0.01.
std::string format_sort_key(double value) { return format_number(value, 17); }

std::string format_html_table(const Table& table) {
  std::ostringstream out;
  out << "<h3>" << escape_html(table.title) << "</h3>\n<div class=\"scroll\"><table class=\"sortable\">\n<tr>";
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
        text = format_table_number(cell.mean);
        if (cell.count > 1) text += " ± " + format_table_number(cell.std_dev, 2) + " (n=" + std::to_string(cell.count) + ")";
      }
      out << "<td class=\"num\"";
      if (cell.count > 0) out << " data-sort=\"" << format_sort_key(cell.mean) << "\"";
      out << ">" << escape_html(text);
      if (row.footnotes[c]) out << "<sup>" << row.footnotes[c] << "</sup>";
      out << "</td>";
    }
    out << "<td>" << row.jobs_done;
    if (row.jobs_failed) out << " (" << row.jobs_failed << " failed)";
    out << "</td></tr>\n";
  }
  out << "</table></div>\n";
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
    "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
    "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px}"
    "th{background:#eee}td.num{text-align:right;font-family:monospace}pre{background:#f6f6f6;padding:1em;"
    "overflow-x:auto;white-space:pre-wrap;overflow-wrap:anywhere}.bad{color:#a00;overflow-wrap:anywhere}"
    "svg{max-width:100%;height:auto}"
    ".scroll{overflow-x:auto;max-width:100%;max-height:40em;overflow-y:auto}"
    "table.sortable th{cursor:pointer}table.sortable th:after{content:' \\2195';color:#999}"
    "nav ul{columns:2}</style>";

// Sorting a table by a click on a header: numbers by their data-sort key, text otherwise; a
// second click reverses. Inline, nothing fetched.
const char* kSortScript =
    "<script>document.querySelectorAll('table.sortable').forEach(function(t){"
    "var h=t.rows[0];Array.prototype.forEach.call(h.cells,function(th,i){th.addEventListener('click',function(){"
    "var rows=Array.prototype.slice.call(t.rows,1),up=th.dataset.dir!=='up';th.dataset.dir=up?'up':'down';"
    "function key(r){var c=r.cells[i];if(!c)return '';var k=c.getAttribute('data-sort');"
    "return k!==null?parseFloat(k):c.textContent;}"
    "rows.sort(function(a,b){var x=key(a),y=key(b);var d=(typeof x==='number'&&typeof y==='number')?x-y:"
    "String(x).localeCompare(String(y),undefined,{numeric:true});return up?d:-d;});"
    "rows.forEach(function(r){t.tBodies[0].appendChild(r);});});});});</script>";

std::string make_sweep_page(const ResultsStore& store, const SweepRecord& sweep, const SweepData& data,
                            const fs::path& work_dir) {
  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>armfarm sweep " << escape_html(sweep.name)
       << "</title>" << kStyle << "</head><body>\n";
  page << "<p><a href=\"index.html\">all sweeps</a></p>\n";
  page << "<h1>Sweep " << escape_html(sweep.name) << "</h1>\n<p>" << escape_html(sweep.description) << "</p>\n";

  // The figures and tables first (rendered now, so that the contents can list them).
  std::ostringstream figures, tables;
  std::vector<std::pair<std::string, std::string>> contents;  // anchor, title
  int n = 0;
  for (PlotKind kind : find_available_plot_kinds(store, data)) {
    PlotRequest request;
    request.kind = kind;
    request.sweep = sweep.name;
    const std::string anchor = "figure-" + std::to_string(++n);
    const fs::path svg_path = work_dir / (std::string(to_string(kind)) + ".svg");
    figures << "<h3 id=\"" << anchor << "\">" << escape_html(to_string(kind)) << "</h3>\n";
    contents.emplace_back(anchor, std::string("Figure: ") + to_string(kind));
    try {
      write_figure(make_plot_figure(store, request), svg_path.string());
      figures << make_inline_svg(read_whole_file(svg_path)) << "\n";
    } catch (const AnalysisError& e) {
      figures << "<p class=\"bad\">" << escape_html(std::string(to_string(kind)) + ": " + e.what()) << "</p>\n";
    }
  }
  n = 0;
  for (const TableSpec& spec : make_default_table_specs(data)) {
    const std::string anchor = "table-" + std::to_string(++n);
    contents.emplace_back(anchor, "Table: " + spec.title);
    tables << "<div id=\"" << anchor << "\">";
    try {
      tables << format_html_table(make_table(data, spec));
    } catch (const AnalysisError& e) {
      tables << "<p class=\"bad\">" << escape_html(spec.title + ": " + e.what()) << "</p>\n";
    }
    tables << "</div>\n";
  }

  const std::optional<SearchSummary> search = load_search_summary(store, sweep.name);
  page << "<nav><h2>Contents</h2>\n<ul>\n";
  for (const auto& [anchor, title] : contents) {
    page << "<li><a href=\"#" << anchor << "\">" << escape_html(title) << "</a></li>\n";
  }
  if (search) page << "<li><a href=\"#Search\">Search</a></li>\n";
  for (const char* section : {"Status", "Provenance", "Spec"}) {
    page << "<li><a href=\"#" << section << "\">" << section << "</a></li>\n";
  }
  page << "</ul></nav>\n";
  page << "<h2 id=\"figures\">Figures</h2>\n" << figures.str();
  page << "<h2 id=\"tables\">Tables</h2>\n<p>Click a column header to sort by it.</p>\n" << tables.str();
  if (search) page << "<h2 id=\"Search\">Search</h2>\n<pre>" << escape_html(format_search_summary(*search)) << "</pre>\n";

  page << "<h2 id=\"Status\">Status</h2>\n<table><tr><th>status</th><th>jobs</th></tr>\n";
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

  page << "<h2 id=\"Provenance\">Provenance</h2>\n<table>\n";
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

  page << "<h2 id=\"Spec\">Spec</h2>\n<pre>" << escape_html(sweep.spec_text) << "</pre>\n" << kSortScript
       << "\n</body></html>\n";
  return page.str();
}

// The index's row of a sweep.
std::string make_index_row(const ResultsStore& store, const SweepRecord& sweep, const SweepData& data,
                           const std::string& file, const DescribeBest& describe_best) {
  const std::map<std::string, int> counts = store.count_jobs_by_status(sweep.name);
  const auto count = [&](const std::string& status) {
    const auto found = counts.find(status);
    return found == counts.end() ? 0 : found->second;
  };
  int jobs = 0;
  for (const auto& [status, number] : counts) jobs += number;
  const std::string best = describe_best ? describe_best(data) : std::string();
  std::ostringstream row;
  row << "<tr><td><a href=\"" << escape_html(file) << "\">" << escape_html(sweep.name) << "</a><br><small>"
      << escape_html(sweep.description) << "</small></td>";
  for (int number : {jobs, count("done"), count("failed") + count("timeout"), count("diverged")}) {
    row << "<td class=\"num\" data-sort=\"" << number << "\">" << number << "</td>";
  }
  row << "<td>" << escape_html(sweep.started_at.substr(0, 10)) << "</td><td><code title=\"" << escape_html(sweep.spec_hash)
      << "\">" << escape_html(sweep.spec_hash.substr(0, 12)) << "</code></td><td>"
      << escape_html(best.empty() ? std::string("–") : best) << "</td></tr>\n";
  return row.str();
}

}  // namespace

std::vector<std::string> write_report(const ResultsStore& store, const std::optional<std::string>& sweep,
                                      const std::string& out_dir, const DescribeBest& describe_best) {
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
        << "</head><body>\n<h1>armfarm report</h1>\n<p>" << escape_html(store.path()) << "</p>\n"
        << "<div class=\"scroll\"><table class=\"sortable\">\n<tr><th>sweep</th><th>jobs</th><th>done</th>"
        << "<th>failed</th><th>diverged</th><th>started</th><th>spec hash</th><th>best by the main metric</th></tr>\n";
  for (const SweepRecord& record : sweeps) {
    const SweepData data = load_sweep_data(store, record.name);
    const std::string file = make_sweep_view_name(record.name) + ".html";
    const fs::path path = fs::path(out_dir) / file;
    write_text_atomically(path, make_sweep_page(store, record, data, pattern));
    written.push_back(path.string());
    index << make_index_row(store, record, data, file, describe_best);
  }
  index << "</table></div>\n" << kSortScript << "\n</body></html>\n";
  const fs::path index_path = fs::path(out_dir) / "index.html";
  write_text_atomically(index_path, index.str());
  written.push_back(index_path.string());
  return written;
}

}  // namespace armfarm
