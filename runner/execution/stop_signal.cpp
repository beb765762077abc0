#include "runner/execution/stop_signal.hpp"

#include <csignal>

namespace armfarm {
namespace {

// A signal handler can only reach file-scope state: these are the one exception to
// "no static mutable state", and only the handler writes them.
std::atomic<bool> g_stop_requested{false};
std::atomic<int> g_signal_number{0};
std::atomic<bool> g_stop_at_once{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the stop flag must be safe to set in a signal handler");

struct sigaction g_previous_int {};
struct sigaction g_previous_term {};
struct sigaction g_previous_usr1 {};

extern "C" void handle_stop_signal(int signal_number) {
  g_signal_number.store(signal_number);
  if (signal_number != SIGUSR1) g_stop_at_once.store(true);
  g_stop_requested.store(true);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

}  // namespace

StopSignalScope::StopSignalScope() {
  g_stop_requested.store(false);
  g_stop_at_once.store(false);
  g_signal_number.store(0);
  struct sigaction action {};
  action.sa_handler = handle_stop_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &g_previous_int);
  sigaction(SIGTERM, &action, &g_previous_term);
  // Slurm's warning before a time limit or preemption (sbatch --signal=B:USR1@T, forwarded by the
  // task script): the same stop. It keeps this handler, so a second warning does not kill.
  sigaction(SIGUSR1, &action, &g_previous_usr1);
}

StopSignalScope::~StopSignalScope() {
  sigaction(SIGINT, &g_previous_int, nullptr);
  sigaction(SIGTERM, &g_previous_term, nullptr);
  sigaction(SIGUSR1, &g_previous_usr1, nullptr);
}

const std::atomic<bool>& StopSignalScope::stop_requested() const { return g_stop_requested; }

const std::atomic<bool>& StopSignalScope::stop_at_once() const { return g_stop_at_once; }

int StopSignalScope::signal_number() const { return g_signal_number.load(); }

}  // namespace armfarm
