// Action Dependency Graph (Hoenig et al., "Persistent and Robust Execution of MAPF Schedules in
// Warehouses", RA-L 2019): each robot's plan becomes a chain of moves; a move into a cell waits
// until every other robot that is at that cell earlier in the plan has moved out of it. Sending a
// move only when its dependencies are done keeps the plan's order at every cell, so delays
// propagate but never cause a collision or a deadlock.
#pragma once

#include <vector>

#include "planner_core/solution.hpp"

namespace coordinator {

struct Move {
  planner_core::Vertex from;
  planner_core::Vertex to;
  int plan_time;  // the timestep at which the plan has the robot arrive at `to`
  // (robot, move index) pairs that must be finished before this move may start.
  std::vector<std::pair<int, int>> after;
};

class ActionDependencyGraph {
 public:
  // Robot r's moves come from column r of `plan` (waits dropped).
  explicit ActionDependencyGraph(const planner_core::Solution& plan);

  int robot_count() const { return static_cast<int>(moves_.size()); }
  const std::vector<Move>& moves(int robot) const { return moves_[robot]; }
  // May robot r start move k, given how many moves each robot has finished?
  bool ready(int robot, int move, const std::vector<int>& finished) const {
    return ready(robot, move, [&finished](int other) { return finished[other]; });
  }
  // The same, with `finished_of(robot)` giving how many moves that robot has finished.
  template <typename FinishedOf>
  bool ready(int robot, int move, FinishedOf finished_of) const {
    if (finished_of(robot) != move) return false;  // its own previous moves first
    for (const auto& [other, index] : moves_[robot][move].after) {
      if (finished_of(other) <= index) return false;
    }
    return true;
  }

 private:
  std::vector<std::vector<Move>> moves_;
};

}  // namespace coordinator
