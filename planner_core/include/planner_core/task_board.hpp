// Which tasks each agent of a lifelong run holds, and how tasks are revealed and handed out
// (docs/FORMATS.md). The task file is read in order and started over at its end. A scheduler
// (TaskScheduler) decides who gets what:
// - round-robin (2023 "roundrobin"): agent a's tasks are a, a + teamSize, a + 2 teamSize...,
//   numTasksReveal (rounded up) of them in hand at a time, done in order.
// - nearest-errand (2023 "greedy"): a pool of numTasksReveal x teamSize revealed tasks (rounded
//   up); an agent without a task takes the one whose first errand is nearest, and the pool is
//   refilled from the file.
// - whole-task: the same pool; an agent without a task takes the one it can finish soonest: the
//   way to its first errand and on through the others (the Start-Kit 3.x default scheduler's rule).
// - whole-task-reassign (ours; the default where the file names no strategy, as from 2024 on,
//   when the system schedules the pool): whole-task, and an agent may also take a task another
//   agent holds but has not opened (no errand finished), when it is nearer that task's first
//   errand than the holder is by now; the holder then takes another from the pool. The 2024 rules
//   allow reassigning unopened tasks.
// The whole-task schedulers' costs are steps on the map: with start headings (the rotation
// model, as the 2024 and 2026 rules are), a quarter turn costs a step as a move forward does, and
// a task's cost is the fewest steps to its first errand and on through the others, over every
// heading the robot may arrive with; without, cell distances (breadth-first searches).
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "planner_core/action_model.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/lifelong.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/task_scheduler.hpp"

namespace planner_core {

class TaskBoard {
 public:
  // `log`, when set, records each task handed out and finished.
  TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log);
  // `start_headings` (the rotation model): turns count in the whole-task schedulers' costs.
  TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log, TaskScheduler scheduler,
            const Headings& start_headings = {});

  // The errand agent a heads for, or kNoVertex.
  Vertex goal(int a) const;
  // The task agent a works on (-1: none), and how many of its errands it has finished.
  int64_t task_of(int a) const { return in_hand_[a].empty() ? -1 : in_hand_[a].front(); }
  int errands_done(int a) const { return errand_[a]; }

  // The time events are recorded at: the steps done so far.
  void set_time(int time) { time_ = time; }

  // Agent a stands on `cell` facing `heading` (told every step, for every agent; the heading
  // matters only to a board given start headings): finishes its errand there, if it is one;
  // returns whether it did, and counts a finished task in `tasks_finished`.
  bool arrive(int a, Vertex cell, int heading, DistTable& distances, int64_t& tasks_finished);

  // Tasks taken from an agent that had not opened them, for one nearer (whole-task-reassign).
  int64_t reassignments() const { return reassignments_; }

 private:
  const std::vector<Vertex>& task(int64_t k) const { return problem_.tasks[k % problem_.tasks.size()]; }
  void refill(int a, Vertex here, DistTable* distances = nullptr);
  bool counts_turns() const { return !heading_of_.empty(); }
  // Whole-task schedulers: agent a at `here` takes a task (from another agent, when `may_take`).
  void schedule(int a, Vertex here, bool may_take);
  // Steps from `from` (facing `heading` when turns count) to every cell, in steps_from_: per cell,
  // or per cell and heading of arrival when turns count (kUnreachable where none).
  void search_from(Vertex from, int heading);
  // The fewest steps to task k's first errand (from the last search_from) and on through its others.
  int64_t cost_of(int64_t k);
  // The steps to task k's first errand from the last search_from.
  int way_to(int64_t k) const;
  // Steps from task k's first errand through its others, per heading it is reached with (all
  // four alike when turns do not count); cached per task of the file.
  const std::array<int, kHeadings>& length_of(int64_t k);
  // Rotation model: steps from (from, each heading) to (to, each heading), fewest first.
  std::array<std::array<int, kHeadings>, kHeadings> leg(Vertex from, Vertex to);
  void hand_out(int a, int64_t task);

  const LorrProblem& problem_;
  LifelongLog* log_;
  TaskScheduler scheduler_;
  int time_ = 0;
  int reveal_ = 1;
  std::vector<std::deque<int64_t>> in_hand_;  // per agent, its tasks in order
  std::vector<int> errand_;                   // per agent, the errand of its first task it heads for
  std::vector<int64_t> next_of_agent_;        // round-robin: the next task each agent gets
  std::vector<int64_t> pool_;                 // the pool: revealed tasks nobody holds
  int64_t next_task_ = 0;
  // Whole-task schedulers: per agent, when it took its task and how far its first errand was.
  std::vector<int> taken_at_;
  std::vector<int> way_when_taken_;
  Config at_;                                 // per agent, the cell it last arrived on
  Headings heading_of_;                       // per agent, its heading there (empty: turns not counted)
  std::vector<std::array<int, kHeadings>> length_;  // per task of the file: -1 until searched
  std::vector<int> steps_from_;
  std::vector<int> frontier_;
  int64_t reassignments_ = 0;
};

}  // namespace planner_core
