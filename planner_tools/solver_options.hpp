// The solver options ctsfleet-solve and ctsfleet-bench share: which parts of a solver run, for
// users who study or tune them.
#pragma once

#include "ctsfleet/program.hpp"
#include "planner_core/solver.hpp"

namespace planner_core {

// --iterations: a work budget after which the final plan is the same on every run and machine.
inline void add_iterations_option(CLI::App& app, int64_t& iterations) {
  app.add_option("--iterations", iterations,
                 "end the solve after N iterations of search (one = " + std::to_string(kWorkPerIteration) +
                     " agent states expanded, about 1 ms here): the same final plan on every run and machine, if "
                     "the time limit (-t, then a safety stop) does not come first (0 = until the time limit)")
      ->check(ctsfleet::count_in(0, kMaxIterations));
}

inline void add_solver_part_options(CLI::App& app, SolverConfig& config) {
  app.add_flag("--no-scatter{false}", config.scatter,
               "lacam-star: no second search guided by paths spread over the map (to study LaCAM* alone)");
  app.add_option("--recursive-lacam", config.recursive_lacam_rate,
                 "lacam-star: share of refinement rounds spent re-planning the plan's tail with a fresh LaCAM "
                 "(lacam3's recursive LaCAM; 0 = never)")
      ->check(ctsfleet::number_in(0, 1))
      ->capture_default_str();
  app.add_flag("--scatter-pibt", config.pibt.scatter,
               "cts-pll-*: Extended-PIBT guided by paths through each agent's tasks spread over the map (Scatter)");
  app.add_flag("--swap,!--no-swap", config.pibt.swap,
               "Extended-PIBT with LaCAM3's swap operation for head-on meetings in corridors (default; --no-swap: without)");
  app.add_flag("--no-rotations", config.forbid_rotations,
               "plans for robots: no agents moving in a cycle within one step (as the coordinator plans; validated so)");
}

}  // namespace planner_core
