// Solver: the interface every CTS-MAPF solver variant implements, with its settings, per-call
// options (deadline, interrupt, improvement callback) and result (plan, metrics, improvement log).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "planner_core/deadline.hpp"
#include "planner_core/extended_pibt.hpp"
#include "planner_core/lacam.hpp"
#include "planner_core/lns.hpp"
#include "planner_core/lock_release.hpp"
#include "planner_core/task_order.hpp"

namespace planner_core {

struct SolverConfig {
  std::string solver = "cts-pibt";  // see solver_names()
  uint32_t seed = 0;
  TaskOrderConfig task_order;
  PibtConfig pibt;
  int pll_stall_window = 150;  // CTS-PLL: Extended-PIBT without progress this long triggers lock release
  LockReleaseConfig lock_release;
  LnsConfig lns;
  // Plans for real robots: no agents moving in a cycle within one step (see PibtConfig).
  bool forbid_rotations = false;
  int max_sequences = 0;  // anytime variants: stop after this many joint sequences (0 = until the deadline)
  // The CTS solvers hand over to the complete search (cts_lacam.hpp) when their own driver has no
  // plan and time remains, so that "not solved" comes only at the deadline or with a proof. Off
  // only to study a driver alone (e.g. the paper's CTS-PIBT baseline locking).
  bool complete_fallback = true;
  // LaCAM* (plain MAPF): after the first plan, a second search guided by agents' paths spread
  // over the map (scatter.hpp); its plan is kept when cheaper. Off to study LaCAM* alone.
  bool scatter = true;
  // LaCAM* (plain MAPF): the share of refinement rounds that re-plan the best plan's tail with a
  // fresh LaCAM from one of its configurations, picked at random (lacam3's recursive LaCAM); the
  // spliced plan is kept when cheaper. 0 = never.
  double recursive_lacam_rate = 0;
  // The solvers that plan with turns (plans_with_turns) in the rotation model: plans made with
  // turns, and four-way plans with turns added afterwards; the cheaper is kept. One of them off, to
  // measure what each gives.
  bool plan_with_turns = true;
  bool add_turns = true;
};

struct Improvement {
  double time_ms = 0;
  int64_t flowtime = 0;
  int sequence_index = 0;  // which joint sequence produced it
};

struct SolveResult {
  bool solved = false;
  Solution solution;
  HeadingPlan headings;  // the plan's headings in the rotation model; empty otherwise
  std::vector<std::vector<int>> orders;  // agent -> task ids in the order the solution follows
  int64_t flowtime = 0;
  int makespan = 0;
  int64_t sum_of_loss = 0;
  int64_t lower_bound = 0;        // 0 when not computed
  // All times count from SolveOptions::started, the moment the user's solve began.
  double comp_time_ms = 0;
  double first_solution_ms = -1;  // -1 when nothing was found
  double preprocessing_ms = 0;    // until the search proper began (instance read, task orders)
  int sequences_tried = 0;
  int pibt_failures = 0;          // runs that hit the step limit (or stalled, for CTS-PLL)
  int lock_releases = 0;          // CTS-PLL: successful lock releases
  int prioritized_completions = 0;  // CTS-PLL: plans completed by prioritized planning after releases
  int searched_completions = 0;     // CTS-PLL: plans completed by the complete search from a lock
  int lns_iterations = 0;
  std::vector<Improvement> improvements;
  std::string failure_reason;
};

struct SolveOptions {
  Deadline deadline;
  // Called with the result so far when the first solution is found and at every improvement.
  std::function<void(const SolveResult&)> on_solution;
  // When the solve began from the user's point of view (a program sets it before it reads the
  // instance); the times in SolveResult count from here.
  Clock::time_point started = Clock::now();
  // Once it has a plan, an anytime solver refines it only until this share of the deadline's
  // budget (counted from its start); the search for a first plan may still use the whole deadline.
  // TurnedSolver keeps the rest for its refinement with turns.
  double refine_share = 1.0;
};

class Solver {
 public:
  virtual ~Solver() = default;
  virtual SolveResult solve(const Instance& instance, const SolveOptions& options) = 0;
};

// Keeps `plan` in `result` when it is the first plan or cheaper than the one kept: validates it
// (an invalid plan is a bug: std::logic_error naming `solver`), records the improvement and
// reports it through options.on_solution.
// In the rotation model `headings` are the plan's headings.
void keep_if_better(SolveResult& result, const Instance& instance, const Solution& plan,
                    const std::vector<std::vector<int>>& orders, int sequence_index, Clock::time_point started,
                    const SolveOptions& options, const std::string& solver, const HeadingPlan& headings = {});

std::vector<std::string> solver_names();
// The solvers that plan with turns themselves in the rotation model (action_model.hpp): cts-pibt,
// cts-pibt-anytime, cts-lacam, lacam and lacam-star. The others plan four-way moves, to which turns
// are added (turned_solver.hpp).
bool plans_with_turns(const std::string& solver);
// Throws std::invalid_argument for an unknown solver name.
std::unique_ptr<Solver> make_solver(const SolverConfig& config);

}  // namespace planner_core
