// WindowWorker: lifelong windows (window_planner.hpp) planned on a thread of their own
// (worker_thread.hpp), so that the coordinator's loop goes on meanwhile (robots' states, commands,
// heartbeats): with hundreds of robots a window takes tens of milliseconds, which the loop would
// otherwise spend not sending moves. One window at a time. The loop hands over a self-contained
// job (where the plan ends, what each robot heads for), polls for the window, and takes it only if
// the plan still ends where the job started (fleet_coordinator_windows.cpp); a window for a plan
// replaced meanwhile is dropped.
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coordinator/window_planner.hpp"
#include "coordinator/worker_thread.hpp"

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

  // Starts planning `job`; only while idle() (else std::logic_error).
  void start(WindowJob job) { thread_.start(std::move(job)); }
  // The outcome once the window is planned (then idle again), else nothing.
  std::optional<WindowOutcome> poll() { return thread_.poll(); }
  // No window under way and none uncollected.
  bool idle() const { return thread_.idle(); }

 private:
  static WindowOutcome plan(WindowPlanner& planner, WindowJob& job, const std::atomic<bool>& cancel);

  std::unique_ptr<WindowPlanner> planner_;         // used on the worker's thread only
  WorkerThread<WindowJob, WindowOutcome> thread_;  // last: its thread ends before the planner goes
};

}  // namespace coordinator
