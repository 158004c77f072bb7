// PlanningWorker: one solve at a time on a thread of its own (worker_thread.hpp), so that the coordinator's loop goes
// on meanwhile (heartbeats, robots' states, admissions, conformance) and a long plan never looks
// like a dead coordinator. The loop hands over a self-contained request (the instance to solve and
// the solver's settings), polls for the outcome, and checks the plan against the world as it is
// when the plan comes back (fleet_coordinator.cpp).
#pragma once

#include <atomic>
#include <chrono>
#include <optional>
#include <string>

#include "coordinator/plan_builder.hpp"
#include "coordinator/window_planner.hpp"
#include "coordinator/worker_thread.hpp"
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
  PlanningWorker() : thread_(&PlanningWorker::plan) {}

  // Starts solving `request`; only while idle() (else std::logic_error).
  void start(PlanningRequest request) { thread_.start(std::move(request)); }
  // The outcome once the solve has ended (then idle again), else nothing.
  std::optional<PlanningOutcome> poll() { return thread_.poll(); }
  // As poll(), waiting up to `timeout` for the solve to end.
  std::optional<PlanningOutcome> wait_for(std::chrono::milliseconds timeout) { return thread_.wait_for(timeout); }
  // Cuts the solve under way short; its outcome comes back `cancelled`.
  void cancel() { thread_.cancel(); }
  bool idle() const { return thread_.idle(); }

 private:
  static PlanningOutcome plan(PlanningRequest& request, const std::atomic<bool>& cancel);
  static planner_core::SolveResult first_window(const PlanningRequest& request, const planner_core::Deadline& deadline);

  WorkerThread<PlanningRequest, PlanningOutcome> thread_;
};

}  // namespace coordinator
