// CTS-LaCAM: a complete search for CTS-MAPF. Joint sequences are taken in cost order; for each,
// LaCAM searches the configurations augmented with every agent's progress along its task order
// (lacam.hpp, waypoints). A sequence whose augmented space is searched to the end without a plan
// cannot be followed, and the next one is tried; when every joint sequence has been searched to
// the end, no plan exists. The standalone solver `cts-lacam` (anytime: LaCAM* search slices and
// LNS refinement until the deadline), and the fallback of the other CTS solvers when their own
// driver is out of ideas before the deadline.
#pragma once

#include <random>

#include "planner_core/dist_table.hpp"
#include "planner_core/solver.hpp"

namespace planner_core {

class CtsLacam : public Solver {
 public:
  explicit CtsLacam(const SolverConfig& config) : config_(config) {}
  SolveResult solve(const Instance& instance, const SolveOptions& options) override;

 private:
  SolverConfig config_;
};

// Searches for a plan into `result` (which may hold one already: a cheaper one replaces it),
// joint sequence after joint sequence, until one is found or the deadline passes; with `anytime`,
// refines it until the deadline. Sets result.failure_reason when no plan was found: a proof of
// unsolvability when every joint sequence was searched to the end.
void solve_completely(const Instance& instance, DistTable& dist, const SolverConfig& config, std::mt19937& rng,
                      bool anytime, const SolveOptions& options, SolveResult& result);

}  // namespace planner_core
