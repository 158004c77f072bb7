// PlanningWorker: one solve at a time on a thread of its own, so that the coordinator's loop goes
// on meanwhile (heartbeats, robots' states, admissions, conformance) and a long plan never looks
// like a dead coordinator. The loop hands over a self-contained request (the instance to solve and
// the solver's settings), polls for the outcome, and checks the plan against the world as it is
// when the plan comes back (fleet_coordinator.cpp).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "coordinator/plan_builder.hpp"
#include "coordinator/window_planner.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"

namespace coordinator {

struct PlanningRequest {
  PlanInstance built;                    // what to solve, and which robot each agent is
  planner_core::SolverConfig solver;
  double time_limit_s = 1;
  int64_t iterations = 0;                // a work budget (planner.iterations), 0 = the time limit alone
  // Lifelong: instead of the solver, the plan's first window (window_planner.hpp) of `window_steps`
  // from the instance's starts, through its tasks, towards its goals; validated as a first stretch.
  bool lifelong_window = false;
  int window_steps = 5;
  std::optional<planner_core::LifelongConfig> lifelong_planner;  // FleetConfig::lifelong_planner
};

struct PlanningOutcome {
  PlanInstance built;                    // the request's, handed back
  planner_core::SolveResult result;      // solved or not (failure_reason)
  planner_core::ValidationReport report;  // of result.solution; checked before anything is sent
  std::string error;                     // the solver threw (a bug: the mission goes on)
  double planning_ms = 0;
  bool cancelled = false;                // cut short by cancel(): to be ignored
};

class PlanningWorker {
 public:
  PlanningWorker();
  ~PlanningWorker();  // cancels a solve under way and waits for its thread
  PlanningWorker(const PlanningWorker&) = delete;
  PlanningWorker& operator=(const PlanningWorker&) = delete;

  // Starts solving `request`; only while idle().
  void start(PlanningRequest request);
  // The outcome once the solve has ended (then idle again), else nothing.
  std::optional<PlanningOutcome> poll();
  // As poll(), waiting up to `timeout` for the solve to end.
  std::optional<PlanningOutcome> wait_for(std::chrono::milliseconds timeout);
  // Cuts the solve under way short; its outcome comes back `cancelled`.
  void cancel() { cancel_.store(true); }
  bool idle() const;

 private:
  void run();
  static planner_core::SolveResult first_window(const PlanningRequest& request, const planner_core::Deadline& deadline);

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;  // an outcome was set
  std::optional<PlanningRequest> request_;
  std::optional<PlanningOutcome> outcome_;
  bool busy_ = false;
  bool quit_ = false;
  std::atomic<bool> cancel_{false};
  std::thread thread_;  // last: starts once the members above exist
};

}  // namespace coordinator
