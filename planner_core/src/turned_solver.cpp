#include "planner_core/turned_solver.hpp"

#include <optional>
#include <set>

#include "planner_core/guided_distances.hpp"
#include "planner_core/lns.hpp"
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

int TurnedSolver::refine_with_turns(const Instance& instance, GuidedDistances* turning, SolveResult& result,
                                    const SolveOptions& options) const {
  DistTable dist(*instance.graph);
  std::mt19937 rng(config_.seed);
  LnsConfig lns_config = config_.lns;
  lns_config.search.forbid_rotations = lns_config.search.forbid_rotations || config_.forbid_rotations;
  LnsRefiner lns(instance, dist, lns_config, rng);
  Solution plan = result.solution;
  HeadingPlan headings = result.headings;
  const std::vector<std::vector<int>> orders = result.orders;
  const LnsStats stats = lns.refine_with_turns(plan, headings, orders, turning, options.deadline);
  keep_if_better(result, instance, plan, orders, 0, options.started, options, config_.solver + " (refined with turns)",
                 headings);
  return stats.iterations;
}

SolveResult TurnedSolver::solve(const Instance& instance, const SolveOptions& options) {
  if (instance.actions != ActionModel::kRotate) return four_way_->solve(instance, options);
  // The bound first, in a tenth of the time (unless the caller has it); its tables (distances
  // with turns) guide the refinement with turns later.
  std::optional<GuidedDistances> own_turning;
  GuidedDistances* turning = known_turning_;
  int64_t lower_bound = known_lower_bound_;
  if (turning == nullptr) {
    turning = &own_turning.emplace(*instance.graph, Guidance::kNone, ActionModel::kRotate);
    lower_bound = turning_lower_bound(instance, *turning, config_.task_order, 0,
                                      options.deadline.slice(0.1 * options.deadline.budget_left_s()));
  }
  SolveResult result;
  bool cycles = false;
  int64_t turned_four_way_flowtime = -1;  // the four-way flowtime of the plan turned last
  const auto keep_turned = [&](const SolveResult& planned) {
    turned_four_way_flowtime = planned.flowtime;
    const std::optional<TurningPlan> turned = execute_with_turns(instance, planned.solution, !config_.forbid_rotations);
    if (!turned) {
      cycles = true;
      return;
    }
    keep_if_better(result, instance, turned->cells, planned.orders, 0, options.started, options,
                   config_.solver + " (turned)", turned->headings);
  };
  Instance four_way = instance;
  four_way.actions = ActionModel::kMove4;
  SolveOptions four_way_options = options;
  // Time kept for adding the turns (measured: about 2 s for 10,000 agents over 1,400 steps, a
  // plan's length being about twice the map's width and height): 50 ns per agent and cell of
  // width and height, at most half the budget.
  const double budget_s = options.deadline.budget_left_s();
  const double turning_s = std::min(0.5 * budget_s, 50e-9 * instance.agent_count() *
                                                        (instance.graph->width() + instance.graph->height()) * 2);
  // An anytime solver then refines the turned plan by LNS over cell and heading: the four-way
  // search refines for a share of the budget (its first plan may take longer), the refinement
  // with turns gets the rest.
  const bool refines_with_turns = config_.solver == "cts-pll-v3";
  four_way_options.deadline = options.deadline.slice(budget_s - turning_s);
  if (refines_with_turns) four_way_options.refine_share = kFourWayShare;
  // The first plan is turned as soon as it is found (the time to a first plan is the turned one's);
  // later ones only at the end, the final plan being the cheapest four-way plan.
  four_way_options.on_solution = [&](const SolveResult& planned) {
    if (!result.solved) keep_turned(planned);
  };
  const SolveResult planned = four_way_->solve(four_way, four_way_options);
  // The final plan, unless it is the one turned already (a solver with one plan, or no better one).
  if (planned.solved && planned.flowtime != turned_four_way_flowtime) keep_turned(planned);
  int lns_iterations = 0;
  if (refines_with_turns && result.solved && !options.deadline.expired()) {
    lns_iterations = refine_with_turns(instance, turning_tables_fit(instance, *turning) ? turning : nullptr, result,
                                       options);
  }

  const SolveResult turned = result;
  result = planned;  // the search's figures (sequences, releases, iterations, ...)
  result.solved = turned.solved;
  result.solution = turned.solution;
  result.headings = turned.headings;
  result.flowtime = turned.flowtime;
  result.makespan = turned.makespan;
  result.sum_of_loss = turned.sum_of_loss;
  result.first_solution_ms = turned.first_solution_ms;
  result.improvements = turned.improvements;
  result.orders = turned.orders;
  result.lns_iterations += lns_iterations;
  result.lower_bound = lower_bound > 0 ? lower_bound : planned.lower_bound;
  if (planned.solved && !turned.solved && cycles) {
    result.failure_reason = "the four-way plan has agents moving in a cycle, which robots that turn cannot follow";
  }
  result.comp_time_ms = elapsed_ms(options.started);
  return result;
}

}  // namespace planner_core
