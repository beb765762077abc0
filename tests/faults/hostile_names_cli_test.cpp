// Issue 30, cases 3, 4 and 8 (ANSI escapes) through the built binary: a database someone else
// made, whose sweep name and a swept parameter's values hold backticks, $(...), quotes, @ macros,
// newlines, HTML and ANSI escapes, goes through plot, report, table (every format), export,
// status and slurm (scripts checked by `bash -n` and run, the array task and the merge, with a
// stand-in sbatch). Nothing is executed (the sentinel file never appears, the victim folder stays),
// every output parses (SVG as XML with tinyxml2, JSON with nlohmann, CSV with equal column counts,
// HTML tag-balanced) and what reaches the terminal holds no escape. A NUL in a spec is refused.
#include <gtest/gtest.h>

#include "support/armfarm_process.hpp"
#include "support/command_line.hpp"
#include "support/scratch_file.hpp"
#include "support/text_file.hpp"

#include <nlohmann/json.hpp>
#include <sqlite3.h>
#include <tinyxml2.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace armfarm {
namespace {

namespace fs = std::filesystem;
using test_support::read_output;
using test_support::read_text_file;
using test_support::start_armfarm;
using test_support::wait_armfarm;

// Field counts of every record of RFC 4180 CSV text ("..." quoting with "" inside; '#' lines are notes).
std::vector<std::size_t> count_csv_fields(const std::string& text) {
  std::vector<std::size_t> counts;
  std::size_t fields = 1;
  bool quoted = false, line_start = true, comment = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (line_start && c == '#') comment = true;
    line_start = false;
    if (comment) {
      if (c == '\n') comment = false, line_start = true;
      continue;
    }
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        ++i;
      } else if (c == '"') {
        quoted = false;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      ++fields;
    } else if (c == '\n') {
      counts.push_back(fields);
      fields = 1;
      line_start = true;
    }
  }
  EXPECT_FALSE(quoted) << "a quoted field is not closed";
  return counts;
}

// Every table of the file (tables are separated by an empty line) has one column count.
void expect_csv_rectangular(const fs::path& path) {
  const std::string text = read_text_file(path);
  const std::vector<std::size_t> counts = count_csv_fields(text);
  ASSERT_GT(counts.size(), 1u) << path;
  // Records that are empty lines end a table (a field count of 1 from an empty line).
  std::size_t header = 0;
  std::size_t at = 0;  // offset of the record's start, to tell an empty line from a one-field record
  std::vector<bool> empty;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    empty.push_back(at < text.size() && text[at] == '\n');
    // Advance to the next record's start: past this record's fields (quoted newlines included).
    bool quoted = false;
    while (at < text.size() && (quoted || text[at] != '\n')) {
      if (text[at] == '"') quoted = !quoted;
      ++at;
    }
    ++at;
  }
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (empty[i]) {
      header = i + 1;
      continue;
    }
    EXPECT_EQ(counts[i], counts[header]) << path << " record " << i + 1;
  }
}

void expect_xml(const fs::path& path) {
  tinyxml2::XMLDocument document;
  EXPECT_EQ(document.LoadFile(path.c_str()), tinyxml2::XML_SUCCESS) << path << ": " << document.ErrorStr();
}

// HTML elements open and close in order (void elements, comments, the doctype, and the bodies of
// script and style set aside), and no '<' of a name reached the page as a tag. A plain scanner:
// std::regex recurses per character and overflows the stack on a long script body.
void expect_html_balanced(const fs::path& path) {
  const std::string html = read_text_file(path);
  const std::set<std::string> void_elements = {"meta", "br", "img", "link", "input", "hr", "col", "source", "wbr"};
  std::vector<std::string> open;
  std::size_t at = 0;
  while ((at = html.find('<', at)) != std::string::npos) {
    if (html.compare(at, 4, "<!--") == 0) {
      at = html.find("-->", at);
      ASSERT_NE(at, std::string::npos) << path << ": a comment is not closed";
      continue;
    }
    const std::size_t end = html.find('>', at);
    ASSERT_NE(end, std::string::npos) << path << ": a tag is not closed";
    const std::string tag = html.substr(at + 1, end - at - 1);
    at = end + 1;
    if (tag.empty() || tag[0] == '!') continue;  // the doctype
    const bool closing = tag[0] == '/';
    std::size_t name_end = closing ? 1 : 0;
    while (name_end < tag.size() && std::isalnum(static_cast<unsigned char>(tag[name_end]))) ++name_end;
    const std::string name = tag.substr(closing ? 1 : 0, name_end - (closing ? 1 : 0));
    ASSERT_FALSE(name.empty()) << path << ": '<" << tag << ">' is not a tag";
    if (void_elements.count(name) || tag.back() == '/') continue;
    if (closing) {
      ASSERT_FALSE(open.empty()) << path << ": </" << name << "> closes nothing";
      ASSERT_EQ(open.back(), name) << path << ": </" << name << "> closes <" << open.back() << ">";
      open.pop_back();
    } else {
      EXPECT_NE(name, "b") << path << ": a name's <b> became a tag";
      open.push_back(name);
      if (name == "script" || name == "style") {  // their bodies are not HTML
        at = html.find("</" + name + ">", at);
        ASSERT_NE(at, std::string::npos) << path << ": <" << name << "> is not closed";
      }
    }
  }
  EXPECT_TRUE(open.empty()) << path << ": " << open.size() << " elements left open";
}

