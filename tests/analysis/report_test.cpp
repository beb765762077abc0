// The report's pages per job, its file names for any sweep name (sweeps named alike get pages of
// their own), its figures of the main metric against the swept parameters, the thesis's values
// beside a sweep, and its pages rendered in a real browser.
#include "analysis/report.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Every href="…" of a page that is not an anchor on the page itself.
std::vector<std::string> find_page_links(const std::string& page) {
  std::vector<std::string> links;
  for (std::size_t at = page.find("href=\""); at != std::string::npos; at = page.find("href=\"", at + 1)) {
    const std::size_t start = at + 6;
    const std::string target = page.substr(start, page.find('"', start) - start);
    if (!target.empty() && target[0] != '#') links.push_back(target);
  }
  return links;
}

TEST(ReportFileNames, KeepSimpleNamesAndCutAndHashTheRest) {
  EXPECT_EQ(make_report_file_name("sweep_", "kernel"), "sweep_kernel");
  EXPECT_EQ(make_report_file_name("job_", "0123abcd"), "job_0123abcd");
  const std::string long_a(5000, 'a');
  std::string long_b = long_a;
  long_b.back() = 'b';  // differs only past the cut
  const std::string a = make_report_file_name("sweep_", long_a), b = make_report_file_name("sweep_", long_b);
  EXPECT_NE(a, b);
  EXPECT_LE(a.size(), 6u + 64u + 17u);
  for (const std::string& hostile : {std::string("../../etc/passwd"), std::string("a/b"), std::string("x\ny"), std::string(""),
                                     std::string("`touch x`"), std::string("ünïcode"), std::string(".")}) {
    const std::string name = make_report_file_name("sweep_", hostile);
    EXPECT_EQ(name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-"), std::string::npos) << name;
    EXPECT_NE(name, "sweep_") << hostile;
  }
  EXPECT_NE(make_report_file_name("sweep_", "a/b"), make_report_file_name("sweep_", "a_b"));  // replaced: hashed
}

class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_ = directory_.file("results.db");
    // Three gains × two seeds, one diverged; a recorded path for the composite jobs' pages.
    std::vector<testing::TestJob> jobs;
    for (double gain : {0.2, 1.0, 5.0}) {
      for (int seed = 1; seed <= 2; ++seed) {
        testing::TestJob job;
        job.params = {{"control.gain_scale", gain}, {"trajectory.sine.duration", 2.0 * gain}, {"seed", seed}};
        job.metrics = {{0, "tracking_nmse", std::nullopt, 0.01 / gain + 0.001 * seed, ""},
                       {0, "tracking_nmse", 1, 0.02 / gain, ""},
                       {0, "ff_fb_ratio_avg", 1, std::nullopt, "no feed-forward"}};
        if (gain == 5.0 && seed == 2) {
          job.status = "diverged";
          job.message = "joint 1 speed above its limit";
          job.metrics.clear();
        }
        if (gain == 1.0) {
          for (const char* name : {"POS", "POS_D"}) {
            SeriesRecord series;
            series.name = name;
            series.columns = {"t", "x", "y", "z"};
            series.rows.resize(50, 4);
            for (int r = 0; r < 50; ++r) {
              series.rows.row(r) << 0.1 * r, 0.5, 0.2 * std::sin(0.1 * r), 0.4 + (name[3] ? 0.0 : 0.01) + 0.1 * std::cos(0.1 * r);
            }
            job.series.push_back(series);
          }
        }
        jobs.push_back(job);
      }
    }
    testing::write_test_sweep(db_, "gains", jobs);
  }

  testing::TemporaryDirectory directory_;
  std::string db_;
};

TEST(ReportFileNames, SweepsNamedAlikeGetTwoPages) {
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("r.db");
  testing::write_test_sweep(db, "a-b", testing::make_gain_jobs());
  testing::write_test_sweep(db, "a_b", testing::make_gain_jobs());
  const auto report = testing::run_armfarm("report " + db + " --out " + directory.file("report"));
  ASSERT_EQ(report.exit_code, 0) << report.output;
  int pages = 0;
  for (const auto& entry : fs::directory_iterator(directory.file("report"))) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("sweep_a", 0) == 0 && entry.path().extension() == ".html") ++pages;  // sweep_a-b, sweep_a_b
  }
  EXPECT_EQ(pages, 2) << report.output;
}

