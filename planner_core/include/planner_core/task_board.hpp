// Which tasks each agent of a lifelong run holds, and how tasks are revealed and handed out, as
// the League of Robot Runners' 2023 rules do (docs/FORMATS.md). The task file is read in order and
// started over at its end. Round-robin: agent a's tasks are a, a + teamSize, a + 2 teamSize...,
// tasks_revealed_per_agent (rounded up) of them revealed at a time, done in order. Greedy (also
// where the file names no strategy, as from 2024 on): a pool of tasks_revealed_per_agent x teamSize
// revealed tasks (rounded up); an agent without a task takes the one whose first errand is
// nearest, and the pool is refilled.
#pragma once

#include <cstdint>
#include <deque>
#include <vector>

#include "planner_core/dist_table.hpp"
#include "planner_core/lifelong.hpp"
#include "planner_core/lorr_problem.hpp"

namespace planner_core {

class TaskBoard {
 public:
  // `log`, when set, records each task handed out and finished.
  TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log);

  // The errand agent a heads for, or kNoVertex.
  Vertex goal(int a) const;

  // The time events are recorded at: the steps done so far.
  void set_time(int time) { time_ = time; }

  // Agent a stands on `cell`: finishes its errand there, if it is one; returns whether it did,
  // and counts a finished task in `tasks_finished`.
  bool arrive(int a, Vertex cell, DistTable& distances, int64_t& tasks_finished);

 private:
  const std::vector<Vertex>& task(int64_t k) const { return problem_.tasks[k % problem_.tasks.size()]; }
  void refill(int a, Vertex here, DistTable* distances = nullptr);
  void hand_out(int a, int64_t task);

  const LorrProblem& problem_;
  LifelongLog* log_;
  int time_ = 0;
  int reveal_ = 1;
  std::vector<std::deque<int64_t>> in_hand_;  // per agent, its tasks in order
  std::vector<int> errand_;                   // per agent, the errand of its first task it heads for
  std::vector<int64_t> next_of_agent_;        // round-robin: the next task each agent gets
  std::vector<int64_t> pool_;                 // greedy: revealed tasks nobody holds
  int64_t next_task_ = 0;
};

}  // namespace planner_core
