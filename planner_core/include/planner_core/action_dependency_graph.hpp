// Action Dependency Graph (Hoenig et al., "Persistent and Robust Execution of MAPF Schedules in
// Warehouses", RA-L 2019): each robot's plan becomes a chain of moves; a move into a cell waits
// until every other robot that is at that cell earlier in the plan has moved out of it. Sending a
// move only when its dependencies are done keeps the plan's order at every cell, so delays
// propagate but never cause a collision or a deadlock (the plan has no cycle of robots moving in
// one step: each move of a cycle would wait for the next).
//
// The plan may grow while it is carried out (lifelong mode): extend() appends steps after its last
// configuration. Moves already there keep their dependencies, since a later move never holds an
// earlier one back. A move its robot has finished is never asked about again, so forget_before()
// frees it (a lifelong plan grows without end); move indices stay as they were.
//
// It is the product's one executor: the coordinator sends robots their moves by it
// (coordinator/plan_execution.hpp), and a lockstep run can carry staged plans out by it as well.
//
// Plans with turns (the rotation model) give each robot's heading at every step: a turn in place
// is a move of its own (from and to the same cell, a new heading) that waits only for the robot's
// own previous moves, since it neither enters nor leaves a cell.
#pragma once

#include <deque>
#include <unordered_map>
#include <vector>

#include "planner_core/solution.hpp"

namespace planner_core {

struct Move {
  Vertex from;
  Vertex to;
  int plan_time;  // the timestep at which the plan has the robot arrive at `to`
  int heading = -1;  // plans with turns: the heading the robot ends the move facing; -1 otherwise
  // (robot, move index) pairs that must be finished before this move may start.
  std::vector<std::pair<int, int>> after;
};

class ActionDependencyGraph {
 public:
  // Robot r's moves come from column r of `plan` (waits dropped); `headings`, when given (plans
  // with turns), holds every robot's heading at every step of `plan`.
  explicit ActionDependencyGraph(const Solution& plan, const HeadingPlan& headings = {});

  // The plan goes on with `more` (and its headings, for plans with turns), whose first
  // configuration must be the plan's last (else std::invalid_argument); its moves become each
  // robot's next moves.
  void extend(const Solution& more, const HeadingPlan& headings = {});

  int robot_count() const { return static_cast<int>(moves_.size()); }
  // Robot r's moves so far, forgotten ones included.
  int move_count(int robot) const { return forgotten_[robot] + static_cast<int>(moves_[robot].size()); }
  // Robot r's move `index` (not forgotten).
  const Move& move(int robot, int index) const { return moves_[robot][index - forgotten_[robot]]; }
  // Robot r's moves from its first one not forgotten on.
  const std::deque<Move>& moves(int robot) const { return moves_[robot]; }
  // Frees robot r's moves before `index` (it has finished them).
  void forget_before(int robot, int index);
  // Timesteps in the plan so far, and its last configuration.
  int plan_steps() const { return steps_; }
  const Config& last_configuration() const { return last_; }
  // Plans with turns: the headings at the plan's last step (empty otherwise).
  const Headings& last_headings() const { return last_headings_; }
  // May robot r start move k, given how many moves each robot has finished?
  bool ready(int robot, int move, const std::vector<int>& finished) const {
    return ready(robot, move, [&finished](int other) { return finished[other]; });
  }
  // The same, with `finished_of(robot)` giving how many moves that robot has finished.
  template <typename FinishedOf>
  bool ready(int robot, int move, FinishedOf finished_of) const {
    if (finished_of(robot) != move) return false;  // its own previous moves first
    for (const auto& [other, index] : this->move(robot, move).after) {
      if (finished_of(other) <= index) return false;
    }
    return true;
  }

 private:
  std::vector<std::deque<Move>> moves_;
  std::vector<int> forgotten_;  // per robot, moves freed from the front
  // Per cell, the latest departure from it so far (robot, move index). A move into the cell waits
  // for that one alone: the robot that left it had itself waited, on arriving, for the departure
  // before, so the cell's whole order follows (and a long lifelong plan keeps one entry per cell,
  // not one per robot that ever left it).
  std::unordered_map<Vertex, std::pair<int, int>> last_departures_;
  Config last_;
  Headings last_headings_;
  int steps_ = 0;
};

}  // namespace planner_core
