// Any solver in the rotation model (action_model.hpp): the solver plans four-way moves, then each
// agent carries its path out with turns (turning_execution.hpp). For the solvers that do not plan
// with turns themselves (all but cts-pibt and cts-pibt-anytime); in the four-way model the
// solver's own result, unchanged. The anytime cts-pll-v3 refines its four-way plan until
// kFourWayShare of its time (its first plan may take longer); LNS over cell and heading refines
// the turned plan for the rest.
#pragma once

#include <memory>

#include "planner_core/guided_distances.hpp"
#include "planner_core/solver.hpp"

namespace planner_core {

class TurnedSolver : public Solver {
 public:
  TurnedSolver(std::unique_ptr<Solver> four_way, const SolverConfig& config)
      : four_way_(std::move(four_way)), config_(config) {}
  SolveResult solve(const Instance& instance, const SolveOptions& options) override;

  static constexpr double kFourWayShare = 0.5;

 private:
  // Refines `result` (a turned plan) with turns until the deadline, guided by `turning` if given;
  // the LNS iterations it made.
  int refine_with_turns(const Instance& instance, GuidedDistances* turning, SolveResult& result,
                        const SolveOptions& options) const;
  std::unique_ptr<Solver> four_way_;
  SolverConfig config_;
};

// The tables of `turning` (a GuidedDistances per cell and heading) for every task and goal fit in
// kTurningTablesBudget bytes.
constexpr size_t kTurningTablesBudget = size_t{1} << 30;
bool turning_tables_fit(const Instance& instance, const GuidedDistances& turning);

// The lower bound with turns (task_order.hpp) when the tables for every task and goal fit in the
// budget and are searched (on two threads) before `deadline`; else `four_way_bound`, lower but
// still a bound.
int64_t turning_lower_bound(const Instance& instance, GuidedDistances& turning, const TaskOrderConfig& config,
                            int64_t four_way_bound, const Deadline& deadline);

}  // namespace planner_core
