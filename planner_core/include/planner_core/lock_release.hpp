// Lock detection and release (CTS-PLL paper, section III-B and Algorithm 3): when Extended-PIBT
// stalls or hits its step limit, find the lock agents and the lock time, solve a local MAPF
// instance over the lock agents with LaCAM while everyone else stands still, and splice the
// local plan into the joint plan so Extended-PIBT can resume from there.
#pragma once

#include <optional>
#include <random>
#include <vector>

#include "planner_core/extended_pibt.hpp"
#include "planner_core/lacam.hpp"
#include "planner_core/safe_interval_planning.hpp"

namespace planner_core {

struct LockReleaseConfig {
  // Work for one local LaCAM search, in seconds at kWorkPerSecond (deadline.hpp): the same
  // search on every run, whatever the machine's speed or load.
  double lacam_budget_s = 0.2;
  bool next_target_goals = false;  // targets = next task/goal of each lock agent instead of a random permutation
  int max_releases = 25;  // per joint sequence; then CTS-PLL-v2/v3 move on to the next sequence
  // When a release fails (LaCAM finds nothing, or nothing would move), it is tried again with
  // next-target goals, then with the lock set widened by the agents within 2, 4, 8, ... cells of
  // it at t^ (random and next-target goals each), this many times before the sequence is given up.
  int max_escalations = 6;
  // After this many releases of one sequence (or when a release fails) the lock agents are
  // completed by prioritized planning (see complete_by_prioritized_planning).
  int completion_after_releases = 4;
};

struct LockSet {
  std::vector<int> agents;  // unfinished agents, plus finished agents in their way
  int lock_time = 0;        // t^: the earliest last-completed-target time among them
};

// Reads the lock from the (failed) run's plan.
LockSet detect_lock(const ExtendedPibt& pibt, DistTable& dist);

// The lock set plus every agent standing within `radius` cells (on the grid) of a lock agent at t^.
LockSet widen_lock(const ExtendedPibt& pibt, const LockSet& lock, int radius);

// The plan up to t^, followed by the local LaCAM plan that moves the lock agents to their
// release targets (others frozen where they stood at t^); nullopt when LaCAM finds none in time.
// Random-permutation targets are drawn within each connected region left free by the frozen
// agents, so every lock agent can at least reach its target.
// `next_target_goals_now` asks for next-target goals on this call whatever the configuration says.
std::optional<Solution> release_lock(const ExtendedPibt& pibt, const LockSet& lock, Lacam& lacam,
                                     const LockReleaseConfig& config, bool next_target_goals_now, std::mt19937& rng,
                                     const Deadline& deadline);

// Last resort when releases keep failing or the lock keeps coming back: everyone outside the lock
// keeps the path of the failed run (finished, resting on its goal); the lock agents are replanned
// from t^ one after another with safe-interval planning through their remaining targets, around
// everyone planned so far, trying up to `attempts` random priority orders. Goal cells in dead-end
// corridors that Extended-PIBT cannot fill in the right order are solved this way. Returns a
// complete feasible plan, or nullopt.
std::optional<Solution> complete_by_prioritized_planning(const ExtendedPibt& pibt, const JointSequence& sequence,
                                                         const LockSet& lock, DistTable& dist, std::mt19937& rng,
                                                         int attempts, bool forbid_rotations,
                                                         const Deadline& deadline);

// The complete search as a lock release (CTS-LaCAM from the lock): every agent, not only the lock
// agents, searched by LaCAM over augmented configurations from where the failed run stood at t^,
// each with its tasks not yet visited by then (in order), then its goal. Complete for the
// sequence: plans are reversible, so whenever the sequence can be followed from the starts it can
// be from t^ (visits made are kept). Returns the run's plan up to t^ followed by the search's
// plan, or nullopt when the deadline passes (or, having searched everything, none exists).
std::optional<Solution> complete_by_search(const ExtendedPibt& pibt, const JointSequence& sequence,
                                           const LockSet& lock, DistTable& dist, std::mt19937& rng,
                                           bool forbid_rotations, const Deadline& deadline);

}  // namespace planner_core
