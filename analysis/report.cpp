#include "analysis/report.hpp"

#include "analysis/analysis_error.hpp"
#include "analysis/plots.hpp"
#include "analysis/printable_text.hpp"
#include "analysis/search_summary.hpp"
#include "analysis/sweep_data.hpp"
#include "analysis/table.hpp"
#include "analysis/thesis_comparison.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <unistd.h>

namespace armfarm {

std::string escape_html(const std::string& text) {
  std::string out;
  for (char c : make_visible_text(text)) {
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

std::string make_report_file_name(const std::string& prefix, const std::string& name) {
  constexpr std::size_t kMaxNameChars = 64;  // with the prefix and hash, far below NAME_MAX (255)
  std::string stem;
  bool changed = name.size() > kMaxNameChars || name.empty();
  for (std::size_t i = 0; i < name.size() && i < kMaxNameChars; ++i) {
    const char c = name[i];
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    stem += keep ? c : '_';
    changed = changed || !keep;
  }
  if (changed) {
    std::uint64_t hash = 14695981039346656037ull;  // FNV-1a, 64 bit, of the whole name
    for (unsigned char c : name) hash = (hash ^ c) * 1099511628211ull;
    char suffix[24];
    std::snprintf(suffix, sizeof suffix, "_%016llx", static_cast<unsigned long long>(hash));
    stem += suffix;
  }
  return prefix + stem;
}

namespace {

namespace fs = std::filesystem;

std::string make_job_file(const JobResult& job) { return make_report_file_name("job_", job.key) + ".html"; }

// The jobs a table row pools: those whose value of every parameter row matches the row's label
// (rows "joint" and "checkpoint" split a job, they do not select one).
std::vector<const JobResult*> find_row_jobs(const SweepData& data, const TableSpec& spec, const TableRow& row) {
  std::vector<const JobResult*> jobs;
  for (const JobResult& job : data.jobs) {
    bool matches = true;
    for (std::size_t i = 0; i < spec.rows.size() && i < row.labels.size() && matches; ++i) {
      if (spec.rows[i] == "joint" || spec.rows[i] == "checkpoint") continue;
      matches = format_param_value(find_param_value(job, spec.rows[i])) == row.labels[i];
    }
    for (const auto& [path, wanted] : spec.where) matches = matches && format_param_value(find_param_value(job, path)) == wanted;
    if (matches) jobs.push_back(&job);
  }
  return jobs;
}

// Links to job pages: "3f2a1b7c" each, a failed job's link marked.
std::string make_job_links(const std::vector<const JobResult*>& jobs) {
  std::string links;
  for (const JobResult* job : jobs) {
    links += (links.empty() ? "" : " ") + std::string("<a href=\"") + escape_html(make_job_file(*job)) + "\"" +
             (job->status == "done" ? "" : " class=\"bad\" title=\"" + escape_html(job->status) + "\"") + "><code>" +
             escape_html(job->key.substr(0, 8)) + "</code></a>";
  }
  return links;
}

// A cell's value for the sorting script: full precision, so that 1.5e-03 sorts below 0.01.
std::string format_sort_key(double value) { return format_number(value, 17); }

std::string format_html_table(const Table& table, const SweepData& data, const TableSpec& spec) {
  std::ostringstream out;
  out << "<h3>" << escape_html(table.title) << "</h3>\n<div class=\"scroll\"><table class=\"sortable\">\n<tr>";
  for (const std::string& header : table.row_headers) out << "<th>" << escape_html(header) << "</th>";
  for (const TableColumn& column : table.columns) out << "<th>" << escape_html(column.header) << "</th>";
  out << "<th>jobs done</th><th>jobs</th></tr>\n";
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
    out << "</td><td>" << make_job_links(find_row_jobs(data, spec, row)) << "</td></tr>\n";
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
    "overflow-x:auto;white-space:pre-wrap;overflow-wrap:anywhere}.bad{color:#a00;overflow-wrap:anywhere}p.caption{overflow-wrap:anywhere}"
    "svg{max-width:100%;height:auto}"
    ".scroll{overflow-x:auto;max-width:100%;max-height:40em;overflow-y:auto}"
    "table.sortable th{cursor:pointer}table.sortable th:after{content:' \\2195';color:#999}"
    "nav ul{columns:2}h1,title,td.name,nav li{overflow-wrap:anywhere}</style>";

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

// A figure as an inline SVG under its heading, or the reason it could not be drawn. `counter`
// numbers the SVG files of `work_dir`.
std::string render_figure_html(const ResultsStore& store, const PlotRequest& request, const std::string& heading,
                               const std::string& anchor, const fs::path& work_dir, int& counter) {
  std::ostringstream html;
  html << "<h3 id=\"" << anchor << "\">" << escape_html(heading) << "</h3>\n";
  const fs::path svg_path = work_dir / ("figure_" + std::to_string(++counter) + ".svg");
  try {
    // The caption (what is drawn from which metric, error bars, jobs not shown) as the page's
    // text under the figure, where it wraps with the page, not inside the drawing.
    const Figure figure = make_plot_figure(store, request);
    const std::vector<std::string>& caption = figure.caption;
    FigureOptions without_caption;
    without_caption.caption = false;
    write_figure(figure, svg_path.string(), without_caption);
    html << make_inline_svg(read_whole_file(svg_path)) << "\n";
    if (!caption.empty()) {
      html << "<p class=\"caption\">";
      for (std::size_t i = 0; i < caption.size(); ++i) html << (i ? "<br>" : "") << escape_html(caption[i]);
      html << "</p>\n";
    }
  } catch (const AnalysisError& e) {
    html << "<p class=\"bad\">" << escape_html(heading + ": " + e.what()) << "</p>\n";
  }
  return html.str();
}

// Whether every job that has `path` has a number there (a parameter a metric can be drawn against).
bool is_numeric_param(const SweepData& data, const std::string& path) {
  bool any = false;
  for (const JobResult& job : data.jobs) {
    const nlohmann::json value = find_param_value(job, path);
    if (value.is_null()) continue;
    if (!value.is_number()) return false;
    any = true;
  }
  return any;
}

// The thesis's tables that map cells to this sweep: per cell the thesis value as printed beside
// armfarm's (analysis/thesis_comparison.hpp does the comparing).
std::string make_thesis_section(const ResultsStore& store, const SweepRecord& sweep, const ReportOptions& options,
                                std::vector<std::pair<std::string, std::string>>& contents) {
  if (!options.against) return "";
  std::ostringstream html;
  html << "<h2 id=\"thesis\">Thesis</h2>\n<p>" << escape_html(options.against->path) << ": the thesis's value as printed, armfarm's "
       << to_string(options.aggregate) << (options.aggregate == Aggregate::mean ? " [95 % Student-t interval]" : "")
       << " over the matching done jobs, their ratio and the verdict (sweeps/thesis/README.md, \"Verdicts\").</p>\n";
  contents.emplace_back("thesis", "Thesis");
  ThesisComparison comparison;
  try {
    comparison = make_thesis_comparison(*options.against, store, options.aggregate, sweep.name);
  } catch (const AnalysisError& e) {
    html << "<p>" << escape_html(e.what()) << "</p>\n";
    return html.str();
  }
  if (!comparison.note.empty()) html << "<p>" << escape_html(comparison.note) << "</p>\n";
  for (const ComparedTable& table : comparison.tables) {
    const ThesisTable& thesis = *table.thesis;
    std::string title = thesis.number ? "Table " + *thesis.number : thesis.id;
    if (!thesis.caption.empty()) title += ": " + thesis.caption;
    if (thesis.page) title += " (p. " + std::to_string(*thesis.page) + ")";
    html << "<h3>" << escape_html(title) << "</h3>\n<div class=\"scroll\"><table class=\"sortable\">\n"
         << "<tr><th>row</th><th>column</th><th>thesis</th><th>armfarm</th><th>armfarm/thesis</th><th>n</th><th>verdict</th></tr>\n";
    for (const ComparedCell& cell : table.cells) {
      const bool compared = cell.state == CellState::compared;
      std::string armfarm = cell.reason.empty() ? "–" : cell.reason;
      if (compared) armfarm = format_compared_value(cell, options.aggregate);  // as `table --against` prints it
      std::string verdict = cell.verdict == Verdict::none ? "" : to_string(cell.verdict);
      if (!cell.verdict_note.empty()) verdict += " (" + cell.verdict_note + ")";
      html << "<tr><td>" << escape_html(cell.thesis->row) << "</td><td>" << escape_html(cell.thesis->column)
           << "</td><td class=\"num\" data-sort=\"" << format_sort_key(cell.thesis->value) << "\">" << escape_html(cell.thesis->printed)
           << "</td><td" << (compared ? " class=\"num\" data-sort=\"" + format_sort_key(cell.armfarm_value) + "\"" : std::string())
           << ">" << escape_html(armfarm) << "</td><td class=\"num\"" << (cell.ratio ? " data-sort=\"" + format_sort_key(*cell.ratio) + "\"" : std::string())
           << ">" << escape_html(format_compared_ratio(cell)) << "</td><td class=\"num\">" << cell.armfarm.count
           << "</td><td>" << escape_html(verdict) << "</td></tr>\n";
    }
    html << "</table></div>\n";
  }
  return html.str();
}

// A row per job: its page, status, varying parameters and main metric.
std::string make_jobs_table(const SweepData& data, const std::optional<std::string>& main_metric) {
  std::ostringstream html;
  html << "<div class=\"scroll\"><table class=\"sortable\">\n<tr><th>job</th><th>status</th>";
  for (const std::string& path : data.varying_params) html << "<th>" << escape_html(path) << "</th>";
  if (main_metric) html << "<th>" << escape_html(make_metric_axis_label(data.metric_info, MetricId{*main_metric})) << "</th>";
  html << "</tr>\n";
  for (const JobResult& job : data.jobs) {
    html << "<tr><td>" << make_job_links({&job}) << "</td><td" << (job.status == "done" ? "" : " class=\"bad\"") << ">"
         << escape_html(job.status) << "</td>";
    for (const std::string& path : data.varying_params) {
      const nlohmann::json value = find_param_value(job, path);
      html << "<td" << (value.is_number() ? " class=\"num\" data-sort=\"" + format_sort_key(value.get<double>()) + "\"" : std::string())
           << ">" << escape_html(format_param_value(value)) << "</td>";
    }
    if (main_metric) {
      const auto value = job.metrics.find(MetricId{*main_metric});
      const bool defined = value != job.metrics.end() && std::isfinite(value->second);
      html << "<td class=\"num\"" << (defined ? " data-sort=\"" + format_sort_key(value->second) + "\"" : std::string()) << ">"
           << (defined ? escape_html(format_number(value->second)) : "–") << "</td>";
    }
    html << "</tr>\n";
  }
  html << "</table></div>\n";
  return html.str();
}

// A sweep page's table of contents: an anchor and a title per entry.
using Contents = std::vector<std::pair<std::string, std::string>>;

// The figures of a sweep page: the plot kinds it has data for, then the main metric against
// each numeric swept parameter (the others split the curves). Adds them to `contents`; `count`
// is how many were attempted.
std::string render_sweep_figures(const ResultsStore& store, const SweepRecord& sweep, const SweepData& data, const fs::path& work_dir,
                                 const ReportOptions& options, const std::optional<std::string>& main_metric, Contents& contents,
                                 int& count) {
  std::ostringstream figures;
  int svg_files = 0;
  PlotRequest base;
  base.sweep = sweep.name;
  base.param_unit = options.param_unit;
  for (PlotKind kind : find_available_plot_kinds(store, data)) {
    PlotRequest request = base;
    request.kind = kind;
    const std::string anchor = "figure-" + std::to_string(++count);
    contents.emplace_back(anchor, std::string("Figure: ") + to_string(kind));
    figures << render_figure_html(store, request, to_string(kind), anchor, work_dir, svg_files);
  }
  if (!main_metric) return figures.str();
  for (const std::string& path : data.varying_params) {
    if (path == "seed" || !is_numeric_param(data, path)) continue;
    PlotRequest request = base;
    request.kind = PlotKind::metric_vs_param;
    request.metric = *main_metric;
    request.param = path;
    const std::string anchor = "figure-" + std::to_string(++count);
    const std::string heading = *main_metric + " against " + path;
    contents.emplace_back(anchor, "Figure: " + heading);
    figures << render_figure_html(store, request, heading, anchor, work_dir, svg_files);
  }
  return figures.str();
}

// The default tables of a sweep, each in its own box, then the jobs table; added to `contents`.
std::string render_sweep_tables(const SweepData& data, const std::optional<std::string>& main_metric, Contents& contents) {
  std::ostringstream tables;
  int n = 0;
  for (const TableSpec& spec : make_default_table_specs(data)) {
    const std::string anchor = "table-" + std::to_string(++n);
    contents.emplace_back(anchor, "Table: " + spec.title);
    tables << "<div id=\"" << anchor << "\">";
    try {
      tables << format_html_table(make_table(data, spec), data, spec);
    } catch (const AnalysisError& e) {
      tables << "<p class=\"bad\">" << escape_html(spec.title + ": " + e.what()) << "</p>\n";
    }
    tables << "</div>\n";
  }
  contents.emplace_back("jobs", "Table: jobs");
  tables << "<h3 id=\"jobs\">Jobs</h3>\n" << make_jobs_table(data, main_metric);
  return tables.str();
}

std::string make_contents_nav(const Contents& contents, bool search) {
  std::ostringstream nav;
  nav << "<nav><h2>Contents</h2>\n<ul>\n";
  for (const auto& [anchor, title] : contents) nav << "<li><a href=\"#" << anchor << "\">" << escape_html(title) << "</a></li>\n";
  if (search) nav << "<li><a href=\"#Search\">Search</a></li>\n";
  for (const char* section : {"Status", "Provenance", "Spec"}) nav << "<li><a href=\"#" << section << "\">" << section << "</a></li>\n";
  nav << "</ul></nav>\n";
  return nav.str();
}

// The jobs per status, then each job that did not finish with its message.
std::string make_status_section(const ResultsStore& store, const SweepRecord& sweep, const SweepData& data) {
  std::ostringstream html;
  html << "<h2 id=\"Status\">Status</h2>\n<table><tr><th>status</th><th>jobs</th></tr>\n";
  for (const auto& [status, count] : store.count_jobs_by_status(sweep.name)) {
    html << "<tr><td>" << escape_html(status) << "</td><td class=\"num\">" << count << "</td></tr>\n";
  }
  html << "</table>\n";
  bool any_failure = false;
  for (const JobResult& job : data.jobs) {
    if (job.status == "done" || job.status == "pending" || job.status == "running") continue;
    if (!any_failure) html << "<ul class=\"bad\">\n";
    any_failure = true;
    html << "<li>" << make_job_links({&job}) << " " << escape_html(job.status + ": " + job.message + " [" + make_job_label(job) + "]")
         << "</li>\n";
  }
  if (any_failure) html << "</ul>\n";
  return html.str();
}

std::string make_provenance_section(const ResultsStore& store, const SweepRecord& sweep) {
  std::ostringstream html;
  html << "<h2 id=\"Provenance\">Provenance</h2>\n<table>\n";
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
  for (const auto& [name, value] : rows) html << "<tr><th>" << escape_html(name) << "</th><td>" << escape_html(value) << "</td></tr>\n";
  html << "</table>\n";
  return html.str();
}

// A sweep's page: contents, figures, tables (and the thesis's), search, status, provenance, spec.
std::string make_sweep_page(const ResultsStore& store, const SweepRecord& sweep, const SweepData& data,
                            const fs::path& work_dir, const ReportOptions& options) {
  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>armfarm sweep " << escape_html(sweep.name)
       << "</title>" << kStyle << "</head><body>\n";
  page << "<p><a href=\"index.html\">all sweeps</a></p>\n";
  page << "<h1>Sweep " << escape_html(sweep.name) << "</h1>\n<p>" << escape_html(sweep.description) << "</p>\n";
  // The figures and tables first (rendered now, so that the contents can list them).
  Contents contents;
  int figure_count = 0;
  const std::optional<std::string> main_metric = options.choose_main_metric ? options.choose_main_metric(data) : std::nullopt;
  const std::string figures = render_sweep_figures(store, sweep, data, work_dir, options, main_metric, contents, figure_count);
  const std::string tables = render_sweep_tables(data, main_metric, contents);
  const std::string thesis = make_thesis_section(store, sweep, options, contents);
  const std::optional<SearchSummary> search = load_search_summary(store, sweep.name);
  page << make_contents_nav(contents, search.has_value());
  page << "<h2 id=\"figures\">Figures</h2>\n" << figures;
  if (figure_count == 0) {
    page << "<p>No figure: no job records the series a figure draws (F and FF, POS and POS_D, RF), and "
         << (main_metric ? "no numeric parameter besides seed is swept" : "no main metric is chosen") << ".</p>\n";
  }
  page << "<h2 id=\"tables\">Tables</h2>\n<p>Click a column header to sort by it; a job's key opens its page.</p>\n"
       << tables << thesis;
  if (search) page << "<h2 id=\"Search\">Search</h2>\n<pre>" << escape_html(format_search_summary(*search)) << "</pre>\n";
  page << make_status_section(store, sweep, data) << make_provenance_section(store, sweep);
  page << "<h2 id=\"Spec\">Spec</h2>\n<pre>" << escape_html(sweep.spec_text) << "</pre>\n" << kSortScript
       << "\n</body></html>\n";
  return page.str();
}

// A job's page: status, parameters, metrics (unit, reason of a NULL), the figures of its
// recorded series, and its full configuration.
std::string make_job_page(const ResultsStore& store, const SweepData& data, const JobResult& job, const std::string& sweep_file,
                          const fs::path& work_dir, const ReportOptions& options) {
  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>armfarm job " << escape_html(job.key.substr(0, 8))
       << "</title>" << kStyle << "</head><body>\n<p><a href=\"index.html\">all sweeps</a> · <a href=\"" << escape_html(sweep_file)
       << "\">sweep " << escape_html(data.name) << "</a></p>\n<h1>Job <code>" << escape_html(job.key) << "</code></h1>\n";
  page << "<div class=\"scroll\"><table><tr><th>status</th><td" << (job.status == "done" ? " class=\"name\"" : " class=\"bad\"") << ">" << escape_html(job.status)
       << (job.message.empty() ? "" : ": " + escape_html(job.message)) << "</td></tr>\n<tr><th>seed</th><td class=\"num\">"
       << job.seed << "</td></tr>\n";
  for (const std::string& path : data.varying_params) {
    page << "<tr><th>" << escape_html(path) << "</th><td class=\"name\">" << escape_html(format_param_value(find_param_value(job, path)))
         << "</td></tr>\n";
  }
  page << "</table></div>\n<nav><ul><li><a href=\"#metrics\">Metrics</a></li><li><a href=\"#figures\">Figures</a></li>"
       << "<li><a href=\"#config\">Configuration</a></li></ul></nav>\n";

  page << "<h2 id=\"metrics\">Metrics</h2>\n<div class=\"scroll\"><table class=\"sortable\">\n"
       << "<tr><th>metric</th><th>joint</th><th>checkpoint</th><th>value</th><th>unit</th><th>reason</th></tr>\n";
  for (const auto& [id, value] : job.metrics) {
    const auto info = data.metric_info.find(id.name);
    const auto reason = job.reasons.find(id);
    const bool defined = std::isfinite(value);
    page << "<tr><td title=\"" << escape_html(info == data.metric_info.end() ? std::string() : info->second.meaning) << "\">"
         << escape_html(id.name) << "</td><td class=\"num\">" << (id.joint ? std::to_string(*id.joint) : "")
         << "</td><td class=\"num\">" << (id.checkpoint ? std::to_string(*id.checkpoint) : "") << "</td><td class=\"num\""
         << (defined ? " data-sort=\"" + format_sort_key(value) + "\"" : std::string()) << ">"
         << (defined ? escape_html(format_number(value, 6)) : "NULL") << "</td><td>"
         << escape_html(info == data.metric_info.end() ? std::string() : info->second.unit) << "</td><td>"
         << escape_html(reason == job.reasons.end() ? std::string() : reason->second) << "</td></tr>\n";
  }
  page << "</table></div>\n<h2 id=\"figures\">Figures</h2>\n";
  const std::vector<std::string> names = job.status == "done" ? store.find_series_names(job.id) : std::vector<std::string>();
  const auto has = [&](const char* name) { return std::find(names.begin(), names.end(), name) != names.end(); };
  std::vector<PlotKind> kinds;
  if (has("F") && has("FF")) kinds.push_back(PlotKind::signals);
  if (has("POS") && has("POS_D")) kinds.push_back(PlotKind::tracking);
  if (has("RF")) kinds.push_back(PlotKind::rf_growth);
  if (kinds.empty() && names.empty()) page << "<p>No recorded series (recording.series in the spec records them).</p>\n";
  if (kinds.empty() && !names.empty()) {
    std::string list;
    for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
    page << "<p>Recorded series: " << escape_html(list)
         << ". None is one a figure here draws (signals: F and FF, tracking: POS and POS_D, rf-growth: RF).</p>\n";
  }
  int svg_files = 0, n = 0;
  for (PlotKind kind : kinds) {
    PlotRequest request;
    request.kind = kind;
    request.sweep = data.name;
    request.job_keys = {job.key};
    request.param_unit = options.param_unit;
    page << render_figure_html(store, request, to_string(kind), "figure-" + std::to_string(++n), work_dir, svg_files);
  }
  page << "<h2 id=\"config\">Configuration</h2>\n<pre>" << escape_html(job.config.dump(2)) << "</pre>\n" << kSortScript
       << "\n</body></html>\n";
  return page.str();
}

// A description's first sentence, at most `limit` characters (cut at a space, "…" added): the
// index's rows, where a thesis spec's 1 000-character description made its row a page tall
// (the whole text is on the sweep's page).
std::string make_short_description(const std::string& text, std::size_t limit = 160) {
  std::size_t end = text.find(". ");
  end = end == std::string::npos ? text.size() : end + 1;
  if (end <= limit) return text.substr(0, end) + (end < text.size() ? " …" : "");
  std::size_t cut = text.rfind(' ', limit);
  if (cut == std::string::npos || cut == 0) cut = limit;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
  return text.substr(0, cut) + " …";
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
  row << "<tr><td class=\"name\"><a href=\"" << escape_html(file) << "\">" << escape_html(sweep.name) << "</a><br><small>"
      << escape_html(make_short_description(sweep.description)) << "</small></td>";
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
                                      const std::string& out_dir, const ReportOptions& options) {
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

  std::vector<std::string> written, failures;
  std::ostringstream index;
  index << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>armfarm report</title>" << kStyle
        << "</head><body>\n<h1>armfarm report</h1>\n<p>" << escape_html(store.path()) << "</p>\n"
        << "<div class=\"scroll\"><table class=\"sortable\">\n<tr><th>sweep</th><th>jobs</th><th>done</th>"
        << "<th>failed</th><th>diverged</th><th>started</th><th>spec hash</th><th>best by the main metric</th></tr>\n";
  // A page that cannot be written (a full disk, a failing plot) costs that page, not the index.
  const auto write_page = [&](const fs::path& path, const std::function<std::string()>& make) {
    try {
      write_text_atomically(path, make());
      written.push_back(path.string());
      return true;
    } catch (const AnalysisError& e) {
      failures.push_back(e.what());
      return false;
    }
  };
  for (const SweepRecord& record : sweeps) {
    const SweepData data = load_sweep_data(store, record.name);
    const std::string file = make_report_file_name("sweep_", record.name) + ".html";
    const fs::path work = fs::path(pattern);
    write_page(fs::path(out_dir) / file, [&] { return make_sweep_page(store, record, data, work, options); });
    for (const JobResult& job : data.jobs) {
      write_page(fs::path(out_dir) / make_job_file(job), [&] { return make_job_page(store, data, job, file, work, options); });
    }
    index << make_index_row(store, record, data, file, options.describe_best);
  }
  index << "</table></div>\n" << kSortScript << "\n</body></html>\n";
  const fs::path index_path = fs::path(out_dir) / "index.html";
  write_text_atomically(index_path, index.str());
  written.push_back(index_path.string());
  if (!failures.empty()) {
    throw AnalysisError(std::to_string(failures.size()) + " report pages not written (the index is): " + failures.front() +
                        (failures.size() > 1 ? " … and " + std::to_string(failures.size() - 1) + " more" : ""));
  }
  return written;
}

}  // namespace armfarm
