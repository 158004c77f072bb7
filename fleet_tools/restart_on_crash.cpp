#include "restart_on_crash.hpp"

#include <spdlog/spdlog.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <deque>
#include <stdexcept>
#include <thread>

#include "ctsfleet/program.hpp"

namespace coordinator {
namespace {

using Clock = std::chrono::steady_clock;

// In the child: dies with its parent and runs the work. An error the work throws goes up to the
// program's own handler (ctsfleet::Program), which reports it and ends the child with its code.
[[noreturn]] void run_child(pid_t parent, const std::function<int()>& work) {
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(1);  // the parent died before the line above
  const int code = work();
  spdlog::default_logger()->flush();
  std::fflush(nullptr);
  _exit(code);
}

// Waits for the child, passing a stop request on to it once and calling `every_second` meanwhile.
// Returns its wait status.
int wait_for_child(pid_t child, const std::function<void()>& every_second) {
  bool stop_passed_on = false;
  Clock::time_point next_call = Clock::now() + std::chrono::seconds(1);
  for (;;) {
    int status = 0;
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child) return status;
    if (done < 0 && errno != EINTR) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    if (ctsfleet::stop_requested().load() && !stop_passed_on) {
      kill(child, SIGTERM);
      stop_passed_on = true;
    }
    if (every_second && Clock::now() >= next_call) {
      every_second();
      next_call = Clock::now() + std::chrono::seconds(1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace

int run_restarting_on_crash(const std::string& what, const std::function<int()>& work, RestartPolicy policy,
                            const SupervisorHooks& hooks) {
  std::deque<Clock::time_point> crashes;  // within the last minute
  const pid_t parent = getpid();
  for (;;) {
    const pid_t child = fork();
    if (child < 0) throw std::runtime_error(std::string("cannot start ") + what + ": fork: " + std::strerror(errno));
    if (child == 0) run_child(parent, work);
    const int status = wait_for_child(child, hooks.every_second);
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    const int signal_number = WTERMSIG(status);
    if (ctsfleet::stop_requested().load()) return 128 + signal_number;  // killed while stopping: not a crash
    const Clock::time_point now = Clock::now();
    crashes.push_back(now);
    while (now - crashes.front() > std::chrono::minutes(1)) crashes.pop_front();
    if (static_cast<int>(crashes.size()) > policy.max_crashes_a_minute) {
      spdlog::error("{} crashed ({}, signal {}), {} time(s) within a minute, more than the {} allowed: not "
                    "started again", what, strsignal(signal_number), signal_number, crashes.size(),
                    policy.max_crashes_a_minute);
      return 1;
    }
    spdlog::error("{} crashed ({}, signal {}): starting it again in {} s (crash {} of at most {} a minute)", what,
                  strsignal(signal_number), signal_number, policy.pause_s, crashes.size(),
                  policy.max_crashes_a_minute);
    const Clock::time_point restart_at = now + std::chrono::duration_cast<Clock::duration>(
                                                   std::chrono::duration<double>(policy.pause_s));
    while (Clock::now() < restart_at) {
      if (ctsfleet::stop_requested().load()) return 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (hooks.before_restart) hooks.before_restart();
  }
}

}  // namespace coordinator
