#include "planner_core/task_board.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace planner_core {

TaskBoard::TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log)
    : problem_(problem), log_(log), in_hand_(starts.size()), errand_(starts.size(), 0) {
  const int team = static_cast<int>(starts.size());
  reveal_ = std::max(1, static_cast<int>(std::ceil(problem.tasks_revealed_per_agent)));
  if (problem.assignment == TaskAssignment::kRoundRobin) {
    next_of_agent_.resize(team);
    for (int a = 0; a < team; ++a) next_of_agent_[a] = a;
    for (int a = 0; a < team; ++a) refill(a, starts[a]);
  } else {
    // numTasksReveal x teamSize revealed at a time (2024 on: a multiple of the team, 1.5 in 2026).
    const auto pool = static_cast<int64_t>(std::ceil(problem.tasks_revealed_per_agent * team - 1e-9));
    for (int64_t k = 0; k < std::max<int64_t>(1, pool); ++k) pool_.push_back(next_task_++);
    for (int a = 0; a < team; ++a) refill(a, starts[a]);
  }
}

Vertex TaskBoard::goal(int a) const {
  if (in_hand_[a].empty()) return kNoVertex;
  return task(in_hand_[a].front())[errand_[a]];
}

bool TaskBoard::arrive(int a, Vertex cell, DistTable& distances, int64_t& tasks_finished) {
  if (in_hand_[a].empty() || goal(a) != cell) return false;
  if (++errand_[a] == static_cast<int>(task(in_hand_[a].front()).size())) {
    ++tasks_finished;
    if (log_ != nullptr) log_->events[a].push_back({in_hand_[a].front(), time_, true});
    errand_[a] = 0;
    in_hand_[a].pop_front();
    refill(a, cell, &distances);
  }
  return true;
}

void TaskBoard::refill(int a, Vertex here, DistTable* distances) {
  if (problem_.assignment == TaskAssignment::kRoundRobin) {
    while (static_cast<int>(in_hand_[a].size()) < reveal_) {
      hand_out(a, next_of_agent_[a]);
      next_of_agent_[a] += static_cast<int64_t>(in_hand_.size());
    }
    return;
  }
  if (!in_hand_[a].empty() || pool_.empty()) return;
  size_t best = 0;
  int best_distance = std::numeric_limits<int>::max();
  for (size_t k = 0; k < pool_.size(); ++k) {
    const int d = distances ? distances->get(task(pool_[k]).front(), here) : static_cast<int>(k);
    if (d < best_distance) best_distance = d, best = k;
  }
  hand_out(a, pool_[best]);
  pool_[best] = next_task_++;  // the pool is refilled from the file
}

void TaskBoard::hand_out(int a, int64_t task) {
  in_hand_[a].push_back(task);
  if (log_ == nullptr) return;
  log_->events[a].push_back({task, time_, false});
  log_->tasks_revealed = std::max(log_->tasks_revealed, task + 1);
}

}  // namespace planner_core
