#include "planner_core/task_order.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace planner_core {

namespace {
constexpr int kInfinity = std::numeric_limits<int>::max() / 4;
constexpr int kHardExactLimit = 24;  // beyond this the Held-Karp table would not fit in memory
}  // namespace

TourMatrix::TourMatrix(const Instance& instance, int agent, const Distance& distance)
    : task_count_(static_cast<int>(instance.tasks_of_agent[agent].size())),
      task_ids_(instance.tasks_of_agent[agent]) {
  std::vector<Vertex> points;
  points.push_back(instance.starts[agent]);
  for (int t : task_ids_) points.push_back(instance.tasks[t].at);
  points.push_back(instance.goals[agent]);
  const int n = static_cast<int>(points.size());
  d_.resize(static_cast<size_t>(n) * n);
  for (int to = 1; to < n; ++to) {
    for (int from = 0; from < n; ++from) d_[from * n + to] = distance(points[from], points[to], from == 0);
  }
  // No tour returns to its start: the column is filled from the row (as distances are symmetric).
  for (int from = 0; from < n; ++from) d_[from * n] = d_[from];
}

// Every entry comes from a search from a task or the goal, which the path planners need anyway,
// and none from the start.
TourMatrix::TourMatrix(const Instance& instance, int agent, DistTable& dist)
    : TourMatrix(instance, agent, [&](Vertex from, Vertex to, bool) { return dist.get(to, from); }) {}

TourMatrix::TourMatrix(const Instance& instance, int agent, GuidedDistances& turning)
    : TourMatrix(instance, agent, [&](Vertex from, Vertex to, bool from_start) {
        if (from_start) return turning.get(to, from, instance.start_heading(agent));
        int best = GuidedDistances::kUnreachable;
        for (int h = 0; h < kHeadings; ++h) best = std::min(best, turning.get(to, from, h));
        return best;
      }) {}

int TourMatrix::path_cost(int from_point, const std::vector<int>& locals) const {
  int cost = 0;
  int at = from_point;
  for (int local : locals) {
    cost += d(at, point_of_task(local));
    at = point_of_task(local);
  }
  return cost + d(at, goal_point());
}

OrderSolver::OrderSolver(const TourMatrix& matrix, const TaskOrderConfig& config) : matrix_(matrix) {
  const int m = matrix.task_count();
  if (m == 0 || m > std::min(config.exact_task_limit, kHardExactLimit)) return;
  const uint32_t full = (1u << m) - 1;
  backward_.assign(static_cast<size_t>(full + 1) * m, kInfinity);
  const int goal = matrix.goal_point();
  for (uint32_t mask = 1; mask <= full; ++mask) {
    for (int i = 0; i < m; ++i) {
      if (!(mask >> i & 1)) continue;
      const uint32_t rest = mask ^ (1u << i);
      const int pi = TourMatrix::point_of_task(i);
      int best = kInfinity;
      if (rest == 0) {
        best = matrix.d(pi, goal);
      } else {
        const int* row = &backward_[static_cast<size_t>(rest) * m];
        for (int j = 0; j < m; ++j) {
          if (rest >> j & 1) best = std::min(best, matrix.d(pi, TourMatrix::point_of_task(j)) + row[j]);
        }
      }
      backward_[static_cast<size_t>(mask) * m + i] = best;
    }
  }
}

int OrderSolver::cost_of(int from_point, uint32_t mask, int first) const {
  const int m = matrix_.task_count();
  return matrix_.d(from_point, TourMatrix::point_of_task(first)) + backward_[static_cast<size_t>(mask) * m + first];
}

std::optional<Completion> OrderSolver::complete(int from_point, const std::vector<int>& remaining,
                                                const std::vector<int>& banned_first) const {
  if (remaining.empty()) return Completion{{}, matrix_.d(from_point, matrix_.goal_point())};
  if (!exact()) return complete_heuristic(from_point, remaining, banned_first);
  uint32_t mask = 0, banned = 0;
  for (int local : remaining) mask |= 1u << local;
  for (int local : banned_first) banned |= 1u << local;
  return complete_exact(from_point, mask, banned);
}

