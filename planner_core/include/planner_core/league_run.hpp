// A lifelong run under the League of Robot Runners' 2026 rules (MAPF-Competition/Start-Kit 3.x),
// in lockstep: the bench's simulator of what a real fleet does. Time goes in ticks. Every action
// (a step forward or a quarter turn, the rotation model) takes agentCounter ticks; robots are
// delayed as the problem's delayConfig draws (delay_draws.hpp), and a delayed robot stands still,
// mid-move or not. Every plan period (planCommTimeLimit, in ticks of actionMoveTimeLimit) the
// planner is called: it extends the staged plan from the configuration where the staged moves
// end, as many steps as keep the plan a period and a half ahead of the fleet, within the
// period's time; tasks are handed out as the plan reaches errands (task_board.hpp), so a task
// the plan has not reached is still in the pool. The one executor, the Action Dependency Graph
// (action_dependency_graph.hpp), starts each robot's next staged move once the moves it depends
// on are finished: a delayed robot holds up only the robots that must pass where it stands, never
// causes a collision, and waits in its plan cost it nothing once it goes on. An errand counts as
// finished at the tick its robot actually stands on it; a robot with a second errand due on the
// same cell stays a tick for it.
//
//   tick:  [plan period?] -> delays drawn -> moves under way go on -> errands counted (one per
//          robot and tick, as the league counts) -> ready robots start a move -> checked: no two
//          robots on one cell (a moving robot holds both)
//
// Every tick is checked independently of the executor (cells held, moves to neighbours only);
// a fault is counted and logged, never hidden: it would be the worst bug.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "planner_core/lifelong.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/task_board.hpp"

namespace planner_core {

// What the league's 2026 output file records of a run (league_output.hpp); filled when
// LeagueRunSettings::log is set.
struct LeagueLog {
  struct Event {
    int tick;
    int robot;
    int64_t task;
    int errands_done;  // k: the task's k-th errand was finished at `tick`
  };
  std::vector<Vertex> starts;
  Headings start_headings;
  std::vector<std::string> actual;  // per robot, one letter per tick: F R C (a tick of that action) or W
  std::vector<std::vector<std::pair<int, int>>> delay_intervals;  // per robot: [first tick, last tick]
  std::vector<Event> events;
  std::vector<std::vector<std::pair<int, int64_t>>> schedule;  // per robot: (tick, its first task) as it changes
  std::vector<LifelongLog::Error> errors;
  int64_t tasks_revealed = 0;
};

struct LeagueRunSettings {
  int ticks = 5000;                // simulationTime
  int tick_ms = 100;               // actionMoveTimeLimit
  int plan_period_ms = 1000;       // planCommTimeLimit: the planner's call every period, and its budget
  double preprocess_time_s = 30;   // preprocessTimeLimit
  bool delays = true;              // off: the problem's delayConfig is ignored
  // Robots delayed for longer than an action when the planner is called are planned to stay
  // where their staged moves end, the others round them (LeagueEngine::hold). Off: measured no
  // better (docs/RESULTS.md, "The league's 2026 rules").
  bool plan_round_delayed = false;
  // How far ahead of the median robot the staged plan is kept, in plan periods' worth of actions.
  double lead_periods = 1.5;
  // Who gets which task (task_board.hpp); unset: the one the problem's rules name.
  std::optional<TaskScheduler> scheduler;
  LeagueLog* log = nullptr;        // set: the run is recorded there
  const std::atomic<bool>* interrupt = nullptr;  // set (Ctrl-C): the run ends after the tick under way
};

struct LeagueRunResult {
  int64_t tasks_finished = 0;
  int64_t errands_finished = 0;
  std::vector<int> tasks_per_tick;      // tasks finished at each tick
  std::vector<double> plan_ms;          // each planning call's time
  int plan_steps = 0;                   // steps planned in all
  int late_steps = 0;                   // planned after their share of the call's budget: replaced by waiting
  int invalid_steps = 0;                // not a valid step: replaced by waiting
  std::string first_invalid;
  int64_t delayed_robot_ticks = 0;      // robot-ticks spent delayed
  int64_t robot_ticks = 0;              // robots x ticks run
  int64_t moves_finished = 0;           // actions carried out (forward moves and turns)
  int64_t reassignments = 0;            // unopened tasks given to a nearer robot (task_board.hpp)
  int faults = 0;                       // the tick check found two robots on one cell, or a jump: must be 0
  std::string first_fault;
  double preprocess_ms = 0;
  bool interrupted = false;
  // The share of robot time spent delayed: the league's f.
  double delayed_share() const { return robot_ticks == 0 ? 0 : static_cast<double>(delayed_robot_ticks) / robot_ticks; }
};

// Runs `problem` for settings.ticks ticks in the rotation model with `planner`, which must plan
// without rotations (PibtLifelongSettings::forbid_rotations): a cycle of robots moving in one step
// cannot be carried out one move at a time. Throws std::invalid_argument when the planning period
// is not a whole number of ticks.
LeagueRunResult run_league(const LorrProblem& problem, LifelongPlanner& planner, const LeagueRunSettings& settings);

}  // namespace planner_core
