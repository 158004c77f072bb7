#include "planner_core/task_board.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace planner_core {

TaskBoard::TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log)
    : TaskBoard(problem, starts, log, scheduler_for(problem.assignment)) {}

TaskBoard::TaskBoard(const LorrProblem& problem, const Config& starts, LifelongLog* log, TaskScheduler scheduler,
                     const Headings& start_headings)
    : problem_(problem),
      log_(log),
      scheduler_(scheduler),
      in_hand_(starts.size()),
      errand_(starts.size(), 0),
      taken_at_(starts.size(), 0),
      way_when_taken_(starts.size(), 0),
      at_(starts),
      heading_of_(start_headings),
      length_(problem.tasks.size(), {-1, -1, -1, -1}) {
  if (!heading_of_.empty() && heading_of_.size() != starts.size()) {
    throw std::invalid_argument("TaskBoard: one start heading per agent");
  }
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

bool TaskBoard::arrive(int a, Vertex cell, int heading, DistTable& distances, int64_t& tasks_finished) {
  at_[a] = cell;
  if (counts_turns()) heading_of_[a] = heading;
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
  search_from(here, counts_turns() ? heading_of_[a] : 0);
  int64_t best_cost = std::numeric_limits<int64_t>::max();
  size_t best_free = pool_.size();
  int best_holder = -1;
  for (size_t k = 0; k < pool_.size(); ++k) {
    const int64_t cost = cost_of(pool_[k]);
    if (cost < best_cost) best_cost = cost, best_free = k;
  }
  if (may_take) {
    for (int b = 0; b < static_cast<int>(in_hand_.size()); ++b) {
      if (b == a || in_hand_[b].empty() || errand_[b] != 0) continue;
      const int64_t held = in_hand_[b].front();
      // What the holder has left to go, assuming it has come a step nearer every step since.
      const int holder_left = std::max(0, way_when_taken_[b] - (time_ - taken_at_[b]));
      if (way_to(held) >= holder_left) continue;
      const int64_t cost = cost_of(held);
      if (cost < best_cost) best_cost = cost, best_holder = b;
    }
  }
  if (best_holder >= 0) {
    const int64_t task_taken = in_hand_[best_holder].front();
    in_hand_[best_holder].pop_front();
    pool_.push_back(task_taken);
    ++reassignments_;
    best_free = pool_.size() - 1;
  }
  if (best_free == pool_.size()) return;  // nothing to take
  const int64_t chosen = pool_[best_free];
  pool_[best_free] = pool_.back();
  pool_.pop_back();
  taken_at_[a] = time_;
  way_when_taken_[a] = way_to(chosen);
  hand_out(a, chosen);
  // The holder it was taken from takes another, from the pool only (no chain of takings).
  if (best_holder >= 0) {
    schedule(best_holder, at_[best_holder], false);
  }
}

namespace {

int plus(int64_t a, int64_t b) { return static_cast<int>(std::min<int64_t>(kUnreachable, a + b)); }

// The rotation model's states (cell x 4 + heading) one action from `state`: the two quarter
// turns and, unless a wall is ahead, the step forward.
template <typename Reach>
void each_action(const Graph& graph, int state, Reach&& reach) {
  const Vertex v = state / kHeadings;
  const int h = state % kHeadings;
  reach(v * kHeadings + turned_clockwise(h));
  reach(v * kHeadings + turned_counter_clockwise(h));
  if (const Vertex forward = ahead(graph, v, h); forward != kNoVertex) reach(forward * kHeadings + h);
}

}  // namespace

void TaskBoard::search_from(Vertex from, int heading) {
  const Graph& graph = *problem_.graph;
  const int per_cell = counts_turns() ? kHeadings : 1;
  steps_from_.assign(graph.vertex_count() * per_cell, kUnreachable);
  frontier_.clear();
  const int source = counts_turns() ? from * kHeadings + heading : from;
  steps_from_[source] = 0;
  frontier_.push_back(source);
  auto reach = [&](int state, int steps) {
    if (steps_from_[state] != kUnreachable) return;
    steps_from_[state] = steps;
    frontier_.push_back(state);
  };
  for (size_t head = 0; head < frontier_.size(); ++head) {
    const int state = frontier_[head];
    const int steps = steps_from_[state] + 1;
    if (!counts_turns()) {
      for (Vertex next : graph.neighbours(state)) reach(next, steps);
      continue;
    }
    each_action(graph, state, [&](int next) { reach(next, steps); });
  }
}

int TaskBoard::way_to(int64_t k) const {
  const Vertex first = task(k).front();
  if (!counts_turns()) return steps_from_[first];
  int way = kUnreachable;
  for (int h = 0; h < kHeadings; ++h) way = std::min(way, steps_from_[first * kHeadings + h]);
  return way;
}

int64_t TaskBoard::cost_of(int64_t k) {
  const Vertex first = task(k).front();
  const std::array<int, kHeadings>& length = length_of(k);
  if (!counts_turns()) return plus(steps_from_[first], length[0]);
  int64_t cost = kUnreachable;
  for (int h = 0; h < kHeadings; ++h) cost = std::min<int64_t>(cost, plus(steps_from_[first * kHeadings + h], length[h]));
  return cost;
}

const std::array<int, kHeadings>& TaskBoard::length_of(int64_t k) {
  std::array<int, kHeadings>& length = length_[k % problem_.tasks.size()];
  if (length[0] >= 0) return length;
  const Graph& graph = *problem_.graph;
  const std::vector<Vertex>& errands = task(k);
  if (!counts_turns()) {
    // A search from each errand to the next, stopped once it is reached.
    std::vector<int> seen(graph.vertex_count(), -1);
    int total = 0;
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
      total = plus(total, seen[errands[e + 1]] < 0 ? kUnreachable : seen[errands[e + 1]]);
    }
    length.fill(total);
    return length;
  }
  // Per heading at the first errand, the fewest steps on through the others: the legs' step
  // counts (from each heading to each heading) chained, min-plus.
  std::array<std::array<int, kHeadings>, kHeadings> through{};
  for (int h = 0; h < kHeadings; ++h) {
    for (int g = 0; g < kHeadings; ++g) through[h][g] = h == g ? 0 : kUnreachable;
  }
  for (size_t e = 0; e + 1 < errands.size(); ++e) {
    const auto step = leg(errands[e], errands[e + 1]);
    std::array<std::array<int, kHeadings>, kHeadings> chained{};
    for (int h = 0; h < kHeadings; ++h) {
      for (int g = 0; g < kHeadings; ++g) {
        chained[h][g] = kUnreachable;
        for (int m = 0; m < kHeadings; ++m) chained[h][g] = std::min(chained[h][g], plus(through[h][m], step[m][g]));
      }
    }
    through = chained;
  }
  for (int h = 0; h < kHeadings; ++h) length[h] = *std::min_element(through[h].begin(), through[h].end());
  return length;
}

