// FleetTrace: what a fleet of robot processes did, as an observer on its domain heard it: each
// robot's poses at rest (cell and heading, each time one changes, timed by the robot's own arrival
// stamp) and the coordinator's task events. league_log_of_fleet turns it into the League of Robot
// Runners' 2026 output (planner_core/league_output.hpp), so PlanViz and the league's tools show the
// fleet's run beside the lockstep run of the same problem.
//
// The fleet has no ticks: its robots move each on its own clock. An action is put on the tick of
// its robot's arrival, (stamp - start) / tick, and on the following ticks when it takes several
// (agentCounter). The executor starts a move only once the moves it depends on have ended, and
// every move lasts at least a step, so a robot entering a cell is put at least a tick after the
// robot that left it: the ticks keep the fleet's order. A robot's action that would land on a tick
// its previous one holds is put on the next free one and counted (`shifted`).
//
//   robot states (at rest) ──> poses per robot ──> letters per tick (F R C, W between) ──┐
//   coordinator events (task_added, task_reassigned, task_done) ──> schedule, events ────┴─> LeagueLog
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "fleet_transport/messages.hpp"
#include "planner_core/league_run.hpp"
#include "planner_core/lorr_problem.hpp"

namespace coordinator {

class FleetTrace {
 public:
  struct Pose {
    int64_t stamp_ms;  // the robot's wall clock when it arrived (or finished turning)
    int x, y, heading;
  };
  struct TaskEvent {
    int64_t stamp_ms;  // the coordinator's wall clock
    std::string kind;  // task_added, task_reassigned, task_done
    std::string robot_id;
    int task;          // the fleet's task id
  };

  // A robot at rest (a state not moving) adds a pose when its cell or heading changed.
  void heard_state(const fleet_transport::RobotState& state);
  void heard_event(const fleet_transport::FleetEvent& event);

  const std::map<std::string, std::vector<Pose>>& poses() const { return poses_; }
  const std::vector<TaskEvent>& task_events() const { return task_events_; }

 private:
  std::map<std::string, std::vector<Pose>> poses_;
  std::vector<TaskEvent> task_events_;
};

struct FleetLeagueRun {
  planner_core::LeagueLog log;
  planner_core::LeagueRunResult result;
  int shifted = 0;  // actions put a tick or more after their robot's arrival (see above)
  int jumps = 0;    // pose changes no action explains (a robot put down elsewhere): logged as errors
};

// The run of robots "robot0".."robot<robots-1>", which started on the problem's first `robots`
// starts, from wall-clock `start_ms` to `end_ms` in ticks of `tick_ms`. `problem_task_of` maps the
// fleet's task ids to the problem's revealed task numbers (k: the problem's task k % its count);
// events of other tasks are left out. `delays`: the robots were delayed (the output's delaysOn; the
// fleet does not know when, so delayIntervals stay empty).
FleetLeagueRun league_log_of_fleet(const FleetTrace& trace, const planner_core::LorrProblem& problem, int robots,
                                   int64_t start_ms, int64_t end_ms, int tick_ms,
                                   const std::map<int, int64_t>& problem_task_of);

}  // namespace coordinator