TEST_F(ReportTest, EveryJobHasAPageWithItsConfigMetricsAndFiguresLinkedFromTheSweepTables) {
  const std::string out = directory_.file("report");
  const auto result = testing::run_armfarm("report " + db_ + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string sweep = read_file(fs::path(out) / "sweep_gains.html");
  std::set<std::string> job_pages;
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("job_", 0) == 0) job_pages.insert(name);
  }
  EXPECT_EQ(job_pages.size(), 6u);
  // The default table's rows link each of their jobs; every link of every page resolves.
  const std::size_t table = sweep.find("<table class=\"sortable\">");
  ASSERT_NE(table, std::string::npos);
  std::set<std::string> linked;
  for (const std::string& link : find_page_links(sweep)) {
    if (link.rfind("job_", 0) == 0) linked.insert(link);
  }
  EXPECT_EQ(linked, job_pages);
  for (const std::string& page : job_pages) {
    for (const std::string& link : find_page_links(read_file(fs::path(out) / page))) {
      EXPECT_TRUE(fs::exists(fs::path(out) / link)) << page << " links " << link;
    }
  }
  // A row of the gain table holds links to exactly its two seeds' jobs.
  const std::size_t row = sweep.find("<tr><td>1</td><td>2</td>", table);
  ASSERT_NE(row, std::string::npos) << sweep.substr(table, 3000);
  const std::string row_text = sweep.substr(row, sweep.find("</tr>", row) - row);
  std::size_t links_in_row = 0;
  for (auto at = row_text.find("href=\"job_"); at != std::string::npos; at = row_text.find("href=\"job_", at + 1)) ++links_in_row;
  EXPECT_EQ(links_in_row, 2u) << row_text;

  // A job page: its configuration, its metrics with unit and the reason of a NULL, its path figure.
  const ResultsStore store = ResultsStore::open(db_, ResultsStore::Mode::read_only);
  std::string composite_key, diverged_key;
  for (const JobRecord& job : store.find_jobs("gains")) {
    if (job.params.at("control.gain_scale") == 1.0) composite_key = job.key;
    if (job.status == "diverged") diverged_key = job.key;
  }
  const std::string page = read_file(fs::path(out) / (make_report_file_name("job_", composite_key) + ".html"));
  EXPECT_NE(page.find("<h2 id=\"config\">Configuration</h2>"), std::string::npos);
  EXPECT_NE(page.find("&quot;gain_scale&quot;: 1.0"), std::string::npos) << page;
  EXPECT_NE(page.find("<td>no feed-forward</td>"), std::string::npos);  // the NULL's reason
  EXPECT_NE(page.find(">NULL<"), std::string::npos);
  EXPECT_NE(page.find("<h3 id=\"figure-1\">tracking</h3>\n<svg"), std::string::npos) << page;
  EXPECT_NE(page.find("href=\"sweep_gains.html\""), std::string::npos);
  const std::string diverged = read_file(fs::path(out) / (make_report_file_name("job_", diverged_key) + ".html"));
  EXPECT_NE(diverged.find("diverged: joint 1 speed above its limit"), std::string::npos);
}

TEST_F(ReportTest, SweepPageDrawsTheMainMetricAgainstEachNumericSweptParameter) {
  const std::string out = directory_.file("report");
  ASSERT_EQ(testing::run_armfarm("report " + db_ + " --out " + out).exit_code, 0);
  const std::string sweep = read_file(fs::path(out) / "sweep_gains.html");
  for (const char* heading : {">tracking_nmse against control.gain_scale</h3>\n<svg", ">tracking_nmse against trajectory.sine.duration</h3>\n<svg"}) {
    EXPECT_NE(sweep.find(heading), std::string::npos) << heading;
  }
  EXPECT_EQ(sweep.find("against seed"), std::string::npos);  // repeats are error bars, not an axis
  // Axis labels: the readable metric name; a parameter with a unit in the key table carries it.
  EXPECT_NE(sweep.find(">tracking nMSE<"), std::string::npos);
  EXPECT_NE(sweep.find(">trajectory.sine.duration (s)<"), std::string::npos);
  EXPECT_NE(sweep.find("marked on the top edge: 1 diverged"), std::string::npos);  // the diverged job is counted
}

