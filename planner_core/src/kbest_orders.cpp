#include "planner_core/kbest_orders.hpp"

#include <algorithm>

namespace planner_core {

KBestOrders::KBestOrders(const Instance& instance, int agent, DistTable& dist, const TaskOrderConfig& config)
    : matrix_(instance, agent, dist), solver_(matrix_, config) {
  push_best_of({}, {});
}

void KBestOrders::push_best_of(std::vector<int> prefix, std::vector<int> banned_next) {
  std::vector<bool> fixed(matrix_.task_count(), false);
  for (int local : prefix) fixed[local] = true;
  std::vector<int> remaining;
  for (int local = 0; local < matrix_.task_count(); ++local) {
    if (!fixed[local]) remaining.push_back(local);
  }
  const int from_point = prefix.empty() ? 0 : TourMatrix::point_of_task(prefix.back());
  const auto completion = solver_.complete(from_point, remaining, banned_next);
  if (!completion) return;
  Subspace subspace{std::move(prefix), std::move(banned_next), {}, 0};
  subspace.order = subspace.prefix;
  subspace.order.insert(subspace.order.end(), completion->locals.begin(), completion->locals.end());
  subspace.cost = matrix_.path_cost(0, subspace.order);
  open_.push(std::move(subspace));
}

const TaskOrder* KBestOrders::get(int k) {
  while (static_cast<int>(orders_.size()) <= k && !open_.empty()) {
    Subspace best = open_.top();
    open_.pop();
    TaskOrder order;
    order.cost = best.cost;
    for (int local : best.order) order.task_ids.push_back(matrix_.task_id(local));
    orders_.push_back(std::move(order));
    // Partition the rest of this subspace: for each free position p, keep best.order[0..p) and ban
    // best.order[p] there (adding to the bans the subspace already had at its first free position).
    const int m = static_cast<int>(best.order.size());
    for (int p = static_cast<int>(best.prefix.size()); p < m - 1; ++p) {
      std::vector<int> prefix(best.order.begin(), best.order.begin() + p);
      std::vector<int> banned = p == static_cast<int>(best.prefix.size()) ? best.banned_next : std::vector<int>{};
      banned.push_back(best.order[p]);
      push_best_of(std::move(prefix), std::move(banned));
    }
  }
  return k < static_cast<int>(orders_.size()) ? &orders_[k] : nullptr;
}

}  // namespace planner_core
