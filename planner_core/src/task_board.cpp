#include "planner_core/task_board.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "planner_core/input_error.hpp"

namespace planner_core {

namespace {

constexpr const char* kSchedulerNames[] = {"round-robin", "nearest-errand", "whole-task", "whole-task-reassign"};

}  // namespace

TaskScheduler scheduler_for(TaskAssignment assignment) {
  switch (assignment) {
    case TaskAssignment::kRoundRobin: return TaskScheduler::kRoundRobin;
    case TaskAssignment::kGreedy: return TaskScheduler::kNearestErrand;
    case TaskAssignment::kPool: break;
  }
  return TaskScheduler::kWholeTaskReassign;
}

std::string to_string(TaskScheduler scheduler) { return kSchedulerNames[static_cast<int>(scheduler)]; }

TaskScheduler parse_task_scheduler(const std::string& text, const std::string& what) {
  for (int k = 0; k < 4; ++k) {
    if (text == kSchedulerNames[k]) return static_cast<TaskScheduler>(k);
  }
  throw InputError(what + ": '" + text + "' is not round-robin, nearest-errand, whole-task or whole-task-reassign");
}

TaskBoard::TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log)
    : TaskBoard(problem, starts, log, scheduler_for(problem.assignment)) {}

TaskBoard::TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log, TaskScheduler scheduler)
    : problem_(problem),
      log_(log),
      scheduler_(scheduler),
      in_hand_(starts.size()),
      errand_(starts.size(), 0),
      taken_at_(starts.size(), 0),
      way_when_taken_(starts.size(), 0),
      at_(starts),
      length_(problem.tasks.size(), -1) {
  const int team = static_cast<int>(starts.size());
  reveal_ = std::max(1, static_cast<int>(std::ceil(problem.tasks_revealed_per_agent)));
  if (scheduler == TaskScheduler::kRoundRobin) {
    next_of_agent_.resize(team);
    for (int a = 0; a < team; ++a) next_of_agent_[a] = a;
    for (int a = 0; a < team; ++a) refill(a, starts[a]);
    return;
  }
  // numTasksReveal x teamSize revealed at a time (2024 on: a multiple of the team, 1.5 in 2026).
  const auto pool = static_cast<int64_t>(std::ceil(problem.tasks_revealed_per_agent * team - 1e-9));
  for (int64_t k = 0; k < std::max<int64_t>(1, pool); ++k) pool_.push_back(next_task_++);
  if (scheduler == TaskScheduler::kNearestErrand) {
    for (int a = 0; a < team; ++a) refill(a, starts[a]);
    return;
  }
  // The 2024 rules: numTasksReveal x teamSize tasks revealed and not finished, held ones included.
  for (int a = 0; a < team; ++a) schedule(a, starts[a], false);
}

Vertex TaskBoard::goal(int a) const {
  if (in_hand_[a].empty()) return kNoVertex;
  return task(in_hand_[a].front())[errand_[a]];
}

bool TaskBoard::arrive(int a, Vertex cell, DistTable& distances, int64_t& tasks_finished) {
  at_[a] = cell;
  if (in_hand_[a].empty() || goal(a) != cell) return false;
  if (++errand_[a] == static_cast<int>(task(in_hand_[a].front()).size())) {
    ++tasks_finished;
    if (log_ != nullptr) log_->events[a].push_back({in_hand_[a].front(), time_, true});
    errand_[a] = 0;
    in_hand_[a].pop_front();
    if (scheduler_ == TaskScheduler::kWholeTask || scheduler_ == TaskScheduler::kWholeTaskReassign) {
      pool_.push_back(next_task_++);  // one finished, one revealed
      schedule(a, cell, scheduler_ == TaskScheduler::kWholeTaskReassign);
    } else {
      refill(a, cell, &distances);
    }
  }
  return true;
}