class HostileNamesCli : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = test_support::make_scratch_folder("faults_hostile");
    // Short paths, outside the folder: the names quote them, and a report page is named after
    // the sweep (a file name is at most 255 bytes).
    sentinel_ = "/tmp/afs-" + std::to_string(getpid());
    victim_ = "/tmp/afv-" + std::to_string(getpid());
    fs::remove(sentinel_);
    fs::create_directories(victim_);
  }
  void TearDown() override {
    fs::remove_all(folder_);
    fs::remove(sentinel_);
    fs::remove_all(victim_);
  }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  // Every command that could run one: "`touch S`", "$(touch S)", and gnuplot's own `...`.
  std::string make_commands() const { return "`touch " + sentinel_ + "`$(touch " + sentinel_ + ")"; }
  // `armfarm ARGS` (fake jobs, no shell): its exit code; its output in `output`.
  int armfarm(const std::vector<std::string>& arguments, std::string& output) const {
    const auto process = start_armfarm(arguments, path("out.txt"));
    const int code = wait_armfarm(process);
    output = read_output(process);
    return code;
  }
  void expect_nothing_ran(const std::string& step) const {
    EXPECT_FALSE(fs::exists(sentinel_)) << step << " ran a command";
    EXPECT_TRUE(fs::exists(victim_)) << step << " removed " << victim_;
  }

  /// Runs path("h.json"), a sweep named `name` of 4 fake jobs (init_D 10, 20 against figure8
  /// and circle), into `db`.
  void run_sweep(const std::string& name, const std::string& db) const {
    std::ofstream(path("h.json")) << nlohmann::json{
        {"name", name},
        {"base", {{"fake", {{"sleep_ms", 1}}}, {"simulation", {{"samples", 50}}}}},
        {"sweep", {{"grid", {{"learning.lwpr.init_D", {10, 20}}, {"trajectory.kind", {"figure8", "circle"}}}}}}}.dump();
    std::string output;
    ASSERT_EQ(armfarm({"run", path("h.json"), "--db", db, "-q"}, output), 0) << output;
  }

  /// Makes `db` someone else's: the sweep's name becomes `stored_name` (in sweeps and jobs), and
  /// the swept value "circle" becomes `value` (in sweep_jobs and jobs).
  static void store_hostile_names(const std::string& db, const std::string& stored_name, const std::string& value) {
    sqlite3* handle = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &handle), SQLITE_OK);
    ASSERT_NO_FATAL_FAILURE(update_rows(handle, "UPDATE sweeps SET name = ?1", stored_name));
    ASSERT_NO_FATAL_FAILURE(update_rows(handle, "UPDATE jobs SET sweep = ?1", stored_name));
    for (const char* table : {"sweep_jobs", "jobs"}) {
      const std::string sql = std::string("UPDATE ") + table +
                              " SET params = json_set(params, '$.\"trajectory.kind\"', ?1) "
                              "WHERE json_extract(params, '$.\"trajectory.kind\"') = 'circle'";
      ASSERT_NO_FATAL_FAILURE(update_rows(handle, sql, value));
    }
    sqlite3_close(handle);
  }
  /// Runs the UPDATE `sql` with `text` bound to ?1.
  static void update_rows(sqlite3* handle, const std::string& sql, const std::string& text) {
    sqlite3_stmt* update = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(handle, sql.c_str(), -1, &update, nullptr), SQLITE_OK);
    sqlite3_bind_text(update, 1, text.c_str(), -1, SQLITE_TRANSIENT);
    EXPECT_EQ(sqlite3_step(update), SQLITE_DONE);
    sqlite3_finalize(update);
  }

  /// `export --metrics` of the sweep parses as CSV; `key` is set to a job key read from it.
  void export_metrics_and_find_a_key(const std::string& db, const std::string& stored_name, std::string& key) const {
    std::string keys;
    ASSERT_EQ(armfarm({"export", db, "--metrics", "--sweep", stored_name, "-o", path("metrics.csv")}, keys), 0) << keys;
    expect_csv_rectangular(path("metrics.csv"));
    const std::string text = read_text_file(path("metrics.csv"));
    const std::smatch found = [&] {
      std::smatch m;
      std::regex_search(text, m, std::regex("[0-9a-f]{32}"));
      return m;
    }();
    ASSERT_FALSE(found.empty()) << text;
    key = found.str();
  }

  /// plot: the name as title, the hostile values as legends, then also as the axis labels; both
  /// SVGs are XML and the first holds no escape.
  void expect_plots_parse(const std::string& db, const std::string& name, const std::string& stored_name,
                          const std::string& value) const {
    std::string output;
    ASSERT_EQ(armfarm({"plot", db, "metric-vs-param", "--metric", "same_run_test_nmse", "--param", "learning.lwpr.init_D",
                       "--group", "trajectory.kind", "--out", path("p.svg")},
                      output),
              0)
        << output;
    expect_xml(path("p.svg"));
    EXPECT_EQ(read_text_file(path("p.svg")).find('\x1b'), std::string::npos);
    ASSERT_EQ(armfarm({"plot", db, "metric-vs-param", "--metric", "tracking_nmse", "--joint", "1", "--param",
                       "learning.lwpr.init_D", "--group", "trajectory.kind", "--title", stored_name, "--xlabel", value,
                       "--ylabel", name, "--out", path("s.svg")},
                      output),
              0)
        << output;
    expect_xml(path("s.svg"));
  }

  /// report: every page tag-balanced, every figure XML, the index and the sweep's page at least.
  void expect_report_parses(const std::string& db) const {
    std::string output;
    ASSERT_EQ(armfarm({"report", db, "--out", path("report")}, output), 0) << output;
    std::size_t pages = 0;
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(path("report"))) {
      if (entry.path().extension() == ".html") ++pages, expect_html_balanced(entry.path());
      if (entry.path().extension() == ".svg") expect_xml(entry.path());
    }
    EXPECT_GE(pages, 2u);  // the index and the sweep's page
  }

  /// table in every format (text for a terminal holds no escape, JSON documents parse, CSV is
  /// rectangular), and the sweep's and a job's series exports are rectangular CSV.
  void expect_tables_and_exports_parse(const std::string& db, const std::string& stored_name, const std::string& key) const {
    std::string output;
    for (const std::string format : {"md", "csv", "latex", "json"}) {
      ASSERT_EQ(armfarm({"table", db, "--format", format}, output), 0) << format << ": " << output;
      // Text for a terminal holds no escape; csv and json are data (json writes \u001b).
      if (format == "md" || format == "latex" || format == "json") {
        EXPECT_EQ(output.find('\x1b'), std::string::npos) << format;
      }
      if (format == "json") {
        ASSERT_NO_FATAL_FAILURE(expect_json_documents(output));
      }
      if (format == "csv") {
        std::ofstream(path("table.csv")) << output;
        expect_csv_rectangular(path("table.csv"));
      }
    }
    ASSERT_EQ(armfarm({"export", db, "--sweep", stored_name, "-o", path("series.csv")}, output), 0) << output;
    expect_csv_rectangular(path("series.csv"));
    ASSERT_EQ(armfarm({"export", db, "--job", key, "--series", "POS", "-o", path("job.csv")}, output), 0) << output;
    expect_csv_rectangular(path("job.csv"));
  }
  /// One JSON document per table, one after the other: each parses, and nothing else is there.
  static void expect_json_documents(const std::string& output) {
    std::istringstream in(output);
    int documents = 0;
    while ((in >> std::ws).peek() != EOF) {
      nlohmann::json parsed;
      ASSERT_NO_THROW(in >> parsed) << output;
      EXPECT_TRUE(parsed.is_object());
      ++documents;
    }
    EXPECT_GE(documents, 1);
  }

  /// status: what reaches the terminal holds no escape (before: the name's ESC[2J printed raw).
  void expect_status_shows_no_escape(const std::string& db) const {
    std::string output;
    EXPECT_EQ(armfarm({"status", db}, output), 0) << output;
    EXPECT_EQ(output.find('\x1b'), std::string::npos) << output;
    EXPECT_EQ(output.find('\x07'), std::string::npos) << output;
    EXPECT_NE(output.find("sweep rep`touch "), std::string::npos) << output;  // the name is shown, as text
  }

  /// slurm for a sweep named `name` (3 fake jobs, 2 tasks): the dry run holds no escape, the
  /// scripts parse, and running them (array task and merge, a stand-in sbatch that runs what it
  /// is given) runs no user string and merges every job.
  void expect_slurm_scripts_parse_and_merge(const std::string& name) const {
    std::ofstream(path("slurm.json")) << nlohmann::json{
        {"name", name},
        {"base", {{"fake", {{"sleep_ms", 1}}}}},
        {"sweep", {{"grid", {{"learning.lwpr.init_D", {10, 20, 30}}}}}}}.dump();
    const std::string slurm_db = path("slurm.db");
    std::string output;
    ASSERT_EQ(armfarm({"slurm", path("slurm.json"), "--db", slurm_db, "--tasks", "2", "--dry-run"}, output), 0) << output;
    EXPECT_EQ(output.find('\x1b'), std::string::npos);
    const fs::path bin = folder_ / "bin";
    fs::create_directories(bin);
    // The stand-in sbatch runs the script it is given with bash (tasks 0 and 1 for an array, their
    // output into SCRIPT.log) and prints a job id the way --parsable does.
    std::ofstream(bin / "sbatch") << "#!/bin/bash\nscript=\"${@: -1}\"\n"
                                     "if grep -q '^#SBATCH --array' \"$script\"; then\n"
                                     "  for t in 0 1; do SLURM_ARRAY_TASK_ID=$t SLURM_ARRAY_TASK_COUNT=2 bash \"$script\" >> \"$script.log\" 2>&1 || exit 1; done\n"
                                     "else bash \"$script\" >> \"$script.log\" 2>&1 || exit 1; fi\necho 4242\n";
    fs::permissions(bin / "sbatch", fs::perms::owner_all);
    const test_support::CommandResult submitted = test_support::run_command_line(
        "cd '" + folder_.string() + "' && PATH='" + bin.string() + "':$PATH " + ARMFARM_FAKE_JOBS_BINARY +
        " slurm '" + path("slurm.json") + "' --db '" + slurm_db + "' --tasks 2 --submit");
    EXPECT_EQ(submitted.exit_code, 0) << submitted.output;
    std::size_t scripts = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder_)) {
      if (entry.path().extension() != ".sbatch") continue;
      ++scripts;
      const test_support::CommandResult parsed = test_support::run_command_line("bash -n '" + entry.path().string() + "'");
      EXPECT_EQ(parsed.exit_code, 0) << entry.path() << ": " << parsed.output;
      EXPECT_EQ(read_text_file(entry.path()).find('\x1b'), std::string::npos) << entry.path();
    }
    EXPECT_EQ(scripts, 2u);
    EXPECT_EQ(armfarm({"status", slurm_db}, output), 0) << output;  // the merge ran: every job there
    EXPECT_NE(output.find(": 3 jobs, 3 done"), std::string::npos) << output;
  }

  /// A NUL is refused at validation: one line naming the file and the place, no database.
  void expect_nul_refused() const {
    std::string output;
    std::ofstream(path("nul.json")) << R"({"name": "a\u0000b", "base": {"fake": {"sleep_ms": 1}}})";
    EXPECT_EQ(armfarm({"run", path("nul.json"), "--db", path("nul.db")}, output), 2) << output;
    EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
    EXPECT_EQ(output.rfind("armfarm: " + path("nul.json") + ": ", 0), 0u) << output;
    EXPECT_FALSE(fs::exists(path("nul.db")));
  }

  fs::path folder_;
  std::string sentinel_;
  fs::path victim_;
};

