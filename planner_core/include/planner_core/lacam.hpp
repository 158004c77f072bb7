// LaCAM: lazy constraints addition search for MAPF (K. Okumura, "LaCAM: Search-Based Algorithm for
// Quick Multi-Agent Pathfinding", AAAI 2023), with the LaCAM* refinement ("Improving LaCAM for
// Scalable Eventually Optimal Multi-Agent Pathfinding", IJCAI 2023) as an option. A depth-first
// search over configurations; each configuration carries a lazily grown tree of constraints and
// PIBT generates the successor that obeys a constraint. Complete: it finds a solution when one
// exists, given time.
//
// With waypoints (CTS-MAPF for a fixed joint sequence: each agent's task cells in its order, then
// its goal) a configuration is augmented with every agent's progress, the number of its waypoints
// visited so far; PIBT then drives each agent to its current waypoint, and an agent is home when
// it has visited them all and stands on its goal. The augmented space is finite, so the search
// stays complete (docs/ARCHITECTURE.md, "CTS-LaCAM").
//
// In the rotation model (action_model.hpp; LacamConfig::turning set, start headings given) a
// configuration also carries every agent's heading, a constraint fixes an agent's action (forward,
// a quarter turn either way, or a wait) and the generator is PIBT over these actions: an agent
// ranks them by the distance with turns of the pose each leads to, and one that must make way can
// only move forward. Every action of every agent can still be fixed by a constraint, so the search
// stays complete.
#pragma once

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "planner_core/action_model.hpp"
#include "planner_core/deadline.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/solution.hpp"

namespace planner_core {

class GuidedDistances;
class Scatter;

struct LacamConfig {
  bool refine = false;  // LaCAM*: after the first solution keep searching for a cheaper one until the deadline
  bool forbid_rotations = false;  // reject successors in which agents move in a cycle
  // The configuration generator uses LaCAM3's swap operation (see CorridorSwap); ignored when
  // cells are blocked, since the swap's corridor walks do not know them.
  bool swap = false;
  // Among moves equally near the goal, the generator tries a cell nobody stands on first (fewer
  // agents pushed). The plain MAPF solvers turn both this and the swap on (measured together:
  // docs/results/HISTORY.md, section 2); CTS-PLL's lock release keeps both off, as measured.
  bool prefer_free_cells = false;
  // Plain MAPF only: each agent's next cell on its Scatter path is its generator's first choice
  // (ahead of the nearest cell to its goal). Must outlive the search; null for none.
  const Scatter* guide = nullptr;
  // The rotation model: distances per cell and heading (a GuidedDistances of ActionModel::kRotate,
  // without lanes), searched for every goal and waypoint as needed; it must outlive the search.
  // Null for the four-move model. Neither the swap nor the guide applies then, and no cell may be
  // blocked.
  GuidedDistances* turning = nullptr;
};

// Per agent, the cells it must visit in this order before its goal; empty rows (or an empty
// vector) for plain MAPF.
using Waypoints = std::vector<std::vector<Vertex>>;

struct LacamResult {
  bool solved = false;
  Solution solution;       // solution[0] = starts, back() = goals
  HeadingPlan headings;    // the rotation model: each step's headings, beside `solution`
  int64_t explored = 0;    // configurations generated
  int64_t cost = 0;        // sum of loss of the solution
  bool exhausted = false;  // the whole reachable space was searched: no solution exists when !solved,
                           // and with LaCAM* the solution is optimal
};

// One search, kept between calls so that LaCAM* can be run in slices between other work.
class LacamSearch {
 public:
  // `start_headings`: in the rotation model (config.turning set), one per agent; else empty.
  LacamSearch(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng, const Config& starts,
              const Config& goals, const std::vector<char>& blocked = {}, const Waypoints& waypoints = {},
              const Headings& start_headings = {});
  ~LacamSearch();
  LacamSearch(const LacamSearch&) = delete;
  LacamSearch& operator=(const LacamSearch&) = delete;

  // Searches until the deadline, until the whole space has been searched (exhausted), or until it
  // holds a solution cheaper than the one it last returned (plain LaCAM: the first); a later call
  // goes on from there. The result carries the best solution so far.
  LacamResult run(const Deadline& deadline);

 private:
  class State;
  std::unique_ptr<State> state_;
};

// A one-shot search.
class Lacam {
 public:
  // `dist` is used for goal distances when nothing is blocked; with blocked cells the search
  // computes its own distances around them.
  Lacam(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng);

  // Plans `starts` -> `goals` (same length, distinct) where cells with blocked[v] != 0 may not be
  // entered (an empty `blocked` means none).
  LacamResult solve(const Config& starts, const Config& goals, const std::vector<char>& blocked,
                    const Deadline& deadline, const Waypoints& waypoints = {});

 private:
  const Graph& graph_;
  DistTable& dist_;
  LacamConfig config_;
  std::mt19937& rng_;
};

}  // namespace planner_core
