// Running a program's work in a child process that is started again when it crashes: for
// ctsfleet-discovery, whose Fast DDS 2.9.1 server can abort on an assertion of its own (see
// docs/ARCHITECTURE.md, "Fast DDS discovery server").
#pragma once

#include <functional>
#include <string>

namespace coordinator {

struct RestartPolicy {
  int max_crashes_a_minute = 5;  // one more within a minute ends it; 0: a crash is never restarted
  double pause_s = 1.0;          // between a crash and the new start
};

// What the supervising process does besides waiting (both optional).
struct SupervisorHooks {
  std::function<void()> every_second;    // while the child runs
  std::function<void()> before_restart;  // after a crash, before the child is started again
};

// Runs `work` in a child process and returns its exit code. A child killed by a signal (an abort,
// a segfault, the kernel's OOM killer) is started again after `policy.pause_s`, and that is logged
// with the signal; more than `policy.max_crashes_a_minute` crashes within a minute end it with
// exit 1. SIGINT/SIGTERM to this process (ctsfleet::stop_requested) are passed on to the child,
// and the child is sent SIGTERM if this process dies, so no child outlives it. Call it before
// any thread is started: the child is a fork of this process.
int run_restarting_on_crash(const std::string& what, const std::function<int()>& work, RestartPolicy policy,
                            const SupervisorHooks& hooks = {});

}  // namespace coordinator
