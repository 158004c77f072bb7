#include "coordinator/planning_worker.hpp"

#include <chrono>
#include <exception>
#include <string>
#include <vector>

namespace coordinator {

planner_core::SolveResult PlanningWorker::first_window(const PlanningRequest& request,
                                                     const planner_core::Deadline& deadline) {
  const planner_core::Instance& instance = request.built.instance;
  std::vector<WindowAgent> agents(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) agents[a].park = instance.goals[a];
  for (const planner_core::Task& task : instance.tasks) {
    for (int a : task.agents) agents[a].errands.push_back(task.at);
  }
  WindowPlanner windows(instance.graph, request.solver.seed, instance.actions,
                        window_settings(request.lifelong_planner, *instance.graph, instance.agent_count(), instance.actions));
  planner_core::Headings headings;
  if (instance.actions == planner_core::ActionModel::kRotate) {
    for (int a = 0; a < instance.agent_count(); ++a) headings.push_back(instance.start_heading(a));
  }
  PlanWindow window = windows.plan({instance.starts, headings}, agents, request.window_steps, deadline);
  planner_core::SolveResult result;
  result.solution = std::move(window.steps);
  result.headings = std::move(window.headings);
  result.solved = true;
  return result;
}

PlanningOutcome PlanningWorker::plan(PlanningRequest& request, const std::atomic<bool>& cancel) {
  PlanningOutcome outcome;
  const auto started = std::chrono::steady_clock::now();
  try {
    const auto deadline = planner_core::Deadline::for_limits(request.time_limit_s, request.iterations, &cancel);
    if (request.lifelong_window) {
      outcome.result = first_window(request, deadline);
    } else {
      outcome.result = planner_core::make_solver(request.solver)->solve(request.built.instance, {deadline, {}});
    }
    if (outcome.result.solved) {
      planner_core::ValidationOptions options;
      options.forbid_rotations = request.solver.forbid_rotations || request.lifelong_window;
      options.first_stretch = request.lifelong_window;
      outcome.report =
          planner_core::validate(request.built.instance, outcome.result.solution, options, outcome.result.headings);
    }
  } catch (const std::exception& e) {  // a solver bug must not end the mission
    outcome.error = std::string("the solver threw: ") + e.what();
  }
  outcome.planning_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  outcome.cancelled = cancel.load();
  outcome.built = std::move(request.built);
  return outcome;
}

}  // namespace coordinator
