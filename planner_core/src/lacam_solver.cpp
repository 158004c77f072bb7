#include "planner_core/lacam_solver.hpp"

#include <random>
#include <stdexcept>

#include "planner_core/validator.hpp"

namespace planner_core {

SolveResult LacamSolver::solve(const Instance& instance, const SolveOptions& options) {
  const Clock::time_point started = options.started;
  SolveResult result;
  DistTable dist(*instance.graph);
  if (instance.task_count() > 0) {
    result.failure_reason = "lacam solves plain MAPF; this instance has tasks (use a cts-* solver)";
    result.comp_time_ms = elapsed_ms(started);
    return result;
  }
  std::mt19937 rng(config_.seed);
  Lacam lacam(*instance.graph, dist, LacamConfig{refine_, config_.forbid_rotations, config_.pibt.swap}, rng);
  result.preprocessing_ms = elapsed_ms(started);
  const LacamResult found = lacam.solve(instance.starts, instance.goals, {}, options.deadline);
  result.sequences_tried = 1;
  if (found.solved) {
    const ValidationReport report = validate(instance, found.solution);
    if (!report.ok()) throw std::logic_error("LaCAM produced an invalid plan:\n" + report.summary());
    result.solved = true;
    result.solution = found.solution;
    result.orders.assign(instance.agent_count(), {});
    result.flowtime = report.flowtime;
    result.makespan = report.makespan;
    result.sum_of_loss = sum_of_loss(found.solution, instance.goals);
    result.first_solution_ms = result.preprocessing_ms + found.first_solution_ms;
    // Alongside the search: the searches from the goals have already reached every start.
    for (int a = 0; a < instance.agent_count(); ++a) result.lower_bound += dist.get(instance.goals[a], instance.starts[a]);
    result.improvements.push_back({result.first_solution_ms, result.flowtime, 0});
    if (options.on_solution) options.on_solution(result);
  } else {
    result.failure_reason = found.exhausted ? "no solution exists (LaCAM searched every reachable configuration)"
                                            : "deadline reached before LaCAM found a solution";
  }
  result.comp_time_ms = elapsed_ms(started);
  return result;
}

}  // namespace planner_core