std::array<std::array<int, kHeadings>, kHeadings> TaskBoard::leg(Vertex from, Vertex to) {
  const Graph& graph = *problem_.graph;
  std::array<std::array<int, kHeadings>, kHeadings> steps{};
  std::vector<int> seen(graph.vertex_count() * kHeadings, -1);
  std::vector<int> queue;
  for (int h = 0; h < kHeadings; ++h) {
    std::fill(seen.begin(), seen.end(), -1);
    queue.assign(1, from * kHeadings + h);
    seen[queue[0]] = 0;
    int found = 0;
    auto reach = [&](int state, int count) {
      if (seen[state] >= 0) return;
      seen[state] = count;
      queue.push_back(state);
      if (state / kHeadings == to) ++found;
    };
    if (from == to) found = 1;
    for (size_t head = 0; head < queue.size() && found < kHeadings; ++head) {
      const int state = queue[head];
      each_action(graph, state, [&](int next) { reach(next, seen[state] + 1); });
    }
    for (int g = 0; g < kHeadings; ++g) steps[h][g] = seen[to * kHeadings + g] < 0 ? kUnreachable : seen[to * kHeadings + g];
  }
  return steps;
}

void TaskBoard::hand_out(int a, int64_t task) {
  in_hand_[a].push_back(task);
  if (log_ == nullptr) return;
  log_->events[a].push_back({task, time_, false});
  log_->tasks_revealed = std::max(log_->tasks_revealed, task + 1);
}

}  // namespace planner_core
