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

  // The caller's tables with turns (turning_lower_bound searched them for every task and goal) and
  // the bound they gave: solve() then searches neither again. `turning` must outlive solve().
  void use_turning_tables(GuidedDistances& turning, int64_t lower_bound) {
    known_turning_ = &turning;
    known_lower_bound_ = lower_bound;
  }

  static constexpr double kFourWayShare = 0.5;

 private:
  // Refines `result` (a turned plan) with turns until the deadline, guided by `turning` if given;
  // the LNS iterations it made.
  int refine_with_turns(const Instance& instance, GuidedDistances* turning, SolveResult& result,
                        const SolveOptions& options) const;
  std::unique_ptr<Solver> four_way_;
  SolverConfig config_;
  GuidedDistances* known_turning_ = nullptr;
  int64_t known_lower_bound_ = 0;
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
