// `armfarm run` on a spec with a search (fake jobs): the trial sequence stored in search_steps
// (trial, rung, visibility, kind, job key, objective) is identical at -j1 and -j2 and after a
// runner is killed with SIGKILL mid-search and resumed at another thread count.
#include <gtest/gtest.h>

#include "support/scratch_file.hpp"
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

namespace armfarm {
namespace {

namespace fs = std::filesystem;

pid_t start(const std::vector<std::string>& arguments, const std::string& output_path) {
  const pid_t pid = fork();
  if (pid == 0) {
    setenv("ARMFARM_FAKE_JOBS", "1", 1);
    if (freopen(output_path.c_str(), "w", stdout) == nullptr) _exit(126);
    dup2(fileno(stdout), fileno(stderr));
    std::vector<char*> argv = {const_cast<char*>(ARMFARM_BINARY)};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(ARMFARM_BINARY, argv.data());
    _exit(127);
  }
  return pid;
}

int wait_exit_code(pid_t pid) {
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::vector<std::string> query(const std::string& db, const std::string& sql) {
  std::vector<std::string> rows;
  sqlite3* handle = nullptr;
  if (sqlite3_open_v2(db.c_str(), &handle, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    sqlite3_close(handle);
    return rows;
  }
  sqlite3_busy_timeout(handle, 2000);
  sqlite3_exec(
      handle, sql.c_str(),
      [](void* out, int n, char** values, char**) {
        std::string row;
        for (int i = 0; i < n; ++i) row += (i ? "|" : "") + std::string(values[i] ? values[i] : "NULL");
        static_cast<std::vector<std::string>*>(out)->push_back(row);
        return 0;
      },
      &rows, nullptr);
  sqlite3_close(handle);
  return rows;
}

const char* const kSteps =
    "SELECT st.step, st.trial, st.rung, st.visible, st.kind, j.key, st.objective, t.params FROM search_steps st "
    "JOIN jobs j ON j.id = st.job_id JOIN search_trials t ON t.search_id = st.search_id AND t.trial = st.trial "
    "ORDER BY st.step";

class CmdRunSearchTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = test_support::make_scratch_folder("run_search");
    std::ofstream(path("search.json")) << R"({"name": "fake search", "base": {"fake": {"sleep_ms": 80}},
      "sweep": {"search": {"method": "tpe", "seed": 3, "slots": 2,
        "objective": {"metric": "tracking_nmse", "joint": 1},
        "space": {"control.gain_scale": {"uniform": [0.5, 50]}, "learning.lwpr.init_D": {"log_uniform": [0.01, 100]}},
        "budget": {"jobs": 14}}}})";
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  int run(const std::string& db, const std::string& threads) {
    return wait_exit_code(start({"run", path("search.json"), "--db", db, "-j", threads, "-q", "--claim-timeout", "1"},
                                path(db.substr(db.rfind('/') + 1) + ".txt")));
  }
  fs::path folder_;
};

TEST_F(CmdRunSearchTest, TheTrialSequenceIsTheSameAtJ1J2AndAfterAKillAndResume) {
  ASSERT_EQ(run(path("j1.db"), "1"), 0);
  const std::vector<std::string> reference = query(path("j1.db"), kSteps);
  ASSERT_EQ(reference.size(), 14u);  // the budget: 14 jobs
  EXPECT_EQ(query(path("j1.db"), "SELECT count(*) FROM search_steps WHERE committed = 1"), std::vector<std::string>{"14"});
  ASSERT_EQ(run(path("j2.db"), "2"), 0);
  EXPECT_EQ(query(path("j2.db"), kSteps), reference);

  // Killed once 5 jobs are done, while jobs run; resumed at -j1.
  const std::string killed = path("killed.db");
  const pid_t victim = start({"run", path("search.json"), "--db", killed, "-j", "2", "-q"}, path("victim.txt"));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    const std::vector<std::string> done = query(killed, "SELECT count(*) FROM jobs WHERE status = 'done'");
    if (!done.empty() && std::stoi(done[0]) >= 5) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(victim, SIGKILL);
  ASSERT_EQ(wait_exit_code(victim), 128 + SIGKILL) << "the search ended before it could be killed";
  ASSERT_LT(std::stoi(query(killed, "SELECT count(*) FROM search_steps WHERE committed = 1").at(0)), 14);
  ASSERT_EQ(run(killed, "1"), 0);
  EXPECT_EQ(query(killed, kSteps), reference);
}

}  // namespace
}  // namespace armfarm
