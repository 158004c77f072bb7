// Safe-interval path planning (SIPP; Phillips and Likhachev, ICRA 2011) for one agent through an
// ordered list of targets (its tasks, then its goal), avoiding the paths in a PathTable: no vertex
// or swap conflicts, never on a cell where another agent rests, and arriving at the goal only in
// its last safe interval, so it can rest there for good. In the rotation model too: then a state
// is also a heading, and a step is forward, a quarter turn or a wait.
#pragma once

#include <cstdint>
#include <vector>

#include "planner_core/deadline.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/guided_distances.hpp"
#include "planner_core/path_table.hpp"

namespace planner_core {

struct SpaceTimeLimits {
  int horizon = 4000;           // no arrival later than this
  int max_expansions = 200000;  // give up beyond this many expanded states
  // Plans for robots: no move that closes a cycle of agents each entering the cell the next one
  // leaves in the same step (a rotation). Following an agent is allowed; entering a cell just
  // left is refused only when the chain of agents ahead leads back into the cell left behind.
  bool forbid_rotations = false;
  // No path longer than this (steps from start_time to the goal): a repair that cannot beat the
  // paths it replaces is given up early.
  int max_length = 1 << 30;
  Deadline deadline;  // the search gives up when it passes
};

// Plans one agent at a time, keeping its scratch (safe intervals per cell, the search's nodes)
// between calls, so that LNS's many small repairs allocate almost nothing.
class SafeIntervalPlanner {
 public:
  explicit SafeIntervalPlanner(const Graph& graph);
  // As plan_through_targets below.
  Path plan(DistTable& dist, const PathTable& table, Vertex start, const std::vector<Vertex>& targets,
            const SpaceTimeLimits& limits, int start_time = 0) {
    return search(dist, nullptr, table, start, -1, targets, limits, start_time, nullptr);
  }
  // The same in the rotation model (action_model.hpp): the agent starts facing `start_heading`, and
  // each step it moves to the cell ahead, turns a quarter or waits; `headings` gets its heading at
  // each step of the path returned. States are (cell, heading, safe interval, targets done).
  // `turning` (distances per cell and heading, ActionModel::kRotate), when given, estimates the way
  // to the next target with its turns; else the cells' distances do (a weaker bound).
  Path plan_with_turns(DistTable& dist, GuidedDistances* turning, const PathTable& table, Vertex start,
                       int start_heading, const std::vector<Vertex>& targets, const SpaceTimeLimits& limits,
                       std::vector<int>& headings, int start_time = 0) {
    return search(dist, turning, table, start, start_heading, targets, limits, start_time, &headings);
  }

 private:
  // start_heading -1: the four-move model (headings is not written).
  Path search(DistTable& dist, GuidedDistances* turning, const PathTable& table, Vertex start, int start_heading,
              const std::vector<Vertex>& targets, const SpaceTimeLimits& limits, int start_time,
              std::vector<int>* headings);
  struct State {
    Vertex v;
    int interval;  // index into the safe intervals of v
    int done;      // targets reached, in order
    int t;         // arrival time
    int f;
    int h;         // remaining distance through the targets, for tie-breaking towards the goal
    int parent;    // index in store_, -1 for the start
    int heading;   // the way it faces (rotation model); 0 in the four-move model
  };
  const Graph& graph_;
  uint32_t stamp_ = 0;
  std::vector<uint32_t> interval_stamp_;  // per vertex: the call whose intervals are in intervals_
  std::vector<std::vector<PathTable::Interval>> intervals_;
  std::vector<State> store_;
  struct OpenEntry {
    int f, h, t;
    int index;  // in store_
  };
  std::vector<OpenEntry> open_;
  std::vector<uint32_t> best_stamp_;  // per vertex: the call whose entries are in best_arrival_
  std::vector<std::vector<int>> best_arrival_;  // per vertex: [(interval * targets + done) * headings + heading]
};

// The earliest-arrival such path, or an empty path when there is none within the limits.
// targets.back() is the goal. The agent is at `start` at `start_time`; the path returned holds
// its cells from `start_time` on (path[0] = start).
Path plan_through_targets(const Graph& graph, DistTable& dist, const PathTable& table, Vertex start,
                          const std::vector<Vertex>& targets, const SpaceTimeLimits& limits, int start_time = 0);

}  // namespace planner_core
