#include "planner_core/turned_solver.hpp"

#include <set>

#include "planner_core/guided_distances.hpp"
#include "planner_core/turning_execution.hpp"

namespace planner_core {

int64_t turning_lower_bound(const Instance& instance, const TaskOrderConfig& config, int64_t four_way_bound,
                            size_t memory_bytes) {
  std::set<Vertex> targets(instance.goals.begin(), instance.goals.end());
  for (const Task& task : instance.tasks) targets.insert(task.at);
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  if (targets.size() * turning.bytes_per_target() > memory_bytes) return four_way_bound;
  return tour_lower_bound(instance, turning, config);
}

SolveResult TurnedSolver::solve(const Instance& instance, const SolveOptions& options) {
  if (instance.actions != ActionModel::kRotate) return four_way_->solve(instance, options);
  Instance four_way = instance;
  four_way.actions = ActionModel::kMove4;
  SolveOptions four_way_options = options;
  four_way_options.on_solution = nullptr;  // its figures are not those of the plan the robots get
  const SolveResult planned = four_way_->solve(four_way, four_way_options);

  SolveResult result = planned;
  result.solved = false;
  result.solution.clear();
  result.headings.clear();
  result.flowtime = 0;
  result.makespan = 0;
  result.sum_of_loss = 0;
  result.first_solution_ms = -1;
  result.improvements.clear();
  result.lower_bound = turning_lower_bound(instance, config_.task_order, planned.lower_bound);
  if (planned.solved) {
    const std::optional<TurningPlan> turned = execute_with_turns(instance, planned.solution, !config_.forbid_rotations);
    if (turned) {
      keep_if_better(result, instance, turned->cells, planned.orders, 0, options.started, options,
                     config_.solver + " (turned)", turned->headings);
    } else {
      result.failure_reason = "the four-way plan has agents moving in a cycle, which robots that turn cannot follow";
    }
  }
  result.comp_time_ms = elapsed_ms(options.started);
  return result;
}

}  // namespace planner_core