std::optional<Completion> OrderSolver::complete_exact(int from_point, uint32_t remaining, uint32_t banned) const {
  const int m = matrix_.task_count();
  int first = -1, best = kInfinity;
  for (int i = 0; i < m; ++i) {
    if ((remaining >> i & 1) && !(banned >> i & 1) && cost_of(from_point, remaining, i) < best) {
      best = cost_of(from_point, remaining, i);
      first = i;
    }
  }
  if (first < 0) return std::nullopt;
  Completion completion{{first}, best};
  uint32_t mask = remaining;
  int at = first;
  while ((mask &= ~(1u << at)) != 0) {
    int next = -1, next_cost = kInfinity;
    for (int j = 0; j < m; ++j) {
      if ((mask >> j & 1) && cost_of(TourMatrix::point_of_task(at), mask, j) < next_cost) {
        next_cost = cost_of(TourMatrix::point_of_task(at), mask, j);
        next = j;
      }
    }
    completion.locals.push_back(next);
    at = next;
  }
  return completion;
}

std::optional<Completion> OrderSolver::complete_heuristic(int from_point, const std::vector<int>& remaining,
                                                          const std::vector<int>& banned_first) const {
  const auto is_banned = [&](int local) {
    return std::find(banned_first.begin(), banned_first.end(), local) != banned_first.end();
  };
  if (std::all_of(remaining.begin(), remaining.end(), is_banned)) return std::nullopt;

  // Cheapest insertion into the path from_point -> goal.
  std::vector<int> path;
  std::vector<int> pending = remaining;
  const auto point_at = [&](int position) {  // position 0 = from_point, path.size()+1 = goal
    if (position == 0) return from_point;
    if (position == static_cast<int>(path.size()) + 1) return matrix_.goal_point();
    return TourMatrix::point_of_task(path[position - 1]);
  };
  while (!pending.empty()) {
    int best_task = 0, best_position = 0, best_added = kInfinity;
    for (int k = 0; k < static_cast<int>(pending.size()); ++k) {
      const int p = TourMatrix::point_of_task(pending[k]);
      for (int pos = 0; pos <= static_cast<int>(path.size()); ++pos) {
        const int a = point_at(pos), b = point_at(pos + 1);
        const int added = matrix_.d(a, p) + matrix_.d(p, b) - matrix_.d(a, b);
        if (added < best_added) {
          best_added = added;
          best_task = k;
          best_position = pos;
        }
      }
    }
    path.insert(path.begin() + best_position, pending[best_task]);
    pending.erase(pending.begin() + best_task);
  }
  improve_path(matrix_, from_point, path, 0);

  if (is_banned(path.front())) {
    // Move the cheapest allowed task to the front, then improve the rest around it.
    std::vector<int> best_path;
    int best_cost = kInfinity;
    for (size_t k = 1; k < path.size(); ++k) {
      if (is_banned(path[k])) continue;
      std::vector<int> candidate = path;
      std::rotate(candidate.begin(), candidate.begin() + k, candidate.begin() + k + 1);
      const int cost = matrix_.path_cost(from_point, candidate);
      if (cost < best_cost) {
        best_cost = cost;
        best_path = std::move(candidate);
      }
    }
    path = std::move(best_path);
    improve_path(matrix_, from_point, path, 1);
  }
  return Completion{path, matrix_.path_cost(from_point, path)};
}

