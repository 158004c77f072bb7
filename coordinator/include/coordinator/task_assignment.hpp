// Tasks given to a running fleet: checking an operator's request against the mission's map and
// choosing the robot for a new task by cheapest insertion (the robot whose current tour -- where it
// stands, its task visits still to make in the order its plan makes them, its goal -- grows least
// when the task is put at its best place in it). Pure functions: no DDS, no clock.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner_core/dist_table.hpp"
#include "planner_core/instance.hpp"

namespace coordinator {

// One robot's tour as its plan makes it: stops[0] is where it stands, the last stop its goal.
struct Tour {
  std::string robot_id;
  int role = -1;
  std::vector<planner_core::Vertex> stops;
};

struct TaskPlacement {
  int tour = -1;        // index into the tours; -1: no tour can reach the task
  size_t position = 0;  // the task goes before stops[position]
  int added_steps = 0;  // how much longer the tour gets
};

// The cheapest insertion of `task` into one of `tours` (ties: the first tour, the earliest place).
// Tours that cannot reach the task are skipped.
TaskPlacement cheapest_insertion(planner_core::DistTable& distances, planner_core::Vertex task,
                                 const std::vector<Tour>& tours);

// Lifelong mode: the tour that reaches `task` soonest when the task goes after its last task
// (before its goal): the steps along the tour to its last task, then on to `task`, as
// `added_steps`. Robots' loads stay even, where cheapest insertion would pile tasks on the robot
// whose way passes by (a long queue, the others idle). Ties: the first tour.
TaskPlacement earliest_arrival(planner_core::DistTable& distances, planner_core::Vertex task,
                               const std::vector<Tour>& tours);

// Lifelong mode's pool, by the league engine's rule (planner_core/task_board.hpp, whole-task
// reassignment): a task added at runtime is given to a robot at once, but until the plan reaches
// it, it may go to another. A robot that has run out of tasks takes the pooled task it reaches
// soonest, when it gets there sooner than the robot holding it would (by that robot's way through
// the tasks it heads for first: the nearest, then the nearest of the rest, as the window planner
// goes) or when that robot is out. Pairs are taken nearest first; a robot takes one task per call.
struct PoolRobot {
  planner_core::Vertex from = planner_core::kNoVertex;  // where its plan ends
  std::vector<planner_core::Vertex> errands;            // task cells it still heads for, not yet in its plan
  bool out = false;                                     // lost: takes nothing, holds nothing it keeps
};
struct PooledTask {
  int task = -1;
  planner_core::Vertex at = planner_core::kNoVertex;
  int holder = -1;  // index into the robots
};
struct TaskMove {
  int task = -1;
  int from = -1, to = -1;  // robots' indices
  int way = 0;             // steps from the taker's plan end to the task
  int holder_way = -1;     // the holder's, -1 when it was out
};
// Moves tasks (updating `robots`' errands and `tasks`' holders) and returns the moves made.
std::vector<TaskMove> rebalance_pool(planner_core::DistTable& distances, std::vector<PoolRobot>& robots,
                                     std::vector<PooledTask>& tasks);

// Why a task at (x, y) cannot be added to `mission` ("" when it can): off the map, or a wall.
std::string task_cell_refusal(const planner_core::Instance& mission, int x, int y);

}  // namespace coordinator
