// Single-agent task ordering: the cheapest order to visit an agent's task cells between its
// start and its goal (cost = sum of shortest-path distances), exact by Held-Karp dynamic
// programming up to a task-count cut-off, greedy insertion + 2-opt + Or-opt beyond it.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "planner_core/dist_table.hpp"
#include "planner_core/guided_distances.hpp"
#include "planner_core/instance.hpp"

namespace planner_core {

struct TaskOrderConfig {
  int exact_task_limit = 14;  // Held-Karp up to this many tasks per agent (measured: see docs/results/HISTORY.md)
};

// Distances among the points of one agent's tour: 0 = start, 1..m = its tasks, m+1 = goal.
class TourMatrix {
 public:
  TourMatrix(const Instance& instance, int agent, DistTable& dist);
  // The rotation model's costs, turns included (`turning` holds a table per cell and heading): from
  // the start facing its start heading; from a task or the goal facing whichever way is best, so
  // that the costs stay below those of any tour (and symmetric, as turning is).
  TourMatrix(const Instance& instance, int agent, GuidedDistances& turning);
  int task_count() const { return task_count_; }
  int task_id(int local) const { return task_ids_[local]; }  // local 0..m-1 -> instance task id
  // Distance between points; point 0 is the start, 1..m the tasks, m+1 the goal.
  int d(int from_point, int to_point) const { return d_[from_point * (task_count_ + 2) + to_point]; }
  int goal_point() const { return task_count_ + 1; }
  static int point_of_task(int local) { return local + 1; }
  int path_cost(int from_point, const std::vector<int>& locals) const;  // from_point -> locals -> goal

 private:
  // distance(from, to, from_is_the_start)
  using Distance = std::function<int(Vertex, Vertex, bool)>;
  TourMatrix(const Instance& instance, int agent, const Distance& distance);

  int task_count_;
  std::vector<int> task_ids_;
  std::vector<int> d_;
};

// Best completion of a partial order: from `from_point`, visit every task of `remaining`
// (local ids) then the goal, where the first task visited is not in `banned_first`.
struct Completion {
  std::vector<int> locals;
  int cost = 0;  // from `from_point` to the goal
};

class OrderSolver {
 public:
  OrderSolver(const TourMatrix& matrix, const TaskOrderConfig& config);
  bool exact() const { return !backward_.empty() || matrix_.task_count() == 0; }
  std::optional<Completion> complete(int from_point, const std::vector<int>& remaining,
                                     const std::vector<int>& banned_first) const;
  // Lower bound on the cost of any full order: exact when exact(), else an MST bound.
  int lower_bound() const;

 private:
  std::optional<Completion> complete_exact(int from_point, uint32_t remaining, uint32_t banned) const;
  std::optional<Completion> complete_heuristic(int from_point, const std::vector<int>& remaining,
                                               const std::vector<int>& banned_first) const;
  int cost_of(int from_point, uint32_t mask, int first) const;  // d(from,first) + backward[mask][first]

  const TourMatrix& matrix_;
  // backward_[mask * m + i]: cheapest path from task i through all tasks of mask (i in mask) to the goal.
  std::vector<int> backward_;
};

// Sum over agents of the shortest single-agent tour start -> its tasks -> goal, ignoring other
// agents: exact within config.exact_task_limit tasks, an MST bound beyond. No plan has a lower flowtime.
int64_t tour_lower_bound(const Instance& instance, DistTable& dist, const TaskOrderConfig& config);
// The same in the rotation model: each tour's turns count as well.
int64_t tour_lower_bound(const Instance& instance, GuidedDistances& turning, const TaskOrderConfig& config);

// Improves `locals` (a path from_point -> locals -> goal) in place with 2-opt and Or-opt moves;
// the first `fixed_prefix` entries stay where they are.
void improve_path(const TourMatrix& matrix, int from_point, std::vector<int>& locals, int fixed_prefix);

}  // namespace planner_core
