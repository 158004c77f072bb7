// CTS-LaCAM: a complete search for CTS-MAPF. Joint sequences are taken in cost order; for each,
// LaCAM searches the configurations augmented with every agent's progress along its task order
// (lacam.hpp, waypoints). A sequence whose augmented space is searched to the end without a plan
// cannot be followed, and the next one is tried; when every joint sequence has been searched to
// the end, no plan exists. The standalone solver `cts-lacam` (anytime: LaCAM* search slices and
// LNS refinement until the deadline), and the fallback of the other CTS solvers: they give it
// time whenever their own method fails on a joint sequence, and the rest of the time when their
// own method has nothing left to try.
//
// In the rotation model `cts-lacam` also searches over cell and heading (lacam.hpp), as lacam
// does (lacam_solver.hpp): four-way CTS-LaCAM's first plan with turns added, then the search with
// turns for a quarter of the time left, and whichever plan is cheaper is kept. The fallback of the
// other CTS solvers still plans four-way moves (their turns are added).
#pragma once

#include <memory>
#include <optional>
#include <random>

#include "planner_core/dist_table.hpp"
#include "planner_core/joint_sequencer.hpp"
#include "planner_core/lacam.hpp"
#include "planner_core/solver.hpp"

namespace planner_core {

// Each agent's task cells in the sequence's order: what an augmented LaCAM search (and a Scatter)
// takes as waypoints.
Waypoints waypoints_of(const Instance& instance, const JointSequence& sequence);

class CtsLacam : public Solver {
 public:
  explicit CtsLacam(const SolverConfig& config) : config_(config) {}
  SolveResult solve(const Instance& instance, const SolveOptions& options) override;

 private:
  SolveResult solve_with_turns(const Instance& instance, const SolveOptions& options);
  SolverConfig config_;
};

// The search itself, resumable: a driver can give it slices of time between its own attempts.
class CompleteSearch {
 public:
  enum class Outcome { kFound, kNoPlanExists, kOutOfTime };

  // `anytime`: keep what LaCAM* needs to improve the plan later (refine()). `turning`: search over
  // cell and heading with these distances (the instance in the rotation model); null: four-way.
  CompleteSearch(const Instance& instance, DistTable& dist, const SolverConfig& config, std::mt19937& rng,
                 bool anytime, GuidedDistances* turning = nullptr);
  ~CompleteSearch();

  // Goes on from where the last call stopped until it has a plan (kept in `result` through
  // keep_if_better, when cheaper than the one there), has proved that none exists (then it sets
  // result.failure_reason), or the deadline passes.
  Outcome search(const Deadline& deadline, const SolveOptions& options, SolveResult& result);

  // After kFound, with `anytime`: LaCAM* search slices and LNS on the plan until options.deadline.
  void refine(const SolveOptions& options, SolveResult& result);

 private:
  const Instance& instance_;
  DistTable& dist_;
  SolverConfig config_;
  std::mt19937& rng_;
  bool anytime_;
  GuidedDistances* turning_;
  std::unique_ptr<JointSequencer> sequencer_;  // made on the first call that has time to finish it
  std::optional<JointSequence> sequence_;      // the one being searched
  std::unique_ptr<LacamSearch> lacam_;
  bool exhausted_ = false;  // the current sequence's space was searched to the end
  int impossible_sequences_ = 0;
};

}  // namespace planner_core
