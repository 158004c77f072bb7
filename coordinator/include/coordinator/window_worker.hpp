// WindowWorker: lifelong windows (window_planner.hpp) planned on a thread of their own, so that the
// coordinator's loop goes on meanwhile (robots' states, commands, heartbeats): with hundreds of
// robots a window takes tens of milliseconds, which the loop would otherwise spend not sending
// moves. One window at a time. The loop hands over a self-contained job (where the plan ends, what
// each robot heads for), polls for the window, and takes it only if the plan still ends where the
// job started (fleet_coordinator_windows.cpp); a window for a plan replaced meanwhile is dropped.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "coordinator/window_planner.hpp"

namespace coordinator {

struct WindowJob {
  int epoch = 0;        // the plan it extends ...
  int plan_steps = 0;   // ... from its end at this step
  planner_core::Poses from;
  std::vector<WindowAgent> agents;
  int steps = 5;
  double budget_s = 0.25;
};

struct WindowOutcome {
  WindowJob job;        // handed back
  PlanWindow window;
  std::string error;    // a step failed its check (a bug: nothing of it may be sent)
  double planning_ms = 0;
};

class WindowWorker {
 public:
  explicit WindowWorker(std::unique_ptr<WindowPlanner> planner);
  ~WindowWorker();  // cuts the window under way short and waits for its thread
  WindowWorker(const WindowWorker&) = delete;
  WindowWorker& operator=(const WindowWorker&) = delete;

  // Starts planning `job`; only while idle().
  void start(WindowJob job);
  // The outcome once the window is planned (then idle again), else nothing.
  std::optional<WindowOutcome> poll();
  // No window under way and none uncollected.
  bool idle() const;

 private:
  void run();

  std::unique_ptr<WindowPlanner> planner_;  // used by the worker's thread only
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<WindowJob> job_;
  std::optional<WindowOutcome> outcome_;
  bool busy_ = false;
  bool quit_ = false;
  std::atomic<bool> cancel_{false};
  std::thread thread_;  // last: starts once the members above exist
};

}  // namespace coordinator
