// LacamSolver: LaCAM (or LaCAM* with refine) as a plain MAPF solver behind the Solver interface,
// for instances without tasks such as MovingAI scenarios. In the rotation model it searches over
// cell and heading (lacam.hpp) and LaCAM* refines with turns.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "planner_core/lacam.hpp"
#include "planner_core/solver.hpp"

namespace planner_core {

class LacamSolver : public Solver {
 public:
  LacamSolver(const SolverConfig& config, bool refine) : config_(config), refine_(refine) {}
  SolveResult solve(const Instance& instance, const SolveOptions& options) override;

 private:
  SolveResult solve_with_turns(const Instance& instance, const SolveOptions& options);
  SolverConfig config_;
  bool refine_;
};

// LaCAM*'s anytime loop: `search` (which found the plan kept in `result`) goes on for cheaper plans
// in slices, between LNS refinement of the best plan so far (as lacam3 runs its refiners beside the
// search), until the deadline or a proved optimum. `orders` and `sequence_index` are the joint
// sequence the search follows (empty orders for plain MAPF). In the rotation model `turning` holds
// the distances with turns the search uses, and the refiner repairs over cell and heading.
void refine_until_deadline(const Instance& instance, DistTable& dist, LacamSearch& search, bool search_done,
                           const SolverConfig& config, std::mt19937& rng, const std::vector<std::vector<int>>& orders,
                           int sequence_index, const SolveOptions& options, SolveResult& result,
                           const std::string& name, GuidedDistances* turning = nullptr);

// The start headings of `instance` in the rotation model, one per agent (east when it gives none).
Headings start_headings_of(const Instance& instance);

}  // namespace planner_core
