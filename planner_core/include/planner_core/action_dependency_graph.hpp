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
// A robot that stops for good (a robot lost mid-plan) would hold back every move that waits on its
// next ones, and those that wait on them in turn: moves_kept_around() finds exactly those moves,
// keep_moves() drops them, and the rest of the plan goes on and can grow from where it then ends.
//
// Plans with turns (the rotation model) give each robot's heading at every step: a turn in place
// is a move of its own (from and to the same cell, a new heading) that waits only for the robot's
// own previous moves, since it neither enters nor leaves a cell.
#pragma once

#include <algorithm>
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

  // Robot `stuck` will finish none of its moves from `unfinished` on: how many moves each robot
  // keeps when its moves from `keep` on go (keep >= unfinished: a move in flight stays, its target
  // still the robot's) and every move of the others that waits on one of its moves from
  // `unfinished` on, directly or through other moves, with every later move of the same robot.
  // keep_moves() then drops the rest. The plan then ends on each robot's last kept move (its start
  // if it has none), at the same step as before: what is kept was a valid prefix of each robot's moves in the plan's order, and no
  // kept move enters a cell after the robot standing on it at its last kept move (that would
  // have waited on the robot's next move, which is dropped), so each robot may wait where its
  // moves now end until the plan goes on. Moves already started are never dropped (they waited
  // only on finished ones) as long as `finished(robot)` is what each robot finished.
  template <typename FinishedOf>
  std::vector<int> moves_kept_around(int stuck, int unfinished, int keep, FinishedOf finished_of) const;
  // A robot not in the plan now stands on `cell`: how many moves each robot keeps when every move
  // into `cell` not finished goes, with every move that waits on one of them, directly or through
  // other moves, and every later move of the same robot (the same argument as above: the plan
  // then ends on distinct cells, none of them `cell`). The caller makes sure no robot stands on
  // `cell` or has a move into or out of it under way.
  template <typename FinishedOf>
  std::vector<int> moves_kept_clear_of(Vertex cell, FinishedOf finished_of) const;
  // A robot joins the plan where it ends, standing on `at` (facing `heading` in plans with turns),
  // with no moves yet: moves into `at` the plan grows by will wait on its leaving. Its index is
  // robot_count() before the call.
  void add_robot(Vertex at, int heading = -1);
  // Drops robot r's moves from kept[r] on (forgotten ones stay forgotten); the plan ends on each
  // robot's last kept move, at the same step.
  void keep_moves(const std::vector<int>& kept);

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
  // How many moves each robot keeps when those `goes(robot, index)` names (of those not finished)
  // go, with every move that waits on one of them or on a move `never_finishes(robot, index)`
  // names, directly or through other moves, and every later move of the same robot.
  template <typename Goes, typename NeverFinishes, typename FinishedOf>
  std::vector<int> moves_kept_without(Goes goes, NeverFinishes never_finishes, FinishedOf finished_of) const;

  std::vector<std::deque<Move>> moves_;
  std::vector<int> forgotten_;  // per robot, moves freed from the front
  // Per cell, the latest departure from it so far (robot, move index). A move into the cell waits
  // for that one alone: the robot that left it had itself waited, on arriving, for the departure
  // before, so the cell's whole order follows (and a long lifelong plan keeps one entry per cell,
  // not one per robot that ever left it).
  std::unordered_map<Vertex, std::pair<int, int>> last_departures_;
  Config first_, last_;
  Headings first_headings_, last_headings_;
  int steps_ = 0;
};

template <typename Goes, typename NeverFinishes, typename FinishedOf>
std::vector<int> ActionDependencyGraph::moves_kept_without(Goes goes, NeverFinishes never_finishes,
                                                          FinishedOf finished_of) const {
  const int robots = robot_count();
  std::vector<int> kept(robots);
  for (int r = 0; r < robots; ++r) {
    kept[r] = move_count(r);
    for (int index = std::max(forgotten_[r], finished_of(r)); index < kept[r]; ++index) {
      if (goes(r, index)) {
        kept[r] = index;
        break;
      }
    }
  }
  // A move goes when it waits on a move that never finishes or on one that goes; dependencies
  // point back in plan time (or to the same step, a robot leaving the cell another enters), so a
  // few passes settle it.
  for (bool changed = true; changed;) {
    changed = false;
    for (int r = 0; r < robots; ++r) {
      for (int index = std::max(forgotten_[r], finished_of(r)); index < kept[r]; ++index) {
        const auto waits_in_vain = [&](const std::pair<int, int>& on) {
          const auto [other, move] = on;
          return move >= kept[other] || (move >= finished_of(other) && never_finishes(other, move));
        };
        const std::vector<std::pair<int, int>>& after = this->move(r, index).after;
        if (std::any_of(after.begin(), after.end(), waits_in_vain)) {
          kept[r] = index;
          changed = true;
          break;
        }
      }
    }
  }
  return kept;
}

template <typename FinishedOf>
std::vector<int> ActionDependencyGraph::moves_kept_around(int stuck, int unfinished, int keep,
                                                         FinishedOf finished_of) const {
  return moves_kept_without([&](int robot, int index) { return robot == stuck && index >= keep; },
                            [&](int robot, int index) { return robot == stuck && index >= unfinished; }, finished_of);
}

template <typename FinishedOf>
std::vector<int> ActionDependencyGraph::moves_kept_clear_of(Vertex cell, FinishedOf finished_of) const {
  return moves_kept_without([&](int robot, int index) { return move(robot, index).to == cell; },
                            [](int, int) { return false; }, finished_of);
}

}  // namespace planner_core
