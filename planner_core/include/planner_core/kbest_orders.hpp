// KBestOrders: one agent's task orders, best first, without duplicates, generated lazily by
// Lawler's partitioning (E. L. Lawler, "A procedure for computing the K best solutions to
// discrete optimization problems", Management Science 1972): each popped order splits the rest
// of the search space by fixing a prefix and banning the next task at the first free position.
#pragma once

#include <memory>
#include <queue>
#include <vector>

#include "planner_core/task_order.hpp"

namespace planner_core {

struct TaskOrder {
  std::vector<int> task_ids;  // instance task ids in visiting order
  int cost = 0;               // start -> tasks -> goal, sum of shortest-path distances
};

class KBestOrders {
 public:
  KBestOrders(const Instance& instance, int agent, DistTable& dist, const TaskOrderConfig& config);
  KBestOrders(const KBestOrders&) = delete;  // solver_ refers to matrix_
  KBestOrders& operator=(const KBestOrders&) = delete;

  // The k-th best order (k = 0 is the best), or nullptr when the agent has fewer than k+1 orders.
  // Costs are non-decreasing in k when the agent's task count is within the exact limit; beyond it
  // the sub-problems are solved heuristically and the sequence follows their estimated costs.
  const TaskOrder* get(int k);
  int lower_bound() const { return solver_.lower_bound(); }
  bool exact() const { return solver_.exact(); }

 private:
  struct Subspace {
    std::vector<int> prefix;        // fixed first tasks (local ids)
    std::vector<int> banned_next;   // tasks not allowed right after the prefix
    std::vector<int> order;         // best full order in this subspace (local ids)
    int cost = 0;
  };
  struct CostGreater {
    bool operator()(const Subspace& a, const Subspace& b) const { return a.cost > b.cost; }
  };
  void push_best_of(std::vector<int> prefix, std::vector<int> banned_next);

  TourMatrix matrix_;
  OrderSolver solver_;
  std::priority_queue<Subspace, std::vector<Subspace>, CostGreater> open_;
  std::vector<TaskOrder> orders_;
};

}  // namespace planner_core