void TaskBoard::refill(int a, Vertex here, DistTable* distances) {
  if (scheduler_ == TaskScheduler::kRoundRobin) {
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

void TaskBoard::schedule(int a, Vertex here, bool may_take) {
  search_from(here);
  int64_t best_cost = std::numeric_limits<int64_t>::max();
  size_t best_free = pool_.size();
  int best_holder = -1;
  for (size_t k = 0; k < pool_.size(); ++k) {
    const int way = distances_from_[task(pool_[k]).front()];
    const int64_t cost = static_cast<int64_t>(way) + length_of(pool_[k]);
    if (cost < best_cost) best_cost = cost, best_free = k;
  }
  if (may_take) {
    for (int b = 0; b < static_cast<int>(in_hand_.size()); ++b) {
      if (b == a || in_hand_[b].empty() || errand_[b] != 0) continue;
      const int64_t held = in_hand_[b].front();
      const int way = distances_from_[task(held).front()];
      // What the holder has left to go, assuming it has come a step nearer every step since.
      const int holder_left = std::max(0, way_when_taken_[b] - (time_ - taken_at_[b]));
      if (way >= holder_left) continue;
      const int64_t cost = static_cast<int64_t>(way) + length_of(held);
      if (cost < best_cost) best_cost = cost, best_holder = b;
    }
  }
  if (best_holder >= 0) {
    const int64_t task_taken = in_hand_[best_holder].front();
    in_hand_[best_holder].pop_front();
    pool_.push_back(task_taken);
    ++reassignments_;
    best_free = pool_.size() - 1;
    best_cost = static_cast<int64_t>(distances_from_[task(task_taken).front()]) + length_of(task_taken);
  }
  if (best_free == pool_.size()) return;  // nothing to take
  const int64_t chosen = pool_[best_free];
  pool_[best_free] = pool_.back();
  pool_.pop_back();
  taken_at_[a] = time_;
  way_when_taken_[a] = distances_from_[task(chosen).front()];
  hand_out(a, chosen);
  // The holder it was taken from takes another, from the pool only (no chain of takings).
  if (best_holder >= 0) {
    schedule(best_holder, at_[best_holder], false);
  }
}

void TaskBoard::search_from(Vertex from) {
  const Graph& graph = *problem_.graph;
  distances_from_.assign(graph.vertex_count(), kUnreachable);
  frontier_.clear();
  distances_from_[from] = 0;
  frontier_.push_back(from);
  for (size_t head = 0; head < frontier_.size(); ++head) {
    const Vertex v = frontier_[head];
    for (Vertex next : graph.neighbours(v)) {
      if (distances_from_[next] != kUnreachable) continue;
      distances_from_[next] = distances_from_[v] + 1;
      frontier_.push_back(next);
    }
  }
}

int TaskBoard::length_of(int64_t k) {
  int& length = length_[k % problem_.tasks.size()];
  if (length >= 0) return length;
  // A search from each errand to the next, stopped once it is reached.
  const Graph& graph = *problem_.graph;
  const std::vector<Vertex>& errands = task(k);
  std::vector<int> seen(graph.vertex_count(), -1);
  length = 0;
  for (size_t e = 0; e + 1 < errands.size(); ++e) {
    std::fill(seen.begin(), seen.end(), -1);
    std::vector<Vertex> queue{errands[e]};
    seen[errands[e]] = 0;
    for (size_t head = 0; head < queue.size() && seen[errands[e + 1]] < 0; ++head) {
      for (Vertex next : graph.neighbours(queue[head])) {
        if (seen[next] >= 0) continue;
        seen[next] = seen[queue[head]] + 1;
        queue.push_back(next);
      }
    }
    length += seen[errands[e + 1]];
  }
  return length;
}

void TaskBoard::hand_out(int a, int64_t task) {
  in_hand_[a].push_back(task);
  if (log_ == nullptr) return;
  log_->events[a].push_back({task, time_, false});
  log_->tasks_revealed = std::max(log_->tasks_revealed, task + 1);
}

}  // namespace planner_core
