#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "planner_core/kbest_orders.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

// A random connected-enough 7x7 grid instance with one agent holding `task_count` tasks.
Instance random_single_agent(std::mt19937& rng, int task_count) {
  std::vector<std::string> rows(7, std::string(7, '.'));
  std::bernoulli_distribution wall(0.15);
  for (int y = 1; y < 6; y += 2) {
    for (int x = 1; x < 6; ++x) {
      if (wall(rng)) rows[y][x] = '@';  // walls only on odd rows keep the grid connected
    }
  }
  auto graph = testing::grid_from_rows(rows);
  std::vector<Vertex> cells(graph->vertex_count());
  for (Vertex v = 0; v < graph->vertex_count(); ++v) cells[v] = v;
  std::shuffle(cells.begin(), cells.end(), rng);
  Instance instance;
  instance.graph = graph;
  instance.starts = {cells[0]};
  instance.goals = {cells[1]};
  for (int t = 0; t < task_count; ++t) instance.tasks.push_back({cells[2 + t], {0}});
  instance.index_tasks();
  return instance;
}

std::vector<int> brute_force_costs(const TourMatrix& matrix) {
  std::vector<int> locals(matrix.task_count());
  for (int i = 0; i < matrix.task_count(); ++i) locals[i] = i;
  std::vector<int> costs;
  do {
    costs.push_back(matrix.path_cost(0, locals));
  } while (std::next_permutation(locals.begin(), locals.end()));
  std::sort(costs.begin(), costs.end());
  return costs;
}

TEST(KBestOrders, ExactMatchesBruteForceOnRandomCases) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 60; ++trial) {
    const int m = 1 + trial % 6;
    const Instance instance = random_single_agent(rng, m);
    DistTable dist(*instance.graph);
    const TourMatrix matrix(instance, 0, dist);
    const std::vector<int> expected = brute_force_costs(matrix);
    KBestOrders orders(instance, 0, dist, TaskOrderConfig{});
    ASSERT_TRUE(orders.exact());
    std::set<std::vector<int>> seen;
    for (int k = 0; k < static_cast<int>(expected.size()); ++k) {
      const TaskOrder* order = orders.get(k);
      ASSERT_NE(order, nullptr) << "trial " << trial << " k " << k;
      EXPECT_EQ(order->cost, expected[k]) << "trial " << trial << " k " << k;
      EXPECT_TRUE(seen.insert(order->task_ids).second) << "duplicate order at k " << k;
      std::vector<int> sorted = order->task_ids;
      std::sort(sorted.begin(), sorted.end());
      EXPECT_EQ(sorted, instance.tasks_of_agent[0]);
    }
    EXPECT_EQ(orders.get(static_cast<int>(expected.size())), nullptr);
    EXPECT_EQ(orders.lower_bound(), expected.front());
  }
}

TEST(KBestOrders, HeuristicEnumeratesEveryOrderOnceAndBoundHolds) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 30; ++trial) {
    const int m = 2 + trial % 5;
    const Instance instance = random_single_agent(rng, m);
    DistTable dist(*instance.graph);
    const TourMatrix matrix(instance, 0, dist);
    const std::vector<int> expected = brute_force_costs(matrix);
    KBestOrders orders(instance, 0, dist, TaskOrderConfig{0});
    ASSERT_FALSE(orders.exact());
    std::multiset<int> costs;
    std::set<std::vector<int>> seen;
    for (int k = 0; orders.get(k); ++k) {
      EXPECT_TRUE(seen.insert(orders.get(k)->task_ids).second);
      EXPECT_EQ(orders.get(k)->cost, matrix.path_cost(0, [&] {
        std::vector<int> locals;
        for (int id : orders.get(k)->task_ids) {
          locals.push_back(static_cast<int>(std::find(instance.tasks_of_agent[0].begin(),
                                                      instance.tasks_of_agent[0].end(), id) -
                                            instance.tasks_of_agent[0].begin()));
        }
        return locals;
      }()));
      costs.insert(orders.get(k)->cost);
    }
    EXPECT_EQ(costs, std::multiset<int>(expected.begin(), expected.end()));
    EXPECT_LE(orders.lower_bound(), expected.front());
    // Greedy insertion with 2-opt and Or-opt is optimal or close on such small cases.
    EXPECT_LE(orders.get(0)->cost, expected.front() * 5 / 4 + 2);
  }
}

TEST(KBestOrders, HeuristicOnManyTasksIsCloseToExact) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 10; ++trial) {
    const Instance instance = random_single_agent(rng, 11);
    DistTable dist(*instance.graph);
    KBestOrders exact(instance, 0, dist, TaskOrderConfig{14});
    KBestOrders heuristic(instance, 0, dist, TaskOrderConfig{0});
    EXPECT_GE(heuristic.get(0)->cost, exact.get(0)->cost);
    EXPECT_LE(heuristic.get(0)->cost, exact.get(0)->cost * 6 / 5 + 2);
  }
}

TEST(KBestOrders, AgentWithoutTasksHasOneOrder) {
  const Instance instance = testing::make_instance({"....."}, {{{0, 0}, {4, 0}}});
  DistTable dist(*instance.graph);
  KBestOrders orders(instance, 0, dist, TaskOrderConfig{});
  ASSERT_NE(orders.get(0), nullptr);
  EXPECT_EQ(orders.get(0)->cost, 4);
  EXPECT_TRUE(orders.get(0)->task_ids.empty());
  EXPECT_EQ(orders.get(1), nullptr);
}

}  // namespace
}  // namespace planner_core
