#include "coordinator/window_worker.hpp"

#include <chrono>
#include <exception>

namespace coordinator {

WindowWorker::WindowWorker(std::unique_ptr<WindowPlanner> planner)
    : planner_(std::move(planner)),
      thread_([planner = planner_.get()](WindowJob& job, const std::atomic<bool>& cancel) {
        return plan(*planner, job, cancel);
      }) {}

WindowOutcome WindowWorker::plan(WindowPlanner& planner, WindowJob& job, const std::atomic<bool>& cancel) {
  WindowOutcome outcome;
  const auto started = std::chrono::steady_clock::now();
  try {
    outcome.window = planner.plan(job.from, job.agents, job.steps, planner_core::Deadline::in_seconds(job.budget_s, &cancel));
  } catch (const std::exception& e) {
    outcome.error = e.what();
  }
  outcome.planning_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  outcome.job = std::move(job);
  return outcome;
}

}  // namespace coordinator