int OrderSolver::lower_bound() const {
  const int m = matrix_.task_count();
  if (m == 0) return matrix_.d(0, matrix_.goal_point());
  if (exact()) {
    int best = kInfinity;
    for (int i = 0; i < m; ++i) best = std::min(best, cost_of(0, (1u << m) - 1, i));
    return best;
  }
  // A minimum spanning tree over all points costs no more than any path through them.
  const int n = m + 2;
  std::vector<int> key(n, kInfinity);
  std::vector<bool> in_tree(n, false);
  key[0] = 0;
  int tree = 0;
  for (int round = 0; round < n; ++round) {
    int u = -1;
    for (int v = 0; v < n; ++v) {
      if (!in_tree[v] && (u < 0 || key[v] < key[u])) u = v;
    }
    in_tree[u] = true;
    tree += key[u];
    for (int v = 0; v < n; ++v) {
      if (!in_tree[v]) key[v] = std::min(key[v], matrix_.d(u, v));
    }
  }
  int through_one = 0;
  for (int i = 0; i < m; ++i) {
    const int p = TourMatrix::point_of_task(i);
    through_one = std::max(through_one, matrix_.d(0, p) + matrix_.d(p, matrix_.goal_point()));
  }
  return std::max(tree, through_one);
}

int64_t tour_lower_bound(const Instance& instance, DistTable& dist, const TaskOrderConfig& config) {
  int64_t bound = 0;
  for (int a = 0; a < instance.agent_count(); ++a) {
    const TourMatrix matrix(instance, a, dist);
    bound += OrderSolver(matrix, config).lower_bound();
  }
  return bound;
}

int64_t tour_lower_bound(const Instance& instance, GuidedDistances& turning, const TaskOrderConfig& config) {
  int64_t bound = 0;
  for (int a = 0; a < instance.agent_count(); ++a) {
    const TourMatrix matrix(instance, a, turning);
    bound += OrderSolver(matrix, config).lower_bound();
  }
  return bound;
}

void improve_path(const TourMatrix& matrix, int from_point, std::vector<int>& locals, int fixed_prefix) {
  // points[0] = from_point, points[1..r] = tasks, points[r+1] = goal.
  std::vector<int> points;
  points.push_back(from_point);
  for (int local : locals) points.push_back(TourMatrix::point_of_task(local));
  points.push_back(matrix.goal_point());
  const int r = static_cast<int>(locals.size());
  const int first_movable = fixed_prefix + 1;
  const auto d = [&](int a, int b) { return matrix.d(points[a], points[b]); };

  for (bool improved = true; improved;) {
    improved = false;
    // 2-opt: reverse points[i..j].
    for (int i = first_movable; i <= r; ++i) {
      for (int j = i + 1; j <= r; ++j) {
        const int delta = d(i - 1, j) + d(i, j + 1) - d(i - 1, i) - d(j, j + 1);
        if (delta < 0) {
          std::reverse(points.begin() + i, points.begin() + j + 1);
          improved = true;
        }
      }
    }
    // Or-opt: move a segment of 1..3 tasks elsewhere, possibly reversed.
    for (int length = 1; length <= 3; ++length) {
      for (int i = first_movable; i + length - 1 <= r; ++i) {
        const int last = i + length - 1;
        const int removed = d(i - 1, i) + d(last, last + 1) - d(i - 1, last + 1);
        int best_gain = 0, best_k = -1;
        bool best_reversed = false;
        for (int k = fixed_prefix; k <= r; ++k) {
          if (k >= i - 1 && k <= last) continue;
          const int straight = d(k, i) + d(last, k + 1) - d(k, k + 1);
          const int reversed = d(k, last) + d(i, k + 1) - d(k, k + 1);
          if (removed - straight > best_gain) best_gain = removed - straight, best_k = k, best_reversed = false;
          if (removed - reversed > best_gain) best_gain = removed - reversed, best_k = k, best_reversed = true;
        }
        if (best_k < 0) continue;
        std::vector<int> segment(points.begin() + i, points.begin() + last + 1);
        if (best_reversed) std::reverse(segment.begin(), segment.end());
        points.erase(points.begin() + i, points.begin() + last + 1);
        const int insert_at = best_k < i ? best_k + 1 : best_k + 1 - length;
        points.insert(points.begin() + insert_at, segment.begin(), segment.end());
        improved = true;
      }
    }
  }
  for (int k = 0; k < r; ++k) locals[k] = points[k + 1] - 1;
}

}  // namespace planner_core
