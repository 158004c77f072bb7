// LacamSolver: LaCAM (or LaCAM* with refine) as a plain MAPF solver behind the Solver interface,
// for instances without tasks such as MovingAI scenarios.
#pragma once

#include "planner_core/lacam.hpp"
#include "planner_core/solver.hpp"

namespace planner_core {

class LacamSolver : public Solver {
 public:
  LacamSolver(const SolverConfig& config, bool refine) : config_(config), refine_(refine) {}
  SolveResult solve(const Instance& instance, const SolveOptions& options) override;

 private:
  SolverConfig config_;
  bool refine_;
};

}  // namespace planner_core