// The steps in order, each stopping the test at its first fatal failure as the one body they
// were did; after each, no command ran.
TEST_F(HostileNamesCli, NothingRunsAndEveryOutputParses) {
  // What a spec may hold (control characters are refused there: see the NUL at the end) ...
  const std::string name = "rep" + make_commands() + "'q\"@a @b <b>&amp;";
  const std::string db = path("h.db");
  ASSERT_NO_FATAL_FAILURE(run_sweep(name, db));
  // ... and what someone else's database may hold: a newline, rm -rf, ANSI escapes, a hostile value.
  const std::string stored_name = name + "\nrm -rf " + victim_.string() + "\n#\x1b[2J\x1b]0;title\x07";
  const std::string value = "k" + make_commands() + "@x\n'y\"\x1b[31m";
  ASSERT_NO_FATAL_FAILURE(store_hostile_names(db, stored_name, value));
  std::string key;
  ASSERT_NO_FATAL_FAILURE(export_metrics_and_find_a_key(db, stored_name, key));
  expect_nothing_ran("export --metrics");
  ASSERT_NO_FATAL_FAILURE(expect_plots_parse(db, name, stored_name, value));
  expect_nothing_ran("plot");
  ASSERT_NO_FATAL_FAILURE(expect_report_parses(db));
  expect_nothing_ran("report");
  ASSERT_NO_FATAL_FAILURE(expect_tables_and_exports_parse(db, stored_name, key));
  expect_nothing_ran("table and export");
  expect_status_shows_no_escape(db);
  ASSERT_NO_FATAL_FAILURE(expect_slurm_scripts_parse_and_merge(name));
  expect_nothing_ran("slurm");
  expect_nul_refused();
}

}  // namespace
}  // namespace armfarm
