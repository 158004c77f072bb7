#include "planner_core/turned_solver.hpp"

#include <set>

#include "planner_core/guided_distances.hpp"
#include "planner_core/turning_execution.hpp"

namespace planner_core {

namespace {

std::vector<Vertex> targets_of(const Instance& instance) {
  std::set<Vertex> targets(instance.goals.begin(), instance.goals.end());
  for (const Task& task : instance.tasks) targets.insert(task.at);
  return {targets.begin(), targets.end()};
}

}  // namespace

bool turning_tables_fit(const Instance& instance, const GuidedDistances& turning) {
  return targets_of(instance).size() * turning.bytes_per_target() <= kTurningTablesBudget;
}

int64_t turning_lower_bound(const Instance& instance, GuidedDistances& turning, const TaskOrderConfig& config,
                            int64_t four_way_bound, const Deadline& deadline) {
  if (!turning_tables_fit(instance, turning)) return four_way_bound;
  const std::vector<Vertex> targets = targets_of(instance);
  turning.prepare(targets, deadline, 2);
  for (Vertex target : targets) {
    if (!turning.held(target)) return four_way_bound;
  }
  return tour_lower_bound(instance, turning, config);
}

SolveResult TurnedSolver::solve(const Instance& instance, const SolveOptions& options) {
  if (instance.actions != ActionModel::kRotate) return four_way_->solve(instance, options);
  // The bound first, in a tenth of the time, while the tables are needed only for it.
  int64_t lower_bound = 0;
  {
    GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
    lower_bound = turning_lower_bound(instance, turning, config_.task_order, 0,
                                      options.deadline.slice(0.1 * options.deadline.budget_left_s()));
  }
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
  result.lower_bound = lower_bound > 0 ? lower_bound : planned.lower_bound;
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
