// Lifelong MAPF as the League of Robot Runners runs it (docs/FORMATS.md, "League of Robot Runners
// problems"): agents never finish. Each has a queue of revealed tasks; a task is a list of errands
// (locations) visited in order; when an agent reaches the errand it heads for, that errand is
// finished, and when its last errand is, the task is, and the next task is revealed. Every step a
// planner decides each agent's next cell within a time budget; a step that takes longer, or that
// is not a valid step (a move to a non-neighbouring cell, two agents on one cell, two agents
// swapping), is replaced by everyone waiting, as the league does. An agent finishes at most one
// errand per step. The figure is errands finished within the horizon.
//
// Agents act in one of two models (action_model.hpp): four moves, or the league's rotation model
// (forward, turn clockwise, turn counter-clockwise, wait), every agent facing east at the start
//
// This header is the run loop (run_lifelong) and what a planner answers to (LifelongPlanner); the
// planner the product runs is PibtLifelong (pibt_lifelong.hpp), its "auto" settings come from
// lifelong_auto_rules.hpp, and tasks are handed out by TaskBoard (task_board.hpp).
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "planner_core/action_model.hpp"
#include "planner_core/deadline.hpp"
#include "planner_core/instance.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/step_faults.hpp"
#include "planner_core/task_scheduler.hpp"

namespace planner_core {

// Decides every agent's next pose from where they stand and the errand each heads for (its
// current cell when it has none).
class LifelongPlanner {
 public:
  virtual ~LifelongPlanner() = default;
  virtual Poses next_step(const Poses& now, const Config& goals, const Deadline& deadline) = 0;
  // The league's preprocessing time, before the first step: learn what helps plan these goals.
  virtual void prepare(const Poses& /*now*/, const Config& /*goals*/, const Deadline& /*deadline*/) {}
};

// What the league's output file records of a run (docs/FORMATS.md, "League of Robot Runners
// output"); filled when LifelongSettings::log is set.
struct LifelongLog {
  struct Event {
    int64_t task;
    int step;
    bool finished;  // else assigned
  };
  struct Error {
    int agent1;
    int agent2;  // -1 when one agent is involved
    int step;
    std::string what;
  };
  std::vector<Vertex> starts;
  ActionModel actions = ActionModel::kMove4;
  Headings start_headings;            // rotation model
  std::vector<std::string> actual;    // per agent, one letter per step: U D L R W, or F R C W
  std::vector<std::string> planned;   // as the planner returned it; T when it was late
  std::vector<std::vector<Event>> events;  // per agent
  std::vector<Error> errors;
  int64_t tasks_revealed = 0;         // tasks 0 .. tasks_revealed-1 were handed out
  std::vector<int> cost;              // per agent, steps it held a task
};

struct LifelongSettings {
  int steps = 500;            // the horizon
  double step_time_s = 1.0;   // the budget to decide one step
  double preprocess_time_s = 60;  // the budget before the first step (the league's preprocessing)
  LifelongLog* log = nullptr;     // set: the run is recorded there
  const std::atomic<bool>* interrupt = nullptr;  // set (Ctrl-C): the run ends after the step under way
  ActionModel actions = ActionModel::kMove4;     // the planner must plan in the same one
  // A step decided after its budget is still taken (and counted in steps_over_budget), not
  // replaced by waiting: for planners whose work is counted, not timed (lns_rounds).
  bool late_steps_taken = false;
  std::optional<TaskScheduler> scheduler;  // who gets which task; none: the problem's rules (scheduler_for)
};

struct LifelongResult {
  int64_t errands_finished = 0;
  int64_t tasks_finished = 0;
  std::vector<int> errands_per_step;  // finished at each step
  std::vector<double> step_ms;        // time the planner took to decide each step
  double preprocess_ms = 0;           // time the planner took to prepare
  int steps_over_budget = 0;          // the planner took longer than its budget: replaced by waiting
                                      // (unless LifelongSettings::late_steps_taken)
  int invalid_steps = 0;              // replaced by waiting: not a valid step
  std::string first_invalid;          // what the first invalid step did
  int64_t moves = 0;                  // agent-steps spent off their current cell
  bool interrupted = false;           // ended by settings.interrupt before the horizon
};

// Runs `problem` for settings.steps steps with `planner`, tasks handed out by TaskBoard
// (task_board.hpp) as the problem says.
LifelongResult run_lifelong(const LorrProblem& problem, LifelongPlanner& planner, const LifelongSettings& settings);

}  // namespace planner_core
