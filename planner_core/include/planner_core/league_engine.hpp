// The engine a fleet works a stream of tasks with: the scheduler (TaskBoard), the window planner
// (a LifelongPlanner that plans without rotations) and the executor's plan (the Action Dependency
// Graph), behind one small interface.
//
//   in:  how many staged moves each robot has finished (its executed progress)
//   out: the staged plan, moves each robot may start once the graph allows (staged());
//        each robot's task (task_of); the errands it reaches, in order (next_errand)
//
// plan() extends the staged plan from where it ends, never from where robots stand now: moves
// already staged are committed. The scheduler moves on as the plan reaches errands (the next
// errand, or a new task), so a task the plan has not reached is still in the pool and may go to
// a nearer robot. An errand counts as finished when its robot has carried the plan out to the
// errand's step (errand_due). The league's lockstep run (league_run.hpp) drives the engine tick
// by tick; a fleet drives it from its robots' reports.
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <string>
#include <utility>
#include <vector>

#include "planner_core/action_dependency_graph.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/lifelong.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/task_board.hpp"

namespace planner_core {

class LeagueEngine {
 public:
  // An errand the plan reaches at `plan_step`.
  struct Errand {
    int plan_step;
    int64_t task;
    int errands_done;   // of the task, this one included
    bool task_finished;
    int64_t next_task;  // the robot's task after this errand (-1: none)
  };
  // What one plan() did.
  struct PlanCall {
    int steps = 0;          // steps added to the staged plan
    int late_steps = 0;     // decided after their share of the budget: replaced by waiting
    int invalid_steps = 0;  // not a valid step (planner_core/step_faults.hpp): replaced by waiting
    std::string first_invalid;
    double ms = 0;
  };

  // Robots start on problem.starts facing east. `lead_steps`: how far ahead of the median robot
  // plan() keeps the staged plan.
  LeagueEngine(const LorrProblem& problem, LifelongPlanner& planner, TaskScheduler scheduler, int lead_steps);

  // The planner's preprocessing, before the first plan().
  void prepare(const Deadline& deadline);
  // Extends the staged plan to lead_steps ahead of the median robot, each step within its share
  // of `budget_s`. moves_finished[r]: staged moves robot r has finished.
  PlanCall plan(const std::vector<int>& moves_finished, double budget_s, const std::atomic<bool>* interrupt = nullptr);
  // Robots seen delayed (held[r] set) are planned to stay where the staged plan leaves them in
  // the next plan(), so the others are planned round them rather than through where they would be
  // had they not been delayed; from then on they are planned as usual.
  void hold(std::vector<char> held) { held_ = std::move(held); }

  const ActionDependencyGraph& staged() const { return staged_; }
  ActionDependencyGraph& staged() { return staged_; }  // for forget_before, as robots finish moves
  // The last plan step robot r stands in, having finished `moves_finished` of its moves.
  int executed_step(int r, int moves_finished) const;
  // Robot r's next errand in the plan, or nullptr; whether it has carried the plan out that far;
  // and the errand counted (pops it).
  const Errand* next_errand(int r) const { return errands_[r].empty() ? nullptr : &errands_[r].front(); }
  bool errand_due(int r, int moves_finished) const;
  void errand_counted(int r) { errands_[r].pop_front(); }

  int64_t task_of(int r) const { return board_.task_of(r); }
  int64_t reassignments() const { return board_.reassignments(); }
  int robots() const { return static_cast<int>(errands_.size()); }

 private:
  Config goals() const;
  // The plan reaches errands at `step`: the board moves on, and each is queued for its robot.
  void reach_errands(int step);

  const Graph& graph_;
  LifelongPlanner& planner_;
  const int lead_steps_;
  DistTable distances_;
  TaskBoard board_;
  Poses planned_;  // where the staged plan ends
  ActionDependencyGraph staged_;
  std::vector<std::deque<Errand>> errands_;
  std::vector<char> held_;  // per robot: planned to stay in the next plan() (empty: none)
};

}  // namespace planner_core