TEST_F(ReportTest, AFiveThousandCharacterSweepNameGetsPagesAndTheIndex) {
  // Issue 30: a 5 000-character name made `report` write 10 pages and no index.
  const std::string long_name(5000, 'n');
  std::vector<testing::TestJob> jobs(2);
  jobs[0].params = {{"control.gain_scale", 0.5}};
  jobs[0].metrics = {{0, "tracking_nmse", std::nullopt, 0.5, ""}};
  jobs[1].params = {{"control.gain_scale", 2.0}};
  jobs[1].metrics = {{0, "tracking_nmse", std::nullopt, 0.25, ""}};
  testing::write_test_sweep(db_, long_name, jobs);
  const std::string out = directory_.file("long");
  const auto result = testing::run_armfarm("report " + db_ + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output.substr(0, 500);
  const std::string index = read_file(fs::path(out) / "index.html");
  const std::string file = make_report_file_name("sweep_", long_name) + ".html";
  EXPECT_NE(index.find("href=\"" + file + "\""), std::string::npos);
  EXPECT_TRUE(fs::exists(fs::path(out) / file));
  EXPECT_NE(read_file(fs::path(out) / file).find(long_name), std::string::npos);  // the name itself is shown whole
  std::size_t pages = 0;
  for (const auto& entry : fs::directory_iterator(out)) {
    EXPECT_LE(entry.path().filename().string().size(), 100u) << entry.path();
    ++pages;
  }
  EXPECT_EQ(pages, 1u + 2u + 6u + 2u);  // index, two sweep pages, a page per job (keys of 5 000 characters too)
  // The index shows a description's first sentence or 160 characters (a thesis spec's 1 000 made
  // its row a page tall); the sweep's page shows it whole.
  EXPECT_NE(index.find("<small>test sweep …</small>"), std::string::npos);
  EXPECT_EQ(index.find("test sweep " + long_name), std::string::npos);
  EXPECT_NE(read_file(fs::path(out) / file).find("<p>test sweep " + long_name + "</p>"), std::string::npos);
}

// Issue 29: a sweep named with an ANSI escape kept the raw ESC in every page; the reader now
// sees it as its control picture (U+241B), also in a job's message and a string parameter.
TEST(ReportNames, ControlCharactersOfNamesShowAsControlPicturesAndNoneReachesAPage) {
  testing::TemporaryDirectory dir;
  const std::string db = dir.file("results.db");
  const std::string name = "red\x1b[31mname\x07\r";
  std::vector<testing::TestJob> jobs(2);
  jobs[0].params = {{"control.gain_scale", 0.5}, {"trajectory.kind", "a\x1b[2Jb"}};
  jobs[0].metrics = {{0, "tracking_nmse", std::nullopt, 0.5, ""}};
  jobs[1].params = {{"control.gain_scale", 2.0}, {"trajectory.kind", "c"}};
  jobs[1].status = "failed";
  jobs[1].message = "boom\x1b]0;title\x07\x7f";
  testing::write_test_sweep(db, name, jobs);
  const std::string out = dir.file("report");
  const auto result = testing::run_armfarm("report " + db + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  std::size_t pages = 0;
  for (const auto& entry : fs::directory_iterator(out)) {
    const std::string page = read_file(entry.path());
    ++pages;
    for (const char c : page) {
      const auto byte = static_cast<unsigned char>(c);
      EXPECT_FALSE(byte < 0x20 && c != '\n' && c != '\t') << entry.path().filename() << ": control byte " << int(byte);
      EXPECT_NE(byte, 0x7F) << entry.path().filename();
      if (byte < 0x20 && c != '\n' && c != '\t') break;
    }
  }
  EXPECT_EQ(pages, 1u + 1u + 2u);
  const std::string index = read_file(fs::path(out) / "index.html");
  EXPECT_NE(index.find("red\xE2\x90\x9B[31mname\xE2\x90\x87\xE2\x90\x8D"), std::string::npos) << index;  // ␛ ␇ ␍
  const std::string sweep = read_file(fs::path(out) / (make_report_file_name("sweep_", name) + ".html"));
  EXPECT_NE(sweep.find("a\xE2\x90\x9B[2Jb"), std::string::npos);
  EXPECT_NE(sweep.find("boom\xE2\x90\x9B]0;title\xE2\x90\x87\xE2\x90\xA1"), std::string::npos);  // … ␇ ␡
  EXPECT_NE(sweep.find("<pre>{&quot;name&quot;"), std::string::npos);  // the spec in <pre>, escaped as before
}

TEST(ReportNoFigures, PagesSayWhichSeriesAreRecordedAndWhyNoFigureIsDrawn) {
  // Review of 2026-12-03: a job with only heldout_* series and TRIAL read "No recorded series",
  // and its sweep page had an empty Figures heading.
  testing::TemporaryDirectory dir;
  const std::string db = dir.file("results.db");
  std::vector<testing::TestJob> jobs(2);
  for (int i = 0; i < 2; ++i) {
    jobs[i].params = {{"control.mode", i ? "composite" : "feedback"}, {"seed", i}};
    jobs[i].metrics = {{0, "tracking_nmse", std::nullopt, 0.1 * (i + 1), ""}};
    for (const char* name : {"heldout_F_c1", "TRIAL"}) {
      jobs[i].series.push_back(testing::make_series(name, {"t", "q1"}, 5, [](int r, int c) { return r + c; }));
    }
  }
  testing::write_test_sweep(db, "heldout", jobs);
  const std::string out = dir.file("report");
  const auto result = testing::run_armfarm("report " + db + " --out " + out);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string sweep = read_file(fs::path(out) / "sweep_heldout.html");
  EXPECT_EQ(sweep.find("<svg"), std::string::npos);
  const std::size_t figures = sweep.find("<h2 id=\"figures\">Figures</h2>\n");
  ASSERT_NE(figures, std::string::npos) << sweep;
  EXPECT_EQ(sweep.find("<p>No figure:", figures), figures + std::string("<h2 id=\"figures\">Figures</h2>\n").size()) << sweep;
  const ResultsStore store = ResultsStore::open(db, ResultsStore::Mode::read_only);
  const std::string key = store.find_jobs("heldout").at(0).key;
  const std::string page = read_file(fs::path(out) / (make_report_file_name("job_", key) + ".html"));
  EXPECT_EQ(page.find("No recorded series"), std::string::npos) << page;
  EXPECT_NE(page.find("heldout_F_c1"), std::string::npos) << page;
  EXPECT_NE(page.find("TRIAL"), std::string::npos) << page;
}

// The report in a real browser: headless Chromium renders every page of a small sweep's report;
// a probe script added to a copy of each page reports horizontal overflow of the page, script
// errors (window errors and console.error) and images that did not load. Skips, saying so, when
// Chromium is absent (.ci/install-deps installs the Debian package).

std::string find_chromium() {
  if (const char* given = std::getenv("ARMFARM_CHROMIUM")) return given;
  for (const char* path : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"}) {
    if (fs::exists(path)) return path;
  }
  return "";
}

// Runs first in <head>: collects errors. Runs on load: measures and writes the findings into a
// <pre id="armfarm-probe"> that --dump-dom prints.
const char* kProbeHead =
    "<script>window.__errors=[];window.addEventListener('error',function(e){window.__errors.push(String(e.message||"
    "(e.target&&e.target.src)||e.type));},true);var __error=console.error;console.error=function(){"
    "window.__errors.push(Array.prototype.join.call(arguments,' '));};</script>";
const char* kProbeTail =
    "<script>window.addEventListener('load',function(){var d=document.documentElement,broken=[],svgs=0;"
    "Array.prototype.forEach.call(document.images,function(i){if(!i.complete||i.naturalWidth===0)broken.push(i.src);});"
    "document.querySelectorAll('svg').forEach(function(s){var r=s.getBoundingClientRect();if(r.width>0&&r.height>0)svgs++;});"
    "var p=document.createElement('pre');p.id='armfarm-probe';p.textContent='overflow='+(d.scrollWidth-d.clientWidth)+"
    "' errors='+window.__errors.length+' broken='+broken.length+' svgs='+svgs+' first='+(window.__errors[0]||broken[0]||'');"
    "document.body.appendChild(p);});</script>";

struct PageFindings {
  bool probed = false;
  int overflow = 0, errors = 0, broken = 0, svgs = 0;
  std::string first, output;
};

PageFindings probe_page(const std::string& chromium, const fs::path& page) {
  std::ifstream in(page);
  std::ostringstream text;
  text << in.rdbuf();
  std::string html = text.str();
  html.insert(html.find("<head>") + 6, kProbeHead);
  html.insert(html.rfind("</body>"), kProbeTail);
  const fs::path probe = page.parent_path() / ("probe_" + page.filename().string());
  std::ofstream(probe) << html;
  const auto result = test_support::run_command_line(
      chromium + " --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir=" + (page.parent_path() / "profile").string() +
      " --window-size=1024,800 --virtual-time-budget=5000 --dump-dom file://" + probe.string());
  fs::remove(probe);
  PageFindings findings;
  findings.output = result.output;
  const std::size_t at = result.output.find("<pre id=\"armfarm-probe\">");
  if (at == std::string::npos) return findings;
  std::istringstream line(result.output.substr(at + 24));
  std::string overflow, errors, broken, svgs;
  line >> overflow >> errors >> broken >> svgs;
  findings.probed = true;
  findings.overflow = std::stoi(overflow.substr(9));
  findings.errors = std::stoi(errors.substr(7));
  findings.broken = std::stoi(broken.substr(7));
  findings.svgs = std::stoi(svgs.substr(5));
  std::getline(line, findings.first);
  return findings;
}

TEST(ReportInBrowser, EveryPageRendersWithoutOverflowErrorsOrBrokenImages) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "Chromium is absent (apt-get install chromium, or ARMFARM_CHROMIUM=PATH): report not rendered";
  testing::TemporaryDirectory directory;
  const std::string db = directory.file("results.db");
  // Two gains × two modes, a recorded path and torques, a long description and parameter value.
  std::vector<testing::TestJob> jobs;
  for (const char* mode : {"feedback", "composite"}) {
    for (double gain : {0.2, 1.0}) {
      testing::TestJob job;
      job.params = {{"control.mode", mode}, {"control.gain_scale", gain}, {"trajectory.recorded.file", std::string(300, 'p') + ".csv"}};
      job.metrics = {{0, "tracking_nmse", std::nullopt, 0.01 / gain, ""}, {0, "ff_fb_ratio_avg", 1, std::nullopt, "no feed-forward"}};
      for (const char* name : {"POS", "POS_D", "F", "FF", "TOR"}) {
        SeriesRecord series;
        series.name = name;
        series.columns = name[0] == 'P' ? std::vector<std::string>{"t", "x", "y", "z"} : std::vector<std::string>{"t", "j1", "j2"};
        series.rows.resize(40, static_cast<Eigen::Index>(series.columns.size()));
        for (int r = 0; r < 40; ++r) {
          for (Eigen::Index c = 0; c < series.rows.cols(); ++c) series.rows(r, c) = c == 0 ? 0.1 * r : std::sin(0.1 * r * c) / gain;
        }
        job.series.push_back(series);
      }
      jobs.push_back(job);
    }
  }
  jobs.back().status = "diverged";
  jobs.back().message = std::string(400, 'm');  // a long unbroken message must wrap, not widen the page
  testing::write_test_sweep(db, "browser", jobs);
  const fs::path out = directory.file("report");
  const auto report = testing::run_armfarm("report " + db + " --out " + out.string() + " --against " + ARMFARM_SOURCE_DIR +
                                           "/sweeps/thesis/thesis_results.json");
  ASSERT_EQ(report.exit_code, 0) << report.output;

  int pages = 0;
  for (const auto& entry : fs::directory_iterator(out)) {
    if (entry.path().extension() != ".html") continue;
    const PageFindings findings = probe_page(chromium, entry.path());
    ASSERT_TRUE(findings.probed) << entry.path() << ": no probe result from Chromium: " << findings.output.substr(0, 2000);
    EXPECT_LE(findings.overflow, 0) << entry.path().filename() << " overflows horizontally by " << findings.overflow << " px";
    EXPECT_EQ(findings.errors, 0) << entry.path().filename() << ": " << findings.first;
    EXPECT_EQ(findings.broken, 0) << entry.path().filename() << ": " << findings.first;
    if (entry.path().filename() == "sweep_browser.html") {
      EXPECT_GE(findings.svgs, 3);  // signals, tracking, tracking_nmse vs gain
    }
    ++pages;
  }
  EXPECT_EQ(pages, 1 + 1 + 4);  // index, the sweep, a page per job

  // The probe can fail: a page with a script error, a missing image and a too-wide element.
  const fs::path bad = out / "bad.html";
  std::ofstream(bad) << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"></head><body><div style=\"width:3000px\">x</div>"
                        "<img src=\"missing.png\"><script>no_such_function();</script></body></html>";
  const PageFindings findings = probe_page(chromium, bad);
  ASSERT_TRUE(findings.probed) << findings.output.substr(0, 2000);
  EXPECT_GT(findings.overflow, 1000);
  EXPECT_GE(findings.errors, 1);
  EXPECT_EQ(findings.broken, 1);
}

TEST(ReportAgainst, SweepPageShowsTheThesisValueBesideArmfarms) {
  testing::TemporaryDirectory dir;
  const std::string db = dir.file("results.db");
  std::vector<testing::TestJob> jobs(1);
  jobs[0].params = {{"control.mode", "composite"}, {"control.feed_forward", "learner"}, {"active_joints", {1, 2, 3, 4, 5, 6}}};
  jobs[0].metrics = {{0, "ff_fb_ratio_avg", 1, 0.456195, ""}, {0, "fb_abs_avg", 6, 0.001557, ""}, {0, "ff_fb_ratio_avg", 6, 0.7, ""}};
  testing::write_test_sweep(db, "table6_4_sine", jobs);
  const std::string thesis = std::string(ARMFARM_SOURCE_DIR) + "/sweeps/thesis/thesis_results.json";
  const std::string out = dir.file("report");
  const auto result = testing::run_armfarm("report " + db + " --out " + out + " --against " + thesis);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string page = read_file(fs::path(out) / "sweep_table6_4_sine.html");
  EXPECT_NE(page.find("<h2 id=\"thesis\">Thesis</h2>"), std::string::npos);
  EXPECT_NE(page.find("<a href=\"#thesis\">Thesis</a>"), std::string::npos);
  EXPECT_NE(page.find("<th>thesis</th><th>armfarm</th><th>armfarm/thesis</th>"), std::string::npos);
  // The same cell `table --against` prints: thesis 0.912390, armfarm 0.4562, ratio 0.5, one seed.
  const std::size_t row = page.find("<td>Joint 1</td><td>avg(ff/fb)</td>");
  ASSERT_NE(row, std::string::npos) << page;
  const std::string cells = page.substr(row, page.find("</tr>", row) - row);
  std::size_t at = 0;
  for (const char* cell : {">0.912390</td>", ">0.4562</td>", ">0.5</td>", ">1</td>", "<td>one seed</td>"}) {
    at = cells.find(cell, at);
    EXPECT_NE(at, std::string::npos) << cell << " in " << cells;
  }
  EXPECT_NE(page.find("<td>one seed</td>"), std::string::npos);
  // The digits of `table --against` (4 significant): 0.7 / 0.803066 is 0.8717, not 0.871659.
  const std::size_t joint6 = page.find("<td>Joint 6</td><td>avg(ff/fb)</td>");
  ASSERT_NE(joint6, std::string::npos);
  const std::string ratio_row = page.substr(joint6, page.find("</tr>", joint6) - joint6);
  EXPECT_NE(ratio_row.find(">0.8717</td>"), std::string::npos) << ratio_row;
  EXPECT_EQ(ratio_row.find(">0.871659"), std::string::npos) << ratio_row;  // (its sort key keeps every digit)
  const auto table = testing::run_armfarm("table " + db + " --against " + thesis);
  EXPECT_NE(table.output.find("| Joint 6 | avg(ff/fb) | 0.803066 | 0.7 (1) | 0.8717 |"), std::string::npos) << table.output;
  // Without --against the section is absent.
  ASSERT_EQ(testing::run_armfarm("report " + db + " --out " + dir.file("plain")).exit_code, 0);
  EXPECT_EQ(read_file(fs::path(dir.file("plain")) / "sweep_table6_4_sine.html").find("id=\"thesis\""), std::string::npos);
  // A file that does not parse: one line, exit 2, no page.
  const std::string bad = dir.file("bad.json");
  std::ofstream(bad) << "{";
  const auto failure = testing::run_armfarm("report " + db + " --out " + dir.file("bad") + " --against " + bad);
  EXPECT_EQ(failure.exit_code, 2);
  EXPECT_FALSE(fs::exists(fs::path(dir.file("bad")) / "index.html"));
}

}  // namespace
}  // namespace armfarm
