// The report in a real browser (issue 24): headless Chromium renders every page of a small
// sweep's report; a probe script added to a copy of each page reports horizontal overflow of
// the page, script errors (window errors and console.error) and images that did not load.
// Skips, saying so, when Chromium is absent (.ci/install-deps installs the Debian package).
#include "support/command_line.hpp"
#include "support/test_database.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

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

}  // namespace
}  // namespace armfarm
